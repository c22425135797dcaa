// SGI_texture_color_table and SGIX_pixel_texture (docs/hardware.md, "Colour tables",
// "Pixel texture").
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "tex_test_util.h"
#include "texunit/color_table.h"
#include "texunit/texture_units.h"

namespace rg::tex {
namespace {

using testing::makeRgba8;
using testing::Rng;

TEST(ColorTable, IndexIsRoundOfClampTimesNMinus1) {
    // Exhaustive: every 8-bit component against every table size 1..256 (65,536 pairs),
    // round(v/255·(N−1)) with halves rounded up, as a quotient and remainder in integers.
    for (size_t n = 1; n <= 256; ++n)
        for (int v = 0; v < 256; ++v) {
            const uint32_t q = uint32_t(v) * uint32_t(n - 1);
            ASSERT_EQ(colorTableIndex(uint8_t(v), n), q / 255 + (2 * (q % 255) >= 255 ? 1 : 0))
                << "v=" << v << " N=" << n;
        }
    EXPECT_EQ(colorTableIndex(42, 4), 0u);  // 0.494 → 0
    EXPECT_EQ(colorTableIndex(43, 4), 1u);  // 0.506 → 1
}

// Pinned (docs/hardware.md): a table of 0 entries reads none and changes nothing.
TEST(ColorTable, AnEmptyTableChangesNothing) {
    ColorTable t;
    for (BaseFormat f : {BaseFormat::Alpha, BaseFormat::Luminance, BaseFormat::LuminanceAlpha,
                         BaseFormat::Intensity, BaseFormat::Rgb, BaseFormat::Rgba}) {
        t.format = f;
        for (Rgba8 c : {Rgba8{0, 85, 170, 255}, Rgba8{1, 2, 3, 4}}) EXPECT_EQ(applyColorTable(t, c), c);
    }
}

TEST(ColorTable, MappingPerTableBaseFormat) {
    ColorTable t;
    for (int i = 0; i < 4; ++i)
        t.entries.push_back({uint8_t(10 + i), uint8_t(20 + i), uint8_t(30 + i), uint8_t(40 + i)});
    const Rgba8 texel{0, 85, 170, 255};  // indices 0, 1, 2, 3
    struct Row { BaseFormat f; Rgba8 expect; };
    const Row rows[] = {
        {BaseFormat::Alpha, {0, 85, 170, 43}},
        {BaseFormat::Luminance, {10, 11, 12, 255}},
        {BaseFormat::LuminanceAlpha, {10, 11, 12, 43}},
        {BaseFormat::Intensity, {10, 11, 12, 13}},
        {BaseFormat::Rgb, {10, 21, 32, 255}},
        {BaseFormat::Rgba, {10, 21, 32, 43}},
    };
    for (const Row& r : rows) {
        t.format = r.f;
        EXPECT_EQ(applyColorTable(t, texel), r.expect) << baseFormatName(r.f);
    }
    EXPECT_EQ(colorTableResultFormat(BaseFormat::Intensity, BaseFormat::Rgba), BaseFormat::Rgba);
    EXPECT_EQ(colorTableResultFormat(BaseFormat::Luminance, BaseFormat::Alpha), BaseFormat::LuminanceAlpha);
    EXPECT_EQ(colorTableResultFormat(BaseFormat::Luminance, BaseFormat::Luminance), BaseFormat::Luminance);
    EXPECT_EQ(colorTableResultFormat(BaseFormat::Alpha, BaseFormat::Rgb), BaseFormat::Rgba);
}

TEST(ColorTable, VqCodebookDecodingFromAnI8IndexTexture) {
    const Profile& p = profile(ProfileId::SgiOctaneMxe);
    TextureMemory mem(p);
    auto idx = mem.create({TextureTarget::Texture2D, TexelFormat::I8, 4, 4, 1, 1, 1});
    std::vector<uint8_t> indices(16);
    for (int i = 0; i < 16; ++i) indices[size_t(i)] = uint8_t(i * 17);
    mem.upload(*idx, 0, 0, indices);
    auto table = std::make_shared<ColorTable>();
    table->format = BaseFormat::Rgba;
    for (int i = 0; i < 256; ++i)
        table->entries.push_back({uint8_t(255 - i), uint8_t(i / 2), uint8_t(i * 3), uint8_t(i ^ 0x5a)});
    TextureUnits tu;
    tu.setTexture(0, idx);
    SamplerState s;
    s.magFilter = s.minFilter = FilterMode::Nearest;
    tu.setSampler(0, s);
    tu.setColorTable(0, table);
    tu.setStage(0, texEnvStage(TexEnvMode::Replace,
                               colorTableResultFormat(BaseFormat::Intensity, BaseFormat::Rgba)));
    EXPECT_NO_THROW(tu.validate(p));
    EXPECT_THROW(tu.validate(profile(ProfileId::GeForce256)), UnsupportedFeature);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; x += 2) {
            FragmentQuad q;
            for (int i = 0; i < 4; ++i) {
                int px = x + (i & 1), py = std::min(3, y + (i >> 1));
                q.texCoord[0][size_t(i)] = {(px + 0.5f) / 4, (py + 0.5f) / 4, 0, 1};
                q.diffuse[size_t(i)] = {1, 2, 3, 4};
            }
            std::array<Rgba8, 4> out;
            tu.shadeQuad(q, out, Path::Reference);
            for (int i = 0; i < 2; ++i)
                EXPECT_EQ(out[size_t(i)], table->entries[size_t((y * 4 + x + i) * 17)]) << x << "," << y;
        }
}

TEST(PixelTexture, IdentityTexture2DLeavesTheImageUnchanged) {
    const Profile& p = profile(ProfileId::SgiOctaneMxe);
    TextureMemory mem(p);
    auto id = makeRgba8(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 256, 256, 1, 1, 1},
                        [](int, int, int x, int y, int, int) { return Rgba8{uint8_t(x), uint8_t(y), 0, 255}; });
    TextureUnits tu;
    tu.setTexture(0, id);
    SamplerState s;
    s.magFilter = s.minFilter = FilterMode::Nearest;
    s.address = {AddressMode::ClampToEdge, AddressMode::ClampToEdge, AddressMode::ClampToEdge,
                 AddressMode::ClampToEdge};
    tu.setSampler(0, s);
    tu.setPixelTexture({true, PixelTexGenMode::Rgba, 0});
    EXPECT_NO_THROW(tu.validate(p));
    EXPECT_THROW(tu.validate(profile(ProfileId::SgiO2)), UnsupportedFeature);  // no pixel texture
    std::vector<Rgba8> image;
    for (int r = 0; r < 256; ++r)
        for (int g = 0; g < 256; g += 3) image.push_back({uint8_t(r), uint8_t(g), 0, 255});
    std::vector<Rgba8> row = image;
    tu.applyPixelTransfer(row);
    EXPECT_EQ(row, image);
    // RGB mode: q = 1 and the pixel's alpha is kept.
    tu.setPixelTexture({true, PixelTexGenMode::Rgb, 0});
    for (size_t i = 0; i < image.size(); ++i) image[i].a = uint8_t(i * 7);
    row = image;
    tu.applyPixelTransfer(row);
    EXPECT_EQ(row, image);
    EXPECT_GT(tu.counters().texelFetches, 0u);
}

