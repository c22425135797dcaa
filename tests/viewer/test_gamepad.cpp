// The gamepad decoders on hand-made report bytes, laid out from the public descriptions
// of each pad's input report (see demos/viewer/gamepad_decode.cpp), plus malformed,
// short and random reports that must decode to nothing or to something bounded.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "gamepad.h"

using namespace rg::viewer::pad;

namespace {

std::vector<uint8_t> bytes(size_t n, uint8_t fill = 0) { return std::vector<uint8_t>(n, fill); }

void expectBounded(const PadState& s) {
    for (float v : {s.lx, s.ly, s.rx, s.ry}) {
        EXPECT_TRUE(std::isfinite(v));
        EXPECT_GE(v, -1.0f);
        EXPECT_LE(v, 1.0f);
    }
    for (float v : {s.l2, s.r2}) {
        EXPECT_GE(v, 0.0f);
        EXPECT_LE(v, 1.0f);
    }
    EXPECT_GE(s.hat, -1);
    EXPECT_LE(s.hat, 7);
}

}  // namespace

// ---- DualShock 4 ----------------------------------------------------------------------------

TEST(GamepadDualShock4, UsbReport) {
    auto r = bytes(64);
    r[0] = 0x01;
    r[1] = 255, r[2] = 0, r[3] = 128, r[4] = 128;   // left stick right and up
    r[5] = 0x08 | 0x20;                              // hat centred, cross
    r[6] = 0x01 | 0x20;                              // L1, options
    r[7] = 0x01;                                     // PS
    r[8] = 255, r[9] = 0;                            // L2 full
    auto s = decodeDualShock4(r);
    ASSERT_TRUE(s);
    EXPECT_FLOAT_EQ(s->lx, 1.0f);
    EXPECT_FLOAT_EQ(s->ly, 1.0f);
    EXPECT_FLOAT_EQ(s->rx, 0.0f);
    EXPECT_EQ(s->hat, -1);
    EXPECT_EQ(s->buttons, uint32_t(South | L1 | Start | Home));
    EXPECT_FLOAT_EQ(s->l2, 1.0f);
    EXPECT_FLOAT_EQ(s->r2, 0.0f);
}

TEST(GamepadDualShock4, BluetoothReportIsShiftedByTwo) {
    auto r = bytes(78);
    r[0] = 0x11;
    r[3] = 0, r[4] = 128, r[5] = 128, r[6] = 255;   // left stick left, right stick down
    r[7] = 0x02 | 0x80;                              // hat right, triangle
    r[8] = 0x02;                                     // R1
    auto s = decodeDualShock4(r);
    ASSERT_TRUE(s);
    EXPECT_FLOAT_EQ(s->lx, -1.0f);   // 0 clamps to the rim
    EXPECT_FLOAT_EQ(s->ry, -1.0f);
    EXPECT_EQ(s->hat, 2);
    EXPECT_EQ(s->buttons, uint32_t(North | R1));
}

TEST(GamepadDualShock4, ShortAndUnknownReports) {
    EXPECT_FALSE(decodeDualShock4({}));
    auto r = bytes(9);
    r[0] = 0x01;
    EXPECT_FALSE(decodeDualShock4(r));      // one byte short of the triggers
    auto bt = bytes(11);
    bt[0] = 0x11;
    EXPECT_FALSE(decodeDualShock4(bt));
    auto other = bytes(64);
    other[0] = 0x05;                        // an output-report id echoed back
    EXPECT_FALSE(decodeDualShock4(other));
}

// ---- DualSense --------------------------------------------------------------------------------

