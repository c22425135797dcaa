// Input-report layouts of the known pads. Offsets are bytes of the report as hid_read()
// returns it, byte 0 the report ID. Sources: the public descriptions of these reports
// (Linux hid-sony / hid-playstation / hid-nintendo, dekuNukem's Switch reverse-engineering
// notes, SDL's HIDAPI notes); the byte tables below are ours.
#include <algorithm>
#include <cmath>

#include "gamepad.h"

namespace rg::viewer::pad {

namespace {

// 8-bit stick, 0 = left/up, 255 = right/down, centre 128.
float axis8(uint8_t v) { return std::clamp((float(v) - 128.0f) / 127.0f, -1.0f, 1.0f); }
// 16-bit unsigned stick centred at 32768.
float axis16(uint16_t v) { return std::clamp((float(v) - 32768.0f) / 32767.0f, -1.0f, 1.0f); }
uint16_t le16(std::span<const uint8_t> r, size_t i) { return uint16_t(r[i] | (r[i + 1] << 8)); }
// Hat nibble 0..7 clockwise from up, anything else centred.
int hat8(uint8_t v) { return v < 8 ? int(v) : -1; }

// Sony's common block (DS4 and DualSense's simple report):
//   +0 LX  +1 LY  +2 RX  +3 RY  +4 hat(3:0) □(4) ×(5) ○(6) △(7)
//   +5 L1 R1 L2 R2 share/create options L3 R3 (bits 0..7)  +6 PS(0) touchpad(1)
PadState sonyBlock(std::span<const uint8_t> r, size_t at, size_t triggersAt) {
    PadState s;
    s.lx = axis8(r[at]);
    s.ly = -axis8(r[at + 1]);
    s.rx = axis8(r[at + 2]);
    s.ry = -axis8(r[at + 3]);
    const uint8_t b0 = r[at + 4], b1 = r[at + 5], b2 = r[at + 6];
    s.hat = hat8(b0 & 0x0f);
    if (b0 & 0x10) s.buttons |= West;    // square
    if (b0 & 0x20) s.buttons |= South;   // cross
    if (b0 & 0x40) s.buttons |= East;    // circle
    if (b0 & 0x80) s.buttons |= North;   // triangle
    const uint32_t shoulder[8] = {L1, R1, L2, R2, Select, Start, LStick, RStick};
    for (int i = 0; i < 8; ++i)
        if (b1 & (1 << i)) s.buttons |= shoulder[i];
    if (b2 & 0x01) s.buttons |= Home;
    if (b2 & 0x02) s.buttons |= Misc;
    s.l2 = float(r[triggersAt]) / 255.0f;
    s.r2 = float(r[triggersAt + 1]) / 255.0f;
    return s;
}

}  // namespace

const char* padKindName(PadKind k) {
    switch (k) {
        case PadKind::DualShock4: return "Sony DualShock 4";
        case PadKind::DualSense: return "Sony DualSense";
        case PadKind::SwitchPro: return "Nintendo Switch Pro Controller";
        case PadKind::XboxWireless: return "Xbox Wireless Controller";
        case PadKind::Generic: return "HID gamepad";
    }
    return "?";
}

std::optional<PadKind> knownPad(uint16_t vendor, uint16_t product) {
    if (vendor == 0x054c) {
        if (product == 0x05c4 || product == 0x09cc || product == 0x0ba0) return PadKind::DualShock4;
        if (product == 0x0ce6 || product == 0x0df2) return PadKind::DualSense;
    }
    if (vendor == 0x057e && product == 0x2009) return PadKind::SwitchPro;
    if (vendor == 0x045e)
        for (uint16_t p : {0x02e0, 0x02fd, 0x0b05, 0x0b13, 0x0b20, 0x0b22})
            if (product == p) return PadKind::XboxWireless;
    return std::nullopt;
}

// DualShock 4
//   USB 0x01 (64 bytes; also Bluetooth before the full mode, 10 bytes):
//     [1..4] sticks [5] hat+face [6] shoulders [7] PS, touchpad, counter [8] L2 [9] R2
//   Bluetooth 0x11 (78 bytes): two header bytes, then the same block from byte 3.
std::optional<PadState> decodeDualShock4(std::span<const uint8_t> r) {
    if (r.size() >= 10 && r[0] == 0x01) return sonyBlock(r, 1, 8);
    if (r.size() >= 12 && r[0] == 0x11) return sonyBlock(r, 3, 10);
    return std::nullopt;
}

// DualSense
//   USB 0x01 (64 bytes):  [1] LX [2] LY [3] RX [4] RY [5] L2 [6] R2 [7] sequence
//                         [8] hat+face [9] shoulders [10] PS(0) touchpad(1) mute(2)
//   Bluetooth 0x31 (78 bytes): one extra byte after the ID, then the USB layout from [2].
//   Bluetooth simple 0x01 (10 bytes, before the full mode): the DualShock 4 block.
std::optional<PadState> decodeDualSense(std::span<const uint8_t> r) {
    auto full = [&](size_t at) {
        PadState s;
        s.lx = axis8(r[at]);
        s.ly = -axis8(r[at + 1]);
        s.rx = axis8(r[at + 2]);
        s.ry = -axis8(r[at + 3]);
        s.l2 = float(r[at + 4]) / 255.0f;
        s.r2 = float(r[at + 5]) / 255.0f;
        // [at+7..at+9] are the DualShock 4's hat/face, shoulder and PS bytes: the block
        // read at at+3 takes its buttons from there (its sticks are discarded).
        PadState b = sonyBlock(r, at + 3, at + 4);
        s.buttons = b.buttons;
        s.hat = b.hat;
        if (r[at + 9] & 0x04) s.buttons |= Misc;     // mute
        return s;
    };
    if (r.size() >= 11 && r[0] == 0x01) return full(1);
    if (r.size() == 10 && r[0] == 0x01) return sonyBlock(r, 1, 8);
    if (r.size() >= 12 && r[0] == 0x31) return full(2);
    return std::nullopt;
}

// Switch Pro Controller
//   0x30 / 0x21 (full mode): [1] timer [2] battery/connection
//     [3] Y X B A SR SL R ZR (bits 0..7)  [4] − + RS LS Home Capture
//     [5] down up right left SR SL L ZL   [6..8] left stick, [9..11] right stick:
//     two 12-bit values per 3 bytes, x = b0 | (b1 & 0xf) << 8, y = b1 >> 4 | b2 << 4,
//     centre about 2048, up is larger.
//   0x3F (simple HID mode, Bluetooth default):
//     [1] B A Y X L R ZL ZR  [2] − + LS RS Home Capture  [3] hat (8 centred)
//     [4..11] LX LY RX RY, 16-bit little endian, centre 0x8000, down is larger.
std::optional<PadState> decodeSwitchPro(std::span<const uint8_t> r) {
    if (r.size() >= 12 && (r[0] == 0x30 || r[0] == 0x21)) {
        PadState s;
        auto stick = [&](size_t at, float& x, float& y) {
            int sx = r[at] | ((r[at + 1] & 0x0f) << 8);
            int sy = (r[at + 1] >> 4) | (r[at + 2] << 4);
            // ±1600 counts reach the rim on typical factory calibrations.
            x = std::clamp((float(sx) - 2048.0f) / 1600.0f, -1.0f, 1.0f);
            y = std::clamp((float(sy) - 2048.0f) / 1600.0f, -1.0f, 1.0f);
        };
        stick(6, s.lx, s.ly);
        stick(9, s.rx, s.ry);
        const uint8_t right = r[3], shared = r[4], left = r[5];
        if (right & 0x01) s.buttons |= West;    // Y
        if (right & 0x02) s.buttons |= North;   // X
        if (right & 0x04) s.buttons |= South;   // B
        if (right & 0x08) s.buttons |= East;    // A
        if (right & 0x40) s.buttons |= R1;
        if (right & 0x80) s.buttons |= R2, s.r2 = 1;
        if (shared & 0x01) s.buttons |= Select;
        if (shared & 0x02) s.buttons |= Start;
        if (shared & 0x04) s.buttons |= RStick;
        if (shared & 0x08) s.buttons |= LStick;
        if (shared & 0x10) s.buttons |= Home;
        if (shared & 0x20) s.buttons |= Misc;
        if (left & 0x40) s.buttons |= L1;
        if (left & 0x80) s.buttons |= L2, s.l2 = 1;
        const bool up = left & 0x02, down = left & 0x01, rt = left & 0x04, lf = left & 0x08;
        static const int hatOf[3][3] = {{7, 0, 1}, {6, -1, 2}, {5, 4, 3}};  // [dy+1][dx+1]
        int dx = (rt ? 1 : 0) - (lf ? 1 : 0), dy = (down ? 1 : 0) - (up ? 1 : 0);
        s.hat = hatOf[dy + 1][dx + 1];
        return s;
    }
    if (r.size() >= 12 && r[0] == 0x3f) {
        PadState s;
        const uint8_t b0 = r[1], b1 = r[2];
        const uint32_t first[8] = {South, East, West, North, L1, R1, L2, R2};
        for (int i = 0; i < 8; ++i)
            if (b0 & (1 << i)) s.buttons |= first[i];
        const uint32_t second[6] = {Select, Start, LStick, RStick, Home, Misc};
        for (int i = 0; i < 6; ++i)
            if (b1 & (1 << i)) s.buttons |= second[i];
        s.l2 = (b0 & 0x40) ? 1.0f : 0.0f;
        s.r2 = (b0 & 0x80) ? 1.0f : 0.0f;
        s.hat = hat8(r[3]);
        s.lx = axis16(le16(r, 4));
        s.ly = -axis16(le16(r, 6));
        s.rx = axis16(le16(r, 8));
        s.ry = -axis16(le16(r, 10));
        return s;
    }
    return std::nullopt;
}

// Xbox Wireless Controller over Bluetooth (firmware 5 and later), report 0x01:
//   [1..2] LX [3..4] LY [5..6] RX [7..8] RY   16-bit little endian, centre 0x8000, down larger
//   [9..10] LT [11..12] RT   10-bit little endian
//   [13] hat: 0 centred, 1 up, 2 up-right, … 8 up-left
//   [14] A B _ X Y _ LB RB (bits 0..7)  [15] _ _ View Menu Xbox LS RS _  [16] Share (bit 0)
std::optional<PadState> decodeXboxWireless(std::span<const uint8_t> r) {
    if (r.size() < 16 || r[0] != 0x01) return std::nullopt;
    PadState s;
    s.lx = axis16(le16(r, 1));
    s.ly = -axis16(le16(r, 3));
    s.rx = axis16(le16(r, 5));
    s.ry = -axis16(le16(r, 7));
    s.l2 = std::min(1.0f, float(le16(r, 9) & 0x3ff) / 1023.0f);
    s.r2 = std::min(1.0f, float(le16(r, 11) & 0x3ff) / 1023.0f);
    s.hat = (r[13] >= 1 && r[13] <= 8) ? int(r[13]) - 1 : -1;
    const uint8_t b0 = r[14], b1 = r[15];
    if (b0 & 0x01) s.buttons |= South;
    if (b0 & 0x02) s.buttons |= East;
    if (b0 & 0x08) s.buttons |= West;
    if (b0 & 0x10) s.buttons |= North;
    if (b0 & 0x40) s.buttons |= L1;
    if (b0 & 0x80) s.buttons |= R1;
    if (b1 & 0x04) s.buttons |= Select;
    if (b1 & 0x08) s.buttons |= Start;
    if (b1 & 0x10) s.buttons |= Home;
    if (b1 & 0x20) s.buttons |= LStick;
    if (b1 & 0x40) s.buttons |= RStick;
    if (r.size() > 16 && (r[16] & 0x01)) s.buttons |= Misc;
    if (s.l2 > 0.5f) s.buttons |= L2;
    if (s.r2 > 0.5f) s.buttons |= R2;
    return s;
}

std::optional<PadState> decodeReport(PadKind kind, const HidDescriptor& d, std::span<const uint8_t> r) {
    if (r.empty()) return std::nullopt;
    switch (kind) {
        case PadKind::DualShock4: return decodeDualShock4(r);
        case PadKind::DualSense: return decodeDualSense(r);
        case PadKind::SwitchPro: return decodeSwitchPro(r);
        case PadKind::XboxWireless: return decodeXboxWireless(r);
        case PadKind::Generic: return decodeGeneric(d, r);
    }
    return std::nullopt;
}

void shapeStick(float& x, float& y, const StickShape& shape) {
    float m = std::sqrt(x * x + y * y);
    if (!(m > shape.deadZone)) {  // also catches NaN
        x = y = 0;
        return;
    }
    float mc = std::min(m, 1.0f);
    float t = (mc - shape.deadZone) / (1.0f - shape.deadZone);
    float scaled = std::pow(t, shape.exponent);
    x = x / m * scaled;
    y = y / m * scaled;
}

}  // namespace rg::viewer::pad
