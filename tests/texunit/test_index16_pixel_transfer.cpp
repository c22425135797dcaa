// The sgi-octane-mxe extensions of Heidrich et al. 1999 §5 (16-bit index textures through
// 65,536-entry colour tables) and the pixel-transfer fast path against its reference
// (docs/hardware.md, "Colour tables", "Pixel texture").
#include <gtest/gtest.h>

#include "core/error.h"
#include "rasterizer/device.h"
#include "tex_test_util.h"
#include "texunit/color_table.h"
#include "texunit/texture_units.h"

namespace rg::tex {
namespace {

using testing::makeRgba8;
using testing::Rng;

TEST(ColorTable16, IndexIsRoundOfClampTimesNMinus1ForEvery16BitValue) {
    // Exhaustive over the 65,536 values at four table sizes: round(v/65535·(N − 1)), halves
    // up, as a quotient and remainder.
    for (size_t n : {size_t(1), size_t(256), size_t(1000), size_t(65536)})
        for (uint32_t v = 0; v < 65536; ++v) {
            const uint64_t q = uint64_t(v) * (n - 1);
            const uint64_t expect = n <= 1 ? 0 : q / 65535 + (2 * (q % 65535) >= 65535 ? 1 : 0);
            ASSERT_EQ(colorTableIndex16(uint16_t(v), n), expect) << "v=" << v << " N=" << n;
        }
    EXPECT_EQ(colorTableIndex16(12345, 65536), 12345u);  // the 2-byte index itself
    EXPECT_EQ(narrow16(65535), 255);
    EXPECT_EQ(narrow16(257 * 100), 100);
    EXPECT_EQ(narrow16(128), 0);  // 0.498 of a step
    EXPECT_EQ(narrow16(129), 1);
}

std::shared_ptr<Texture> makeI16(TextureMemory& mem, int w, int h, const std::vector<uint16_t>& v) {
    auto t = mem.create({TextureTarget::Texture2D, TexelFormat::I16, w, h, 1, 1, 1});
    std::vector<uint8_t> bytes;
    for (uint16_t x : v) bytes.insert(bytes.end(), {uint8_t(x & 0xff), uint8_t(x >> 8)});
    mem.upload(*t, 0, 0, bytes);
    return t;
}

std::shared_ptr<ColorTable> codebookTable(size_t n) {
    auto table = std::make_shared<ColorTable>();
    table->format = BaseFormat::Rgba;
    for (size_t i = 0; i < n; ++i)
        table->entries.push_back({uint8_t(i), uint8_t(i >> 8), uint8_t(i * 7), uint8_t(i ^ (i >> 8))});
    return table;
}

TEST(ColorTable16, TwoByteIndicesDecodeEveryEntryOfA65536EntryCodebook) {
    // Heidrich et al. 1999 §5: "all 16 RGB colors in the block are replaced by a single 2
    // Byte color index" into a 2^16-entry table. Every index 0 … 65535 must reach its own
    // entry through the texture unit (NEAREST, I16 through an RGBA table).
    const Profile& p = profile(ProfileId::SgiOctaneMxe);
    EXPECT_EQ(p.colorTableSize, 65536);
    TextureMemory mem(p);
    std::vector<uint16_t> idx(256 * 256);
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = uint16_t(testing::hash32(uint32_t(i)) ^ i);
    auto t = makeI16(mem, 256, 256, idx);
    EXPECT_EQ(t->bytes(), 256u * 256u * 2u);  // two bytes a texel in texture memory
    auto table = codebookTable(65536);
    TextureUnits tu;
    tu.setTexture(0, t);
    SamplerState s;
    s.magFilter = s.minFilter = FilterMode::Nearest;
    tu.setSampler(0, s);
    tu.setColorTable(0, table);
    tu.setStage(0, texEnvStage(TexEnvMode::Replace, colorTableResultFormat(BaseFormat::Intensity, BaseFormat::Rgba)));
    EXPECT_NO_THROW(tu.validate(p));
    // The O2 keeps 256-entry tables: a 65,536-entry one is refused, naming the profile.
    try {
        tu.validate(profile(ProfileId::SgiO2));
        ADD_FAILURE() << "sgi-o2 accepted a 65,536-entry colour table";
    } catch (const UnsupportedFeature& e) {
        EXPECT_NE(std::string(e.what()).find("sgi-o2"), std::string::npos) << e.what();
    }
    for (Path path : {Path::Reference, Path::Fast})
        for (int y = 0; y < 256; y += 2)
            for (int x = 0; x < 256; x += 2) {
                FragmentQuad q;
                q.coverage = 15;
                for (int i = 0; i < 4; ++i)
                    q.texCoord[0][size_t(i)] = {(x + (i & 1) + 0.5f) / 256, (y + (i >> 1) + 0.5f) / 256, 0, 1};
                std::array<Rgba8, 4> out;
                tu.shadeQuad(q, out, path);
                for (int i = 0; i < 4; ++i) {
                    const uint16_t v = idx[size_t(y + (i >> 1)) * 256 + size_t(x + (i & 1))];
                    ASSERT_EQ(out[size_t(i)], table->entries[v]) << x << "," << y;
                }
            }
}

TEST(ColorTable16, WithoutATableAnI16TextureReadsItsEightBitExpansion) {
    TextureMemory mem(profile(ProfileId::SgiOctaneMxe));
    auto t = makeI16(mem, 2, 2, {0, 257 * 7, 65535, 128});
    for (int x = 0; x < 2; ++x)
        for (int y = 0; y < 2; ++y) {
            const Rgba8 c = t->texel8(0, 0, x, y, 0, 0);
            EXPECT_EQ(c.r, narrow16(t->texel16(0, 0, x, y, 0, 0)));
            EXPECT_EQ(c.a, c.r);
        }
    EXPECT_EQ(t->texel8(0, 0, 1, 0, 0, 0).r, 7);
}

TEST(ColorTable16, LinearFilteringInterpolatesTheIndexAtSixteenBits) {
    // Two texels 1000 and 3000, sampled halfway: the filtered index is 2000 exactly (the
    // 8-bit path could not name it), and a 65,536-entry table returns entry 2000.
    TextureMemory mem(profile(ProfileId::SgiOctaneMxe));
    auto t = makeI16(mem, 2, 1, {1000, 3000});
    SamplerState s;
    s.address = {AddressMode::ClampToEdge, AddressMode::ClampToEdge, AddressMode::ClampToEdge, AddressMode::ClampToEdge};
    TapList taps;
    gatherTaps(*t, s, {0.5f, 0.5f, 0, 0}, -(1 << 20), taps);
    EXPECT_EQ(resolveTaps16(*t, s, taps), 2000);
    auto table = codebookTable(65536);
    EXPECT_EQ(applyColorTable16(*table, 2000), table->entries[2000]);
}

// Random pixel-texture states: every row transferred on the reference and the fast path
// must give the same bytes and count the same fetches.
TEST(PixelTransfer, FastPathMatchesReferenceUnderRandomStates) {
    const Profile& p = profile(ProfileId::SgiOctaneMxe);
    Rng rng(7);
    int fastStates = 0;
    for (int iter = 0; iter < 120; ++iter) {
        TextureMemory mem(p);
        const int kind = int(rng.below(3));  // 2D, 3D, 4D
        TextureDesc d;
        d.target = kind == 0 ? TextureTarget::Texture2D : kind == 1 ? TextureTarget::Texture3D : TextureTarget::Texture4D;
        d.width = 1 << rng.below(kind == 2 ? 4 : 7);
        d.height = 1 << rng.below(kind == 2 ? 4 : 7);
        d.depth = kind >= 1 ? 1 << rng.below(kind == 2 ? 4 : 3) : 1;
        d.size4 = kind == 2 ? 1 << rng.below(4) : 1;
        const uint32_t seed = rng.next();
        auto t = makeRgba8(mem, d, [&](int, int, int x, int y, int z, int w) {
            const uint32_t h = testing::hash32(seed ^ uint32_t(((w * 64 + z) * 128 + y) * 128 + x));
            return Rgba8{uint8_t(h), uint8_t(h >> 8), uint8_t(h >> 16), uint8_t(h >> 24)};
        });
        TextureUnits tu;
        tu.setTexture(0, t);
        SamplerState s;
        s.magFilter = rng.below(2) ? FilterMode::Linear : FilterMode::Nearest;
        for (auto& a : s.address) a = AddressMode(rng.below(5));
        s.borderColor = {uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next())};
        tu.setSampler(0, s);
        if (rng.below(3) == 0) {
            auto table = std::make_shared<ColorTable>();
            table->format = BaseFormat(rng.below(6));
            const size_t n = 1 + rng.below(256);
            for (size_t i = 0; i < n; ++i) table->entries.push_back({uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next())});
            tu.setColorTable(0, table);
        }
        tu.setPixelTexture({true, rng.below(2) ? PixelTexGenMode::Rgb : PixelTexGenMode::Rgba, 0});
        std::vector<Rgba8> row(333);
        for (auto& px : row) px = {uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next())};
        row[0] = {0, 0, 0, 0};
        row[1] = {255, 255, 255, 255};
        std::vector<Rgba8> a = row, b = row;
        tu.resetCounters();
        tu.applyPixelTransfer(a, Path::Reference);
        const uint64_t fa = tu.counters().texelFetches;
        tu.resetCounters();
        tu.applyPixelTransfer(b, Path::Fast);
        const uint64_t fb = tu.counters().texelFetches;
        for (size_t i = 0; i < a.size(); ++i) ASSERT_EQ(a[i], b[i]) << "iteration " << iter << " pixel " << i << " kind " << kind << " mode " << int(tu.pixelTexture().mode) << " filter " << int(s.magFilter) << " addr " << int(s.address[0]) << int(s.address[1]) << int(s.address[2]) << int(s.address[3]) << " table " << (tu.colorTable(0) ? int(tu.colorTable(0)->format) : -1) << " size " << d.width << "x" << d.height << "x" << d.depth << "x" << d.size4;
        ASSERT_EQ(fa, fb) << "iteration " << iter;
        fastStates += (tu.pixelTexture().mode == PixelTexGenMode::Rgb || kind == 2);
    }
    EXPECT_GT(fastStates, 40);  // the fast path's states were drawn often
}