TEST(GamepadDualSense, UsbReport) {
    auto r = bytes(64);
    r[0] = 0x01;
    r[1] = 128, r[2] = 128, r[3] = 255, r[4] = 0;    // right stick right and up
    r[5] = 0, r[6] = 255;                            // R2 full
    r[7] = 0x42;                                     // sequence, ignored
    r[8] = 0x06 | 0x10;                              // hat left, square
    r[9] = 0x02 | 0x10;                              // R1, create
    r[10] = 0x04;                                    // mute
    auto s = decodeDualSense(r);
    ASSERT_TRUE(s);
    EXPECT_FLOAT_EQ(s->rx, 1.0f);
    EXPECT_FLOAT_EQ(s->ry, 1.0f);
    EXPECT_FLOAT_EQ(s->r2, 1.0f);
    EXPECT_EQ(s->hat, 6);
    EXPECT_EQ(s->buttons, uint32_t(West | R1 | Select | Misc));
}

TEST(GamepadDualSense, BluetoothFullReport) {
    auto r = bytes(78);
    r[0] = 0x31;
    r[1] = 0x10;                                     // the extra Bluetooth byte
    r[2] = 0, r[3] = 128, r[4] = 128, r[5] = 128;    // left stick left
    r[9] = 0x08 | 0x40;                              // hat centred, circle
    r[10] = 0x40;                                    // L3
    auto s = decodeDualSense(r);
    ASSERT_TRUE(s);
    EXPECT_FLOAT_EQ(s->lx, -1.0f);
    EXPECT_EQ(s->hat, -1);
    EXPECT_EQ(s->buttons, uint32_t(East | LStick));
}

TEST(GamepadDualSense, BluetoothSimpleReport) {
    auto r = bytes(10);
    r[0] = 0x01;
    r[1] = 128, r[2] = 0, r[3] = 128, r[4] = 128;    // left stick up
    r[5] = 0x00 | 0x20;                              // hat up, cross
    auto s = decodeDualSense(r);
    ASSERT_TRUE(s);
    EXPECT_FLOAT_EQ(s->ly, 1.0f);
    EXPECT_EQ(s->hat, 0);
    EXPECT_EQ(s->buttons, uint32_t(South));
}

TEST(GamepadDualSense, ShortReports) {
    for (size_t n = 0; n < 10; ++n) {
        auto r = bytes(n, 0xff);
        if (n) r[0] = 0x01;
        EXPECT_FALSE(decodeDualSense(r)) << n;
    }
    auto bt = bytes(11);
    bt[0] = 0x31;
    EXPECT_FALSE(decodeDualSense(bt));
}

// ---- Switch Pro Controller ----------------------------------------------------------------------

namespace {
// Packs two 12-bit stick values the way the 0x30 report does.
void packStick(std::vector<uint8_t>& r, size_t at, int x, int y) {
    r[at] = uint8_t(x & 0xff);
    r[at + 1] = uint8_t(((x >> 8) & 0x0f) | ((y & 0x0f) << 4));
    r[at + 2] = uint8_t(y >> 4);
}
}  // namespace

TEST(GamepadSwitchPro, FullReport0x30) {
    auto r = bytes(64);
    r[0] = 0x30;
    r[3] = 0x08 | 0x40;          // A, R
    r[4] = 0x02 | 0x20;          // +, capture
    r[5] = 0x02 | 0x08 | 0x80;   // up, left, ZL
    packStick(r, 6, 2048 + 1600, 2048);      // left stick full right
    packStick(r, 9, 2048, 2048 - 1600);      // right stick full down
    auto s = decodeSwitchPro(r);
    ASSERT_TRUE(s);
    EXPECT_FLOAT_EQ(s->lx, 1.0f);
    EXPECT_FLOAT_EQ(s->ly, 0.0f);
    EXPECT_FLOAT_EQ(s->rx, 0.0f);
    EXPECT_FLOAT_EQ(s->ry, -1.0f);
    EXPECT_EQ(s->hat, 7);        // up-left
    EXPECT_EQ(s->buttons, uint32_t(East | R1 | Start | Misc | L2));
    EXPECT_FLOAT_EQ(s->l2, 1.0f);
}

