// Texel formats, texture storage and the emulated texture memory
// (docs/hardware.md, "Texel formats", "Texture storage and memory").
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "tex_test_util.h"
#include "texunit/format.h"
#include "texunit/texture.h"

namespace rg::tex {
namespace {

TEST(TexelFormats, ExpandPerOpenGL12Table315) {
    const uint8_t l[] = {77};
    EXPECT_EQ(expandTexel8(TexelFormat::L8, l), (Rgba8{77, 77, 77, 255}));
    EXPECT_EQ(expandTexel8(TexelFormat::A8, l), (Rgba8{0, 0, 0, 77}));
    EXPECT_EQ(expandTexel8(TexelFormat::I8, l), (Rgba8{77, 77, 77, 77}));
    const uint8_t la[] = {10, 200};
    EXPECT_EQ(expandTexel8(TexelFormat::L8A8, la), (Rgba8{10, 10, 10, 200}));
    const uint8_t rgb[] = {1, 2, 3};
    EXPECT_EQ(expandTexel8(TexelFormat::RGB8, rgb), (Rgba8{1, 2, 3, 255}));
    const uint8_t rgba[] = {1, 2, 3, 4};
    EXPECT_EQ(expandTexel8(TexelFormat::RGBA8, rgba), (Rgba8{1, 2, 3, 4}));
}

TEST(TexelFormats, PackedFieldsWidenByBitReplication) {
    // RGB565 0xF81F: R = 31, G = 0, B = 31 → (255, 0, 255); 0x07E0: G = 63 → 255.
    const uint8_t magenta[] = {0x1f, 0xf8}, green[] = {0xe0, 0x07};
    EXPECT_EQ(expandTexel8(TexelFormat::RGB565, magenta), (Rgba8{255, 0, 255, 255}));
    EXPECT_EQ(expandTexel8(TexelFormat::RGB565, green), (Rgba8{0, 255, 0, 255}));
    // R = 16 (10000b) → 10000100b = 132; G = 32 (100000b) → 10000010b = 130.
    const uint8_t mid[] = {uint8_t((32 << 5) & 0xff), uint8_t((16 << 3) | (32 >> 3))};
    EXPECT_EQ(expandTexel8(TexelFormat::RGB565, mid), (Rgba8{132, 130, 0, 255}));
    // RGBA4444 0x1234 → 17·(1, 2, 3, 4).
    const uint8_t w4[] = {0x34, 0x12};
    EXPECT_EQ(expandTexel8(TexelFormat::RGBA4444, w4), (Rgba8{17, 34, 51, 68}));
    // Bit replication is within one 8-bit step of x·255/(2^n − 1) and differs from its
    // rounding in 4 of the 32 five-bit and 10 of the 64 six-bit values (by one step).
    int off5 = 0, off6 = 0;
    for (uint32_t x = 0; x < 32; ++x) {
        uint16_t w = uint16_t(x << 11);
        const uint8_t b[] = {uint8_t(w & 0xff), uint8_t(w >> 8)};
        const double exact = x * 255.0 / 31.0;
        const int v = expandTexel8(TexelFormat::RGB565, b).r;
        EXPECT_LT(std::abs(v - exact), 1.0);
        off5 += v != int(std::floor(exact + 0.5));
    }
    for (uint32_t x = 0; x < 64; ++x) {
        uint16_t w = uint16_t(x << 5);
        const uint8_t b[] = {uint8_t(w & 0xff), uint8_t(w >> 8)};
        const double exact = x * 255.0 / 63.0;
        const int v = expandTexel8(TexelFormat::RGB565, b).g;
        EXPECT_LT(std::abs(v - exact), 1.0);
        off6 += v != int(std::floor(exact + 0.5));
    }
    EXPECT_EQ(off5, 4);
    EXPECT_EQ(off6, 10);
}

TEST(TexelFormats, HalfFloatAndDepth) {
    EXPECT_EQ(halfToFloat(0x3c00), 1.0f);
    EXPECT_EQ(halfToFloat(0xc000), -2.0f);
    EXPECT_EQ(halfToFloat(0x3800), 0.5f);
    EXPECT_EQ(halfToFloat(0x0001), 5.9604644775390625e-8f);  // smallest subnormal
    const uint8_t d16[] = {0xff, 0xff};
    EXPECT_EQ(expandTexelFloat(TexelFormat::Depth16, d16), glm::vec4(1, 1, 1, 1));
    EXPECT_EQ(floatToRgba8(glm::vec4(0.5f, -1.0f, 2.0f, 1.0f / 255.0f)), (Rgba8{128, 0, 255, 1}));
}

TEST(TextureMemory, CountsPackedBytesAndRefusesOverflow) {
    const Profile& p = profile(ProfileId::SgiOctaneMxe);  // 4 MiB TRAM, 1024² max
    TextureMemory mem(p);
    auto a = mem.create({TextureTarget::Texture2D, TexelFormat::RGBA8, 1024, 512, 1, 1, 1});
    EXPECT_EQ(a->bytes(), 1024u * 512u * 4u);
    EXPECT_EQ(mem.residentBytes(), 2u * 1024u * 1024u);
    auto b = mem.create({TextureTarget::Texture2D, TexelFormat::RGBA8, 1024, 512, 1, 1, 1});
    EXPECT_EQ(mem.residentBytes(), 4u * 1024u * 1024u);
    EXPECT_THROW(mem.create({TextureTarget::Texture2D, TexelFormat::L8, 1, 1, 1, 1, 1}),
                 UnsupportedFeature);
    b.reset();  // freeing makes room again
    EXPECT_EQ(mem.residentBytes(), 2u * 1024u * 1024u);
    auto c = mem.create({TextureTarget::Texture2D, TexelFormat::L8, 16, 16, 1, 1, 5});
    EXPECT_EQ(c->bytes(), 256u + 64u + 16u + 4u + 1u);
}

TEST(TextureMemory, UploadsAreCountedPerFrame) {
    TextureMemory mem(profile(ProfileId::GeForce256));
    auto t = mem.create({TextureTarget::Texture2D, TexelFormat::RGB565, 8, 4, 1, 1, 2});
    EXPECT_FALSE(t->complete());
    mem.upload(*t, 0, 0, std::vector<uint8_t>(8 * 4 * 2));
    mem.upload(*t, 1, 0, std::vector<uint8_t>(4 * 2 * 2));
    EXPECT_TRUE(t->complete());
    EXPECT_EQ(mem.uploadBytes(), 64u + 16u);
    mem.resetFrameCounters();
    EXPECT_EQ(mem.uploadBytes(), 0u);
    EXPECT_THROW(mem.upload(*t, 0, 0, std::vector<uint8_t>(10)), InvalidState);
    EXPECT_THROW(mem.upload(*t, 2, 0, std::vector<uint8_t>(2)), InvalidState);
}

// RGB8 and RGBA8 uploads (their own fast loops, texture_storage.cpp) against the
// OpenGL 1.2 §3.8.1 / table 3.15 expansion written out here: RGB's missing alpha is 1.0,
// i.e. 255; RGBA is taken as is. Every face and level of a cube map, so that the face
// offset and the level's size are exercised, and random bytes so that no channel order
// mix-up passes.
TEST(TextureMemory, Rgb8AndRgba8UploadsExpandPerTheSpec) {
    TextureMemory mem(profile(ProfileId::GeForce256));
    uint32_t seed = 12345u;
    auto next = [&] {
        seed = seed * 1664525u + 1013904223u;
        return uint8_t(seed >> 24);
    };
    for (TexelFormat f : {TexelFormat::RGB8, TexelFormat::RGBA8}) {
        const int bpt = f == TexelFormat::RGB8 ? 3 : 4;
        auto t = mem.create({TextureTarget::CubeMap, f, 8, 8, 1, 1, 4});
        for (int face = 0; face < 6; ++face)
            for (int level = 0; level < 4; ++level) {
                const int n = 8 >> level;
                std::vector<uint8_t> bytes(size_t(n) * n * bpt);
                for (uint8_t& b : bytes) b = next();
                mem.upload(*t, level, face, bytes);
                for (int y = 0; y < n; ++y)
                    for (int x = 0; x < n; ++x) {
                        const uint8_t* p = &bytes[(size_t(y) * n + x) * bpt];
                        const Rgba8 got = t->texel8(level, face, x, y, 0, 0);
                        EXPECT_EQ(got.r, p[0]);
                        EXPECT_EQ(got.g, p[1]);
                        EXPECT_EQ(got.b, p[2]);
                        EXPECT_EQ(got.a, bpt == 4 ? p[3] : 255);
                        if (::testing::Test::HasFailure()) return;
                    }
            }
        EXPECT_TRUE(t->complete());
    }
    // A second face's upload must not touch the first's texels.
    auto t = mem.create({TextureTarget::CubeMap, TexelFormat::RGB8, 4, 4, 1, 1, 1});
    mem.upload(*t, 0, 0, std::vector<uint8_t>(4 * 4 * 3, 7));
    mem.upload(*t, 0, 1, std::vector<uint8_t>(4 * 4 * 3, 9));
    EXPECT_EQ(t->texel8(0, 0, 3, 3, 0, 0).r, 7);
    EXPECT_EQ(t->texel8(0, 1, 0, 0, 0, 0).r, 9);
}

TEST(TextureMemory, ProfileLimitsAndFeatures) {
    TextureMemory gf(profile(ProfileId::GeForce256));
    EXPECT_THROW(gf.create({TextureTarget::Texture2D, TexelFormat::RGBA8, 4096, 1, 1, 1, 1}),
                 UnsupportedFeature);  // > 2048
    EXPECT_THROW(gf.create({TextureTarget::Texture2D, TexelFormat::RGBA8, 48, 64, 1, 1, 1}),
                 UnsupportedFeature);  // not a power of two
    EXPECT_THROW(gf.create({TextureTarget::CubeMap, TexelFormat::RGBA8, 1024, 1024, 1, 1, 1}),
                 UnsupportedFeature);  // cube faces ≤ 512
    EXPECT_THROW(gf.create({TextureTarget::Texture4D, TexelFormat::RGBA8, 4, 4, 4, 4, 1}),
                 UnsupportedFeature);
    EXPECT_THROW(gf.create({TextureTarget::Texture2D, TexelFormat::RGBA32F, 4, 4, 1, 1, 1}),
                 UnsupportedFeature);
    EXPECT_THROW(gf.create({TextureTarget::CubeMap, TexelFormat::RGBA8, 8, 4, 1, 1, 1}), InvalidState);
    EXPECT_THROW(gf.create({TextureTarget::Texture2D, TexelFormat::RGBA8, 8, 8, 1, 1, 5}), InvalidState);
    TextureMemory g8(profile(ProfileId::GeForce8800));
    EXPECT_NO_THROW(g8.create({TextureTarget::Texture2D, TexelFormat::RGBA32F, 48, 64, 1, 1, 1}));
    EXPECT_NO_THROW(g8.create({TextureTarget::Texture2D, TexelFormat::Depth24, 16, 16, 1, 1, 1}));
    TextureMemory sgi(profile(ProfileId::SgiOctaneMxe));
    EXPECT_THROW(sgi.create({TextureTarget::CubeMap, TexelFormat::RGBA8, 8, 8, 1, 1, 1}),
                 UnsupportedFeature);
    EXPECT_NO_THROW(sgi.create({TextureTarget::Texture4D, TexelFormat::RGBA8, 16, 16, 16, 16, 1}));
    EXPECT_THROW(sgi.create({TextureTarget::Texture4D, TexelFormat::RGBA8, 128, 2, 2, 2, 1}),
                 UnsupportedFeature);  // > 64
}

TEST(TextureMemory, BoxMipmapsAverageWithRounding) {
    TextureMemory mem(profile(ProfileId::GeForce256));
    auto t = mem.create({TextureTarget::Texture2D, TexelFormat::L8, 4, 2, 1, 1, 3});
    // Level 0 rows: 0 1 2 3 / 4 5 6 8 → level 1: round(10/4)=3 (2.5 rounds up), round(19/4)=5
    mem.upload(*t, 0, 0, std::vector<uint8_t>{0, 1, 2, 3, 4, 5, 6, 8});
    mem.buildBoxMipmaps(*t);
    EXPECT_TRUE(t->complete());
    EXPECT_EQ(t->texel8(1, 0, 0, 0, 0, 0).r, 3);
    EXPECT_EQ(t->texel8(1, 0, 1, 0, 0, 0).r, 5);
    EXPECT_EQ(t->texel8(2, 0, 0, 0, 0, 0).r, 4);  // (3 + 5)/2
}

}  // namespace
}  // namespace rg::tex