TEST(PixelTransfer, DrawPixelsOnAnyPathAndThreadCountGivesTheReferenceBytes) {
    const Profile& p = profile(ProfileId::SgiOctaneMxe);
    TextureMemory mem(p);
    auto t = makeRgba8(mem, {TextureTarget::Texture3D, TexelFormat::RGBA8, 64, 64, 2, 1, 1},
                       [](int, int, int x, int y, int z, int) { return Rgba8{uint8_t(4 * x), uint8_t(4 * y), uint8_t(200 * z), 255}; });
    std::vector<Rgba8> image(300 * 200);
    for (size_t i = 0; i < image.size(); ++i) {
        const uint32_t h = testing::hash32(uint32_t(i));
        image[i] = {uint8_t(h), uint8_t(h >> 8), uint8_t((h >> 16) & 1 ? 255 : 0), uint8_t(h >> 24)};
    }
    std::vector<Rgba8> expect;
    for (Path path : {Path::Reference, Path::Fast})
        for (int threads : {1, 2, 3}) {
            raster::Device dev(p, 256, 256, raster::DepthFormat::None, {path, threads});
            auto& tu = dev.textureUnits();
            tu.setTexture(0, t);
            SamplerState s;
            s.address = {AddressMode::ClampToEdge, AddressMode::ClampToEdge, AddressMode::ClampToEdge, AddressMode::ClampToEdge};
            tu.setSampler(0, s);
            tu.setPixelTexture({true, PixelTexGenMode::Rgb, 0});
            dev.beginFrame();
            dev.drawPixels(-20, 30, 300, 200, image);  // clipped on the left and at the bottom
            const std::vector<Rgba8> got = dev.readPixels(0, 0, 256, 256);
            if (expect.empty()) expect = got;
            ASSERT_EQ(got, expect) << "path " << int(path) << ", " << threads << " threads";
        }
}