TEST(GamepadSwitchPro, SimpleReport0x3F) {
    auto r = bytes(12);
    r[0] = 0x3f;
    r[1] = 0x01 | 0x10;          // B (South), L
    r[2] = 0x10;                 // home
    r[3] = 0x04;                 // hat down
    r[4] = 0xff, r[5] = 0xff;    // LX max
    r[6] = 0x00, r[7] = 0x80;    // LY centre
    r[8] = 0x00, r[9] = 0x80;
    r[10] = 0x00, r[11] = 0x00;  // RY min = up
    auto s = decodeSwitchPro(r);
    ASSERT_TRUE(s);
    EXPECT_FLOAT_EQ(s->lx, 1.0f);
    EXPECT_FLOAT_EQ(s->ly, 0.0f);
    EXPECT_FLOAT_EQ(s->ry, 1.0f);
    EXPECT_EQ(s->hat, 4);
    EXPECT_EQ(s->buttons, uint32_t(South | L1 | Home));
}

TEST(GamepadSwitchPro, ShortAndSubcommandReplies) {
    auto r = bytes(11);
    r[0] = 0x30;
    EXPECT_FALSE(decodeSwitchPro(r));
    auto reply = bytes(64);
    reply[0] = 0x81;             // USB handshake reply, not input
    EXPECT_FALSE(decodeSwitchPro(reply));
}

// ---- Xbox Wireless Controller (Bluetooth) -------------------------------------------------------

TEST(GamepadXboxWireless, BluetoothReport) {
    auto r = bytes(17);
    r[0] = 0x01;
    r[1] = 0x00, r[2] = 0x80;    // LX centre
    r[3] = 0x00, r[4] = 0x00;    // LY min = up
    r[5] = 0xff, r[6] = 0xff;    // RX right
    r[7] = 0x00, r[8] = 0x80;
    r[9] = 0xff, r[10] = 0x03;   // LT 1023
    r[11] = 0x00, r[12] = 0x00;
    r[13] = 3;                   // hat right
    r[14] = 0x01 | 0x80;         // A, RB
    r[15] = 0x08 | 0x10;         // menu, Xbox
    r[16] = 0x01;                // share
    auto s = decodeXboxWireless(r);
    ASSERT_TRUE(s);
    EXPECT_FLOAT_EQ(s->lx, 0.0f);
    EXPECT_FLOAT_EQ(s->ly, 1.0f);
    EXPECT_FLOAT_EQ(s->rx, 1.0f);
    EXPECT_FLOAT_EQ(s->l2, 1.0f);
    EXPECT_EQ(s->hat, 2);
    EXPECT_EQ(s->buttons, uint32_t(South | R1 | Start | Home | Misc | L2));
}

TEST(GamepadXboxWireless, ShortReport) {
    auto r = bytes(15);
    r[0] = 0x01;
    EXPECT_FALSE(decodeXboxWireless(r));
    auto other = bytes(17);
    other[0] = 0x02;             // the Xbox button report of older firmware
    EXPECT_FALSE(decodeXboxWireless(other));
}

// ---- generic HID gamepad -------------------------------------------------------------------

namespace {
// A small gamepad descriptor: report ID 1; X, Y, Z, Rz as 8-bit 0..255; a 4-bit hat
// 0..7 with 4 bits of padding; 12 buttons, 4 bits padding.
const std::vector<uint8_t> kGenericDescriptor = {
    0x05, 0x01,        // Usage Page (Generic Desktop)
    0x09, 0x05,        // Usage (Game Pad)
    0xa1, 0x01,        // Collection (Application)
    0x85, 0x01,        //   Report ID 1
    0x15, 0x00,        //   Logical Minimum 0
    0x26, 0xff, 0x00,  //   Logical Maximum 255
    0x75, 0x08,        //   Report Size 8
    0x95, 0x04,        //   Report Count 4
    0x09, 0x30, 0x09, 0x31, 0x09, 0x32, 0x09, 0x35,  // X Y Z Rz
    0x81, 0x02,        //   Input (Data, Var, Abs)
    0x25, 0x07,        //   Logical Maximum 7
    0x75, 0x04, 0x95, 0x01,
    0x09, 0x39,        //   Hat switch
    0x81, 0x42,        //   Input (Data, Var, Abs, Null state)
    0x75, 0x04, 0x95, 0x01,
    0x81, 0x03,        //   Input (Constant) padding
    0x05, 0x09,        //   Usage Page (Button)
    0x19, 0x01, 0x29, 0x0c,  // Usage Minimum 1, Maximum 12
    0x15, 0x00, 0x25, 0x01,
    0x75, 0x01, 0x95, 0x0c,
    0x81, 0x02,
    0x75, 0x04, 0x95, 0x01,
    0x81, 0x03,
    0xc0,              // End Collection
};
}  // namespace

