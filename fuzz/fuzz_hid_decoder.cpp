// libFuzzer target: the viewer's gamepad HID decoders (demos/viewer/gamepad_decode.cpp and
// gamepad_hid_descriptor.cpp), which read bytes straight from hidraw — a pad, or anything
// claiming to be one, controls them.
//
// Input layout:
//   byte 0          the pad kind, modulo 5 (DualShock 4, DualSense, Switch Pro, Xbox
//                   Wireless, generic HID gamepad)
//   known kinds     the rest is one input report (report ID first)
//   generic         bytes 1..2 the descriptor's length n (little endian, cut to what is
//                   left), then n bytes of report descriptor, then the input report
//
// Beyond "no crash, no read past the span" (ASan), the decoders promise bounded results
// (gamepad.h): sticks in [−1, 1], triggers in [0, 1], the hat in −1..7, only the 14 named
// buttons, and at most 256 descriptor fields of 1..32 bits. A result outside those traps,
// so libFuzzer keeps it as a crash. The shaped stick must stay inside the unit disc.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include "gamepad.h"

namespace {

using namespace rg::viewer::pad;

void require(bool ok) {
    if (!ok) __builtin_trap();
}

void checkState(const PadState& s) {
    for (float v : {s.lx, s.ly, s.rx, s.ry}) require(std::isfinite(v) && v >= -1.0f && v <= 1.0f);
    for (float v : {s.l2, s.r2}) require(std::isfinite(v) && v >= 0.0f && v <= 1.0f);
    require(s.hat >= -1 && s.hat <= 7);
    require((s.buttons & ~((Misc << 1) - 1)) == 0);
    for (int stick = 0; stick < 2; ++stick) {
        float x = stick ? s.rx : s.lx, y = stick ? s.ry : s.ly;
        shapeStick(x, y, StickShape{});
        require(std::isfinite(x) && std::isfinite(y) && x * x + y * y <= 1.0f + 1e-5f);
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    const PadKind kinds[] = {PadKind::DualShock4, PadKind::DualSense, PadKind::SwitchPro,
                             PadKind::XboxWireless, PadKind::Generic};
    const PadKind kind = kinds[data[0] % 5];
    std::span<const uint8_t> rest(data + 1, size - 1);
    HidDescriptor descriptor;
    if (kind == PadKind::Generic) {
        if (rest.size() < 2) return 0;
        const size_t n = std::min<size_t>(size_t(rest[0]) | size_t(rest[1]) << 8, rest.size() - 2);
        descriptor = parseHidDescriptor(rest.subspan(2, n));
        require(descriptor.fields.size() <= 256);
        for (const HidField& f : descriptor.fields) require(f.bitSize >= 1 && f.bitSize <= 32);
        rest = rest.subspan(2 + n);
    }
    if (auto s = decodeReport(kind, descriptor, rest)) checkState(*s);
    return 0;
}