// RGBA mode divides (R, G, B) by A before the lookup (SGIX_pixel_texture: q = A). With a
// 16×16 texture whose texel (x, y) holds (16x, 16y) and A = 128, pixel R = 4(2m + 1)
// reads s = R/A = (2m + 1)/32, texel ⌊16s⌋ = m — half a texel from either edge, so float
// rounding cannot move it. Without the divide the lookup lands elsewhere.
TEST(PixelTexture, RgbaModeDividesByAlphaBeforeTheLookup) {
    const Profile& p = profile(ProfileId::SgiOctaneMxe);
    TextureMemory mem(p);
    auto id = makeRgba8(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 16, 16, 1, 1, 1},
                        [](int, int, int x, int y, int, int) { return Rgba8{uint8_t(16 * x), uint8_t(16 * y), 7, 255}; });
    TextureUnits tu;
    tu.setTexture(0, id);
    SamplerState s;
    s.magFilter = s.minFilter = FilterMode::Nearest;
    s.address = {AddressMode::ClampToEdge, AddressMode::ClampToEdge, AddressMode::ClampToEdge,
                 AddressMode::ClampToEdge};
    tu.setSampler(0, s);
    tu.setPixelTexture({true, PixelTexGenMode::Rgba, 0});
    std::vector<Rgba8> row, want;
    for (int m = 0; m < 16; ++m)
        for (int n = 0; n < 16; n += 5) {
            row.push_back({uint8_t(4 * (2 * m + 1)), uint8_t(4 * (2 * n + 1)), 200, 128});
            want.push_back({uint8_t(16 * m), uint8_t(16 * n), 7, 255});
        }
    tu.applyPixelTransfer(row);
    EXPECT_EQ(row, want);
}