TEST(GamepadGeneric, DescriptorFields) {
    HidDescriptor d = parseHidDescriptor(kGenericDescriptor);
    EXPECT_TRUE(d.isGamepad);
    EXPECT_TRUE(d.usesReportIds);
    ASSERT_EQ(d.fields.size(), 4u + 1u + 12u);
    EXPECT_EQ(d.fields[0].usage, 0x30);
    EXPECT_EQ(d.fields[0].bitOffset, 0u);
    EXPECT_EQ(d.fields[0].logicalMax, 255);
    EXPECT_EQ(d.fields[4].usage, 0x39);
    EXPECT_EQ(d.fields[4].bitOffset, 32u);
    EXPECT_EQ(d.fields[5].usagePage, 0x09);
    EXPECT_EQ(d.fields[5].usage, 1);
    EXPECT_EQ(d.fields[5].bitOffset, 40u);
    EXPECT_EQ(d.fields[16].usage, 12);
}

TEST(GamepadGeneric, DecodesAxesHatButtons) {
    HidDescriptor d = parseHidDescriptor(kGenericDescriptor);
    std::vector<uint8_t> r = {0x01, 255, 0, 0, 255, 0x08 | 0x03, 0x05, 0x02};
    // hat nibble 3 (down-right... index 3 of 8 = right-down), upper nibble padding;
    // buttons 1 and 3 (bits 0, 2) and 10 (bit 9).
    r[5] = 0x03;
    auto s = decodeGeneric(d, r);
    ASSERT_TRUE(s);
    EXPECT_FLOAT_EQ(s->lx, 1.0f);
    EXPECT_FLOAT_EQ(s->ly, 1.0f);    // Y 0 is up
    EXPECT_FLOAT_EQ(s->rx, -1.0f);   // Z as right X without Rx/Ry
    EXPECT_FLOAT_EQ(s->ry, -1.0f);   // Rz 255 is down
    EXPECT_EQ(s->hat, 3);
    EXPECT_EQ(s->buttons, uint32_t(South | West | Start));
}

TEST(GamepadGeneric, HatNullStateAndWrongReportId) {
    HidDescriptor d = parseHidDescriptor(kGenericDescriptor);
    std::vector<uint8_t> r = {0x01, 128, 128, 128, 128, 0x0f, 0, 0};
    auto s = decodeGeneric(d, r);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->hat, -1);
    r[0] = 0x02;
    EXPECT_FALSE(decodeGeneric(d, r));
}

TEST(GamepadGeneric, ShortReportKeepsOnlyFieldsInside) {
    HidDescriptor d = parseHidDescriptor(kGenericDescriptor);
    std::vector<uint8_t> r = {0x01, 255};    // X only
    auto s = decodeGeneric(d, r);
    ASSERT_TRUE(s);
    EXPECT_FLOAT_EQ(s->lx, 1.0f);
    EXPECT_EQ(s->buttons, 0u);
    EXPECT_FALSE(decodeGeneric(d, std::vector<uint8_t>{}));
}