TEST(PixelTransfer, PixelTextureOnAProfileWithoutItIsRefusedNamingTheProfile) {
    // The O2 has no SGIX_pixel_texture (Heidrich et al. ran its lookup in software): a
    // drawPixels with it enabled is an error, never a silent lookup or a silent copy.
    const Profile& o2 = profile(ProfileId::SgiO2);
    TextureMemory mem(o2);
    auto t = makeRgba8(mem, {TextureTarget::Texture2D, TexelFormat::RGBA8, 4, 4, 1, 1, 1},
                       [](int, int, int, int, int, int) { return Rgba8{1, 2, 3, 4}; });
    raster::Device dev(o2, 8, 8, raster::DepthFormat::None);
    dev.textureUnits().setTexture(0, t);
    dev.textureUnits().setPixelTexture({true, PixelTexGenMode::Rgb, 0});
    std::vector<Rgba8> px(4, Rgba8{9, 9, 9, 9});
    try {
        dev.drawPixels(0, 0, 2, 2, px);
        ADD_FAILURE() << "sgi-o2 ran a pixel-texture lookup";
    } catch (const UnsupportedFeature& e) {
        EXPECT_NE(std::string(e.what()).find("sgi-o2"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("pixel texture"), std::string::npos) << e.what();
    }
}

}  // namespace
}  // namespace rg::tex
