// Float blending of the geforce8800 output merger against the rule written down in
// docs/hardware.md ("Programmable profile", "Output merger"), every source factor × every
// destination factor × every operation on chosen values (issue 24: until now only ONE/ONE
// was checked against real numbers). The values are dyadic rationals, so every product and
// sum is exact in binary32 and the expected result is computed here in double and compared
// with ==: this oracle is the Direct3D 10 definition, not the code under test.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <vector>

#include "core/error.h"
#include "core/profile.h"
#include "rasterizer/programmable_device.h"

namespace rg::raster {
namespace {

struct V {
    glm::vec4 clip;
};
struct CoverVP {
    static constexpr int kVaryings = 0;
    glm::vec4 operator()(const V& v, Varyings&) const { return v.clip; }
};
struct ConstantFP {  // writes one colour everywhere
    static constexpr int kVaryings = 0;
    static constexpr uint32_t kTargets = 1;
    static constexpr uint32_t kUnits = 0;
    static constexpr bool kWritesDepth = false;
    glm::vec4 colour;
    void operator()(FragmentContext& f) const { f.output(0, colour); }
};

// The factor per Direct3D 10 (D3D10_BLEND) for channel c of source s and destination d.
double factor(BlendFactor f, int c, const glm::dvec4& s, const glm::dvec4& d) {
    switch (f) {
        case BlendFactor::Zero: return 0;
        case BlendFactor::One: return 1;
        case BlendFactor::SrcColor: return s[c];
        case BlendFactor::InvSrcColor: return 1 - s[c];
        case BlendFactor::SrcAlpha: return s.w;
        case BlendFactor::InvSrcAlpha: return 1 - s.w;
        case BlendFactor::DestAlpha: return d.w;
        case BlendFactor::InvDestAlpha: return 1 - d.w;
        case BlendFactor::DestColor: return d[c];
        case BlendFactor::InvDestColor: return 1 - d[c];
        case BlendFactor::SrcAlphaSat: return c == 3 ? 1 : std::min(s.w, 1 - d.w);  // (f, f, f, 1)
        case BlendFactor::BothSrcAlpha: return s.w;
        case BlendFactor::BothInvSrcAlpha: return 1 - s.w;
    }
    return -1e300;
}

TEST(ProgrammableBlendOracle, EveryFactorPairAndOperationOnExactValues) {
    const Profile& g80 = profile(ProfileId::GeForce8800);
    tex::TextureMemory memory(g80);
    tex::TextureDesc d;
    d.format = tex::TexelFormat::RGBA32F;
    d.width = d.height = 2;
    auto target = memory.createRenderTarget(d);
    ProgrammableDevice dev(g80, DeviceOptions{Path::Fast, 1});
    ColorTarget ct{target};
    dev.setRenderTargets({&ct, 1});
    const std::vector<V> cover = {{{-1, 1, 0.5f, 1}}, {{3, 1, 0.5f, 1}}, {{-1, -3, 0.5f, 1}}};
    // Dyadic values beyond [0, 1] and negative: float blending is unclamped.
    const glm::vec4 src(0.25f, 1.5f, -0.5f, 0.75f), dst(0.5f, 0.125f, 2.0f, 0.375f);
    const glm::dvec4 s(src), dd(dst);
    const BlendFactor factors[] = {BlendFactor::Zero,        BlendFactor::One,         BlendFactor::SrcColor,
                                   BlendFactor::InvSrcColor, BlendFactor::SrcAlpha,    BlendFactor::InvSrcAlpha,
                                   BlendFactor::DestAlpha,   BlendFactor::InvDestAlpha, BlendFactor::DestColor,
                                   BlendFactor::InvDestColor, BlendFactor::SrcAlphaSat, BlendFactor::BothSrcAlpha,
                                   BlendFactor::BothInvSrcAlpha};
    const BlendOp ops[] = {BlendOp::Add, BlendOp::Subtract, BlendOp::RevSubtract, BlendOp::Min, BlendOp::Max};
    int checked = 0, refused = 0;
    for (BlendFactor sf : factors)
        for (BlendFactor df : factors)
            for (BlendOp op : ops) {
                ProgramState st;
                st.blend[0].enable = 1;
                st.blend[0].src = sf;
                st.blend[0].dst = df;
                st.blend[0].op = op;
                dev.clearColor(0, dst);
                const bool bothAsDest = df == BlendFactor::BothSrcAlpha || df == BlendFactor::BothInvSrcAlpha;
                if (bothAsDest) {
                    // BOTH* name the source factor and force the destination's (D3D9); as a
                    // destination factor they mean nothing and are refused, as the
                    // fixed-function blender refuses them.
                    EXPECT_THROW(dev.setState(st), Error);
                    ++refused;
                    continue;
                }
                dev.setState(st);
                dev.draw(CoverVP{}, ConstantFP{src}, ProgramPrimitive::TriangleList, std::span<const V>(cover));
                // BOTHSRCALPHA / BOTHINVSRCALPHA force the destination factor to INVSRCALPHA / SRCALPHA.
                const BlendFactor dEff = sf == BlendFactor::BothSrcAlpha      ? BlendFactor::InvSrcAlpha
                                         : sf == BlendFactor::BothInvSrcAlpha ? BlendFactor::SrcAlpha
                                                                              : df;
                const glm::vec4 got = target->renderDataF(0, 0)[0];
                for (int c = 0; c < 4; ++c) {
                    const double a = s[c] * factor(sf, c, s, dd), b = dd[c] * factor(dEff, c, s, dd);
                    double want = 0;
                    switch (op) {
                        case BlendOp::Add: want = a + b; break;
                        case BlendOp::Subtract: want = a - b; break;
                        case BlendOp::RevSubtract: want = b - a; break;
                        case BlendOp::Min: want = std::min(s[c], dd[c]); break;  // factors ignored
                        case BlendOp::Max: want = std::max(s[c], dd[c]); break;
                    }
                    ASSERT_EQ(double(got[c]), want) << "src " << int(sf) << " dst " << int(df) << " op " << int(op)
                                                    << " channel " << c;
                }
                ++checked;
            }
    EXPECT_EQ(checked, 13 * 11 * 5);
    EXPECT_EQ(refused, 13 * 2 * 5);
}

}  // namespace
}  // namespace rg::raster
