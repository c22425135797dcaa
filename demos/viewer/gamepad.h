// Gamepads through hidapi, decoded from their HID input reports with no SDL in between.
//
//   hidraw ─▶ hid_read() bytes ─▶ decode<Pad>() ─▶ PadState ─▶ shapeStick() ─▶ viewer actions
//
// Known pads are decoded from their documented report layouts; any other HID gamepad
// through its report descriptor (Generic Desktop X/Y/Z/Rx/Ry/Rz/hat switch and Button
// usages). Decoders take whole input reports including the report ID byte and return
// nullopt for reports they do not know or that are too short; they never read past the
// span. Layouts per pad are drawn in gamepad_decode.cpp and docs/viewer.md.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace rg::viewer::pad {

// Positional names (the Xbox layout's A is South, Nintendo's B is South).
enum Button : uint32_t {
    South = 1u << 0, East = 1u << 1, West = 1u << 2, North = 1u << 3,
    L1 = 1u << 4, R1 = 1u << 5, L2 = 1u << 6, R2 = 1u << 7,
    Select = 1u << 8, Start = 1u << 9, LStick = 1u << 10, RStick = 1u << 11,
    Home = 1u << 12, Misc = 1u << 13,   // touchpad click, capture, share, mute
};

struct PadState {
    // Sticks in [−1, 1], x right, y up (pushed away from the player is +1).
    float lx = 0, ly = 0, rx = 0, ry = 0;
    float l2 = 0, r2 = 0;    // analog triggers in [0, 1] (0 where the pad has none)
    uint32_t buttons = 0;
    int hat = -1;            // −1 centred, 0 up, 1 up-right, … 7 up-left (clockwise)
    friend bool operator==(const PadState&, const PadState&) = default;
};

enum class PadKind { DualShock4, DualSense, SwitchPro, XboxWireless, Generic };
const char* padKindName(PadKind kind);
// The known pads by USB vendor/product id; nullopt for everything else.
std::optional<PadKind> knownPad(uint16_t vendor, uint16_t product);

// ---- known layouts ----------------------------------------------------------------------
std::optional<PadState> decodeDualShock4(std::span<const uint8_t> report);  // USB 0x01, BT 0x11
std::optional<PadState> decodeDualSense(std::span<const uint8_t> report);   // USB 0x01, BT 0x31, BT simple 0x01
std::optional<PadState> decodeSwitchPro(std::span<const uint8_t> report);   // 0x30/0x21 full, 0x3F simple
std::optional<PadState> decodeXboxWireless(std::span<const uint8_t> report);  // BT 0x01

// ---- any HID gamepad: the report descriptor -----------------------------------------------
struct HidField {
    uint8_t reportId = 0;
    uint32_t bitOffset = 0;   // from the first data byte (after the report ID, if any)
    uint32_t bitSize = 0;
    uint16_t usagePage = 0, usage = 0;
    int32_t logicalMin = 0, logicalMax = 0;
};

struct HidDescriptor {
    std::vector<HidField> fields;  // inputs the decoder uses: axes, hat, buttons
    bool usesReportIds = false;
    bool isGamepad = false;        // an application collection Generic Desktop Joystick/Gamepad
};
// Parses short items (Main, Global incl. Push/Pop, Local incl. usage ranges). Malformed
// or truncated descriptors yield what was parsed before the fault; never throws.
HidDescriptor parseHidDescriptor(std::span<const uint8_t> descriptor);
// Left stick X/Y, right stick Rx/Ry (else Z/Rz), hat switch, buttons 1..14 in order
// South East West North L1 R1 L2 R2 Select Start LStick RStick Home Misc.
std::optional<PadState> decodeGeneric(const HidDescriptor& descriptor, std::span<const uint8_t> report);

std::optional<PadState> decodeReport(PadKind kind, const HidDescriptor& descriptor,
                                     std::span<const uint8_t> report);

// ---- shaping --------------------------------------------------------------------------
// Radial dead zone, then rescaled to reach 1 at the rim, then |v|^exponent (response
// curve: fine control near the centre).
struct StickShape {
    float deadZone = 0.12f;
    float exponent = 2.0f;
};
void shapeStick(float& x, float& y, const StickShape& shape);

}  // namespace rg::viewer::pad