TEST(PixelTexture, QAtOrBelowZeroGivesTheBorderColour) {
    TextureMemory mem(profile(ProfileId::SgiOctaneMxe));
    auto id = makeRgba8(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 4, 4, 1, 1, 1},
                        [](int, int, int, int, int, int) { return Rgba8{1, 1, 1, 1}; });
    TextureUnits tu;
    tu.setTexture(0, id);
    SamplerState s;
    s.borderColor = {9, 8, 7, 6};
    tu.setSampler(0, s);
    tu.setPixelTexture({true, PixelTexGenMode::Rgba, 0});
    std::vector<Rgba8> row{{100, 100, 100, 0}, {100, 100, 100, 255}};
    tu.applyPixelTransfer(row);
    EXPECT_EQ(row[0], (Rgba8{9, 8, 7, 6}));
    EXPECT_EQ(row[1], (Rgba8{1, 1, 1, 1}));
}

TEST(PixelTexture, IdentityTexture4DLeavesQuantizedImageUnchanged) {
    const Profile& p = profile(ProfileId::SgiOctaneMxe);
    TextureMemory mem(p);
    auto id = makeRgba8(mem, {TextureTarget::Texture4D, TexelFormat::RGBA8, 16, 16, 16, 16, 1},
                        [](int, int, int x, int y, int z, int w) {
                            return Rgba8{uint8_t(17 * x), uint8_t(17 * y), uint8_t(17 * z), uint8_t(17 * w)};
                        });
    TextureUnits tu;
    tu.setTexture(0, id);
    SamplerState s;
    s.magFilter = s.minFilter = FilterMode::Nearest;
    s.address = {AddressMode::ClampToEdge, AddressMode::ClampToEdge, AddressMode::ClampToEdge,
                 AddressMode::ClampToEdge};
    tu.setSampler(0, s);
    tu.setPixelTexture({true, PixelTexGenMode::Rgba, 0});
    EXPECT_NO_THROW(tu.validate(p));
    std::vector<Rgba8> image;
    Rng rng(4);
    for (int i = 0; i < 20000; ++i)
        image.push_back({uint8_t(17 * rng.below(16)), uint8_t(17 * rng.below(16)),
                         uint8_t(17 * rng.below(16)), uint8_t(17 * rng.below(16))});
    std::vector<Rgba8> row = image;
    tu.applyPixelTransfer(row);
    EXPECT_EQ(row, image);
    // Quadrilinear: the pixel (R, G, B, A) = 255·((i + ½)/16) would sit on texel centres;
    // between two texel centres in every dimension the result is their mean.
    s.magFilter = FilterMode::Linear;
    tu.setSampler(0, s);
    // R = 8 → u − ½ = 8·16/255 − ½ = 0.0019..: almost exactly texel 0 → 0; R = 24:
    // 24·16/255 − ½ = 1.0059 → texel 1 (17) plus 0.0059·17 → 17.
    std::vector<Rgba8> two{{8, 8, 8, 8}, {24, 24, 24, 24}};
    tu.applyPixelTransfer(two);
    EXPECT_EQ(two[0], (Rgba8{0, 0, 0, 0}));
    EXPECT_EQ(two[1], (Rgba8{17, 17, 17, 17}));
}

}  // namespace
}  // namespace rg::tex