TEST(GamepadGeneric, TruncatedDescriptorParsesPrefix) {
    for (size_t n = 0; n <= kGenericDescriptor.size(); ++n) {
        std::vector<uint8_t> part(kGenericDescriptor.begin(), kGenericDescriptor.begin() + long(n));
        HidDescriptor d = parseHidDescriptor(part);
        EXPECT_LE(d.fields.size(), 17u);
    }
}

TEST(GamepadGeneric, SignedAxes) {
    // X, Y as 16-bit −32768..32767 without report IDs.
    const std::vector<uint8_t> desc = {0x05, 0x01, 0x09, 0x04, 0xa1, 0x01, 0x16, 0x00, 0x80,
                                       0x26, 0xff, 0x7f, 0x75, 0x10, 0x95, 0x02, 0x09, 0x30,
                                       0x09, 0x31, 0x81, 0x02, 0xc0};
    HidDescriptor d = parseHidDescriptor(desc);
    EXPECT_TRUE(d.isGamepad);
    EXPECT_FALSE(d.usesReportIds);
    ASSERT_EQ(d.fields.size(), 2u);
    std::vector<uint8_t> r = {0x00, 0x80, 0xff, 0x7f};   // X −32768, Y 32767
    auto s = decodeGeneric(d, r);
    ASSERT_TRUE(s);
    EXPECT_FLOAT_EQ(s->lx, -1.0f);
    EXPECT_FLOAT_EQ(s->ly, -1.0f);
}

// ---- by kind, shaping, fuzz ----------------------------------------------------------------

TEST(GamepadKnownPads, VendorProduct) {
    EXPECT_EQ(knownPad(0x054c, 0x09cc), PadKind::DualShock4);
    EXPECT_EQ(knownPad(0x054c, 0x0ce6), PadKind::DualSense);
    EXPECT_EQ(knownPad(0x057e, 0x2009), PadKind::SwitchPro);
    EXPECT_EQ(knownPad(0x045e, 0x0b13), PadKind::XboxWireless);
    EXPECT_FALSE(knownPad(0x046d, 0xc52b));
}

TEST(GamepadShape, DeadZoneAndCurve) {
    StickShape shape{0.2f, 2.0f};
    float x = 0.1f, y = 0.1f;
    shapeStick(x, y, shape);
    EXPECT_EQ(x, 0.0f);
    EXPECT_EQ(y, 0.0f);
    x = 1.0f, y = 0.0f;
    shapeStick(x, y, shape);
    EXPECT_FLOAT_EQ(x, 1.0f);
    x = 0.6f, y = 0.0f;                  // halfway between dead zone and rim → 0.5² = 0.25
    shapeStick(x, y, shape);
    EXPECT_NEAR(x, 0.25f, 1e-6f);
    x = std::nanf(""), y = 0.5f;
    shapeStick(x, y, shape);
    EXPECT_EQ(x, 0.0f);
}

TEST(GamepadFuzz, RandomBytesNeverCrashAndStayBounded) {
    std::mt19937 rng(7);
    HidDescriptor generic = parseHidDescriptor(kGenericDescriptor);
    const uint8_t ids[] = {0x01, 0x11, 0x31, 0x30, 0x21, 0x3f, 0x00, 0xff};
    for (int i = 0; i < 20000; ++i) {
        std::vector<uint8_t> r(rng() % 80);
        for (auto& b : r) b = uint8_t(rng());
        if (!r.empty() && (i & 1)) r[0] = ids[rng() % 8];
        for (PadKind k : {PadKind::DualShock4, PadKind::DualSense, PadKind::SwitchPro,
                          PadKind::XboxWireless, PadKind::Generic})
            if (auto s = decodeReport(k, generic, r)) expectBounded(*s);
        // Random descriptors, then a random report through them.
        HidDescriptor d = parseHidDescriptor(r);
        std::vector<uint8_t> rep(rng() % 40);
        for (auto& b : rep) b = uint8_t(rng());
        if (auto s = decodeGeneric(d, rep)) expectBounded(*s);
        if (HasFailure()) FAIL() << "iteration " << i;
    }
}
