// Exhaustive checks of the 8-bit multiplies against their one-line definitions
// (docs/hardware.md, "8-bit arithmetic").
#include <gtest/gtest.h>

#include <cmath>

#include "core/arith8.h"

namespace rg {
namespace {

TEST(Arith8, MulDiv255IsExactRoundingForAll65536Pairs) {
    for (uint32_t a = 0; a < 256; ++a)
        for (uint32_t b = 0; b < 256; ++b) {
            uint32_t expected = uint32_t(std::floor(double(a) * double(b) / 255.0 + 0.5));
            ASSERT_EQ(arith8::mulDiv255(a, b), expected) << "a=" << a << " b=" << b;
        }
}

TEST(Arith8, MulShiftDiffersFromExactIn18760Cases) {
    int differ = 0;
    for (uint32_t a = 0; a < 256; ++a)
        for (uint32_t b = 0; b < 256; ++b) {
            ASSERT_EQ(arith8::mulShift(a, b), (a * (b + 1)) >> 8);
            differ += arith8::mulShift(a, b) != arith8::mulDiv255(a, b);
        }
    EXPECT_EQ(differ, 18760);
}

TEST(Arith8, IdentitiesHoldForBothMultiplies) {
    for (uint32_t x = 0; x < 256; ++x) {
        EXPECT_EQ(arith8::mulDiv255(x, 255), x);
        EXPECT_EQ(arith8::mulDiv255(x, 0), 0u);
        EXPECT_EQ(arith8::mulShift(x, 255), x);
        EXPECT_EQ(arith8::mulShift(x, 0), 0u);
    }
}

TEST(Arith8, SaturatingAddAndSubtract) {
    for (uint32_t a = 0; a < 256; ++a)
        for (uint32_t b = 0; b < 256; ++b) {
            ASSERT_EQ(arith8::addSat(a, b), std::min(a + b, 255u));
            ASSERT_EQ(arith8::subSat(a, b), a >= b ? a - b : 0u);
        }
}

}  // namespace
}  // namespace rg
