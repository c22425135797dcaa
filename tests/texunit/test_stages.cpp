// The texture-stage arithmetic: every op on edge values, exhaustively against its
// one-line definition, the argument modifiers, and the OpenGL environments on the same
// machinery (docs/hardware.md, "Texture stages").
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "tex_test_util.h"
#include "texunit/stages.h"

namespace rg::tex {
namespace {

int rnd(double x) { return int(std::floor(x + 0.5)); }
int sat(int x) { return std::clamp(x, 0, 255); }

// One-line definitions on real numbers, rounded once to 8 bits (docs/hardware.md).
int definition(TextureOp op, int a, int b, int w) {
    switch (op) {
        case TextureOp::SelectArg1: return a;
        case TextureOp::SelectArg2: return b;
        case TextureOp::Modulate: return rnd(a * b / 255.0);
        case TextureOp::Modulate2x: return sat(2 * rnd(a * b / 255.0));
        case TextureOp::Modulate4x: return sat(4 * rnd(a * b / 255.0));
        case TextureOp::Add: return sat(a + b);
        case TextureOp::AddSigned: return sat(a + b - 128);
        case TextureOp::AddSigned2x: return sat(2 * (a + b - 128));
        case TextureOp::Subtract: return sat(a - b);
        case TextureOp::AddSmooth: return rnd(a + b - a * b / 255.0);
        case TextureOp::BlendDiffuseAlpha:
        case TextureOp::BlendTextureAlpha:
        case TextureOp::BlendFactorAlpha:
        case TextureOp::BlendCurrentAlpha: return rnd((a * w + b * (255.0 - w)) / 255.0);
        case TextureOp::BlendTextureAlphaPM: return sat(a + rnd(b * (255.0 - w) / 255.0));
        case TextureOp::Lerp: return rnd((a * w + b * (255.0 - w)) / 255.0);
        default: return -1;
    }
}

const TextureOp kChannelOps[] = {
    TextureOp::SelectArg1,        TextureOp::SelectArg2,        TextureOp::Modulate,
    TextureOp::Modulate2x,        TextureOp::Modulate4x,        TextureOp::Add,
    TextureOp::AddSigned,         TextureOp::AddSigned2x,       TextureOp::Subtract,
    TextureOp::AddSmooth,         TextureOp::BlendDiffuseAlpha, TextureOp::BlendTextureAlpha,
    TextureOp::BlendFactorAlpha,  TextureOp::BlendTextureAlphaPM, TextureOp::BlendCurrentAlpha,
    TextureOp::Lerp};

TEST(StageOps, EdgeValues) {
    struct Row { TextureOp op; int a, b, w, expect; };
    const Row rows[] = {
        {TextureOp::Modulate, 0, 255, 0, 0},        {TextureOp::Modulate, 255, 255, 0, 255},
        {TextureOp::Modulate, 128, 128, 0, 64},     {TextureOp::Modulate, 128, 255, 0, 128},
        {TextureOp::Modulate2x, 128, 128, 0, 128},  {TextureOp::Modulate2x, 255, 255, 0, 255},
        {TextureOp::Modulate4x, 128, 128, 0, 255},  {TextureOp::Modulate4x, 64, 255, 0, 255},
        {TextureOp::Modulate4x, 0, 255, 0, 0},      {TextureOp::Add, 128, 128, 0, 255},
        {TextureOp::Add, 128, 0, 0, 128},           {TextureOp::AddSigned, 128, 128, 0, 128},
        {TextureOp::AddSigned, 0, 0, 0, 0},         {TextureOp::AddSigned, 255, 255, 0, 255},
        {TextureOp::AddSigned, 0, 128, 0, 0},       {TextureOp::AddSigned2x, 128, 128, 0, 255},
        {TextureOp::AddSigned2x, 128, 0, 0, 0},     {TextureOp::AddSigned2x, 64, 128, 0, 128},
        {TextureOp::Subtract, 128, 255, 0, 0},      {TextureOp::Subtract, 255, 128, 0, 127},
        {TextureOp::AddSmooth, 128, 128, 0, 192},   {TextureOp::AddSmooth, 255, 255, 0, 255},
        {TextureOp::AddSmooth, 0, 128, 0, 128},     {TextureOp::BlendTextureAlpha, 255, 0, 128, 128},
        {TextureOp::BlendTextureAlpha, 255, 0, 0, 0}, {TextureOp::BlendTextureAlpha, 255, 0, 255, 255},
        {TextureOp::BlendTextureAlphaPM, 128, 255, 128, 255}, {TextureOp::BlendTextureAlphaPM, 0, 128, 255, 0},
        {TextureOp::Lerp, 0, 255, 128, 127},        {TextureOp::SelectArg2, 1, 2, 0, 2},
    };
    for (const Row& r : rows)
        EXPECT_EQ(combineChannel(r.op, uint8_t(r.a), uint8_t(r.b), uint8_t(r.w), uint8_t(r.w)), r.expect)
            << textureOpName(r.op) << "(" << r.a << ", " << r.b << ", w=" << r.w << ")";
}

TEST(StageOps, Exhaustive65536PairsAgainstDefinition) {
    const int weights[] = {0, 1, 127, 128, 254, 255};
    for (TextureOp op : kChannelOps)
        for (int w : weights)
            for (int a = 0; a < 256; ++a)
                for (int b = 0; b < 256; ++b)
                    ASSERT_EQ(combineChannel(op, uint8_t(a), uint8_t(b), uint8_t(w), uint8_t(w)),
                              definition(op, a, b, w))
                        << textureOpName(op) << "(" << a << ", " << b << ", w=" << w << ")";
}

TEST(StageOps, Lerp255ExactOverAllTriples) {
    for (int w = 0; w < 256; ++w)
        for (int a = 0; a < 256; ++a)
            for (int b = 0; b < 256; ++b)
                ASSERT_EQ(lerp255(uint8_t(a), uint8_t(b), uint8_t(w)),
                          rnd((a * w + b * (255.0 - w)) / 255.0))
                    << a << " " << b << " " << w;
}

TEST(StageOps, DotProduct3) {
    auto def = [](Rgba8 a, Rgba8 b) {
        double s = 0;
        for (int i = 0; i < 3; ++i) {
            double x = (&a.r)[i] / 255.0 - 0.5, y = (&b.r)[i] / 255.0 - 0.5;
            s += x * y;
        }
        return sat(rnd(255.0 * 4.0 * s));
    };
    EXPECT_EQ(dotProduct3({255, 255, 255, 0}, {255, 255, 255, 0}), 255);
    EXPECT_EQ(dotProduct3({128, 128, 128, 0}, {255, 255, 255, 0}), 3);
    EXPECT_EQ(dotProduct3({0, 0, 0, 0}, {255, 255, 255, 0}), 0);
    EXPECT_EQ(dotProduct3({0, 0, 0, 0}, {0, 0, 0, 0}), 255);
    EXPECT_EQ(dotProduct3({255, 128, 128, 0}, {255, 128, 128, 0}), 255);  // +x normal · itself
    for (int a = 0; a < 256; ++a)
        for (int b = 0; b < 256; ++b) {
            Rgba8 x{uint8_t(a), uint8_t(b), uint8_t(255 - a), 0}, y{uint8_t(b), uint8_t(a), 128, 0};
            ASSERT_EQ(dotProduct3(x, y), def(x, y)) << a << " " << b;
        }
}

// The four ops that mix colour and alpha, on every (x, y) pair: arg1 = DIFFUSE =
// (x, 255 − x, 128, y), arg2 = TEXTURE = (y, x, 255, 0); per channel against
//   MODULATEALPHA_ADDCOLOR     a1 + a1.a·a2
//   MODULATECOLOR_ADDALPHA     a1·a2 + a1.a
//   MODULATEINVALPHA_ADDCOLOR  a1 + (1 − a1.a)·a2
//   MODULATEINVCOLOR_ADDALPHA  (1 − a1)·a2 + a1.a
// each product rounded once, the sum saturated.
TEST(StageOps, ColourAlphaMixOpsExhaustive65536Pairs) {
    auto m = [](int a, int b) { return rnd(a * b / 255.0); };
    const TextureOp ops[] = {TextureOp::ModulateAlphaAddColor, TextureOp::ModulateColorAddAlpha,
                             TextureOp::ModulateInvAlphaAddColor, TextureOp::ModulateInvColorAddAlpha};
    for (TextureOp op : ops) {
        StageState st;
        st.colorOp = op;
        st.colorArg1 = arg::Diffuse;
        st.colorArg2 = arg::Texture;
        st.alphaOp = TextureOp::SelectArg1;
        st.alphaArg1 = arg::Diffuse;
        for (int x = 0; x < 256; ++x)
            for (int y = 0; y < 256; ++y) {
                const Rgba8 a1{uint8_t(x), uint8_t(255 - x), 128, uint8_t(y)};
                const Rgba8 a2{uint8_t(y), uint8_t(x), 255, 0};
                const Rgba8 o = evaluateStage(st, {a1, {}, {}, a2, {}});
                for (int c = 0; c < 3; ++c) {
                    const int u = (&a1.r)[c], v = (&a2.r)[c], al = a1.a;
                    int expect = 0;
                    switch (op) {
                        case TextureOp::ModulateAlphaAddColor: expect = sat(u + m(al, v)); break;
                        case TextureOp::ModulateColorAddAlpha: expect = sat(m(u, v) + al); break;
                        case TextureOp::ModulateInvAlphaAddColor: expect = sat(u + m(255 - al, v)); break;
                        default: expect = sat(m(255 - u, v) + al); break;
                    }
                    ASSERT_EQ((&o.r)[c], expect) << textureOpName(op) << " x=" << x << " y=" << y << " c=" << c;
                }
                ASSERT_EQ(o.a, y);
            }
    }
}

TEST(StageOps, ColourAlphaMixOpsAndDot3OnEdgeValues) {
    // arg1 = DIFFUSE, arg2 = TEXTURE; one channel shown (all three are equal here).
    struct Row { TextureOp op; uint8_t c1, a1, c2, expect; };
    const Row rows[] = {
        {TextureOp::ModulateAlphaAddColor, 128, 128, 128, 192},     // 128 + 64
        {TextureOp::ModulateAlphaAddColor, 255, 255, 255, 255},
        {TextureOp::ModulateAlphaAddColor, 0, 0, 255, 0},
        {TextureOp::ModulateColorAddAlpha, 128, 128, 128, 192},     // 64 + 128
        {TextureOp::ModulateColorAddAlpha, 0, 255, 0, 255},
        {TextureOp::ModulateInvAlphaAddColor, 128, 128, 255, 255},  // 128 + 127
        {TextureOp::ModulateInvAlphaAddColor, 0, 255, 255, 0},
        {TextureOp::ModulateInvColorAddAlpha, 128, 0, 255, 127},
        {TextureOp::ModulateInvColorAddAlpha, 255, 128, 255, 128},
        {TextureOp::DotProduct3, 255, 0, 255, 255},
        {TextureOp::DotProduct3, 128, 0, 255, 3},
        {TextureOp::DotProduct3, 0, 0, 255, 0},
    };
    for (const Row& r : rows) {
        StageState st;
        st.colorOp = r.op;
        st.colorArg1 = arg::Diffuse;
        st.colorArg2 = arg::Texture;
        st.alphaOp = TextureOp::SelectArg1;
        st.alphaArg1 = arg::Diffuse;
        const Rgba8 o = evaluateStage(st, {{r.c1, r.c1, r.c1, r.a1}, {}, {}, {r.c2, r.c2, r.c2, 77}, {}});
        EXPECT_EQ(o.r, r.expect) << textureOpName(r.op);
        EXPECT_EQ(o.b, r.expect) << textureOpName(r.op);
    }
}

StageInputs inputs() {
    return {{200, 100, 50, 128}, {1, 2, 3, 4}, {10, 20, 30, 40}, {255, 128, 0, 64}, {9, 8, 7, 6}};
}

TEST(StageArgs, SourcesAndModifiers) {
    StageInputs in = inputs();
    EXPECT_EQ(selectArg(arg::Diffuse, in), in.diffuse);
    EXPECT_EQ(selectArg(arg::Current, in), in.current);
    EXPECT_EQ(selectArg(arg::Texture, in), in.texture);
    EXPECT_EQ(selectArg(arg::TFactor, in), in.tfactor);
    EXPECT_EQ(selectArg(arg::Specular, in), in.specular);
    EXPECT_EQ(selectArg(arg::Current | arg::Complement, in), (Rgba8{245, 235, 225, 215}));
    EXPECT_EQ(selectArg(arg::Current | arg::AlphaReplicate, in), (Rgba8{40, 40, 40, 40}));
    EXPECT_EQ(selectArg(arg::Current | arg::AlphaReplicate | arg::Complement, in),
              (Rgba8{215, 215, 215, 215}));
}

TEST(StageEvaluate, ColourAndAlphaOpsTogether) {
    StageInputs in = inputs();
    StageState s;
    s.colorOp = TextureOp::Modulate;  // TEXTURE × CURRENT
    s.alphaOp = TextureOp::SelectArg1;
    EXPECT_EQ(evaluateStage(s, in), (Rgba8{10, 10, 0, 64}));
    // Blend*Alpha weight by their named alpha: texture (64), diffuse (128), factor (6), current (40).
    s.colorArg1 = arg::Diffuse;
    s.colorArg2 = arg::Current;
    s.colorOp = TextureOp::BlendTextureAlpha;
    EXPECT_EQ(evaluateStage(s, in).r, rnd((200 * 64 + 10 * 191) / 255.0));
    s.colorOp = TextureOp::BlendDiffuseAlpha;
    EXPECT_EQ(evaluateStage(s, in).r, rnd((200 * 128 + 10 * 127) / 255.0));
    s.colorOp = TextureOp::BlendFactorAlpha;
    EXPECT_EQ(evaluateStage(s, in).r, rnd((200 * 6 + 10 * 249) / 255.0));
    s.colorOp = TextureOp::BlendCurrentAlpha;
    EXPECT_EQ(evaluateStage(s, in).r, rnd((200 * 40 + 10 * 215) / 255.0));
    // The colour-and-alpha ops: arg1 = DIFFUSE (200,100,50 | 128), arg2 = TEXTURE.
    s.colorArg2 = arg::Texture;
    s.colorOp = TextureOp::ModulateAlphaAddColor;  // a1 + a1.a·a2
    EXPECT_EQ(evaluateStage(s, in), (Rgba8{255, uint8_t(100 + rnd(128 * 128 / 255.0)), 50, 64}));
    s.colorOp = TextureOp::ModulateColorAddAlpha;  // a1·a2 + a1.a
    EXPECT_EQ(evaluateStage(s, in), (Rgba8{255, uint8_t(rnd(100 * 128 / 255.0) + 128), 128, 64}));
    s.colorOp = TextureOp::ModulateInvAlphaAddColor;  // a1 + (1 − a1.a)·a2
    EXPECT_EQ(evaluateStage(s, in), (Rgba8{255, uint8_t(100 + rnd(127 * 128 / 255.0)), 50, 64}));
    s.colorOp = TextureOp::ModulateInvColorAddAlpha;  // (1 − a1)·a2 + a1.a
    EXPECT_EQ(evaluateStage(s, in),
              (Rgba8{uint8_t(rnd(55 * 255 / 255.0) + 128), uint8_t(rnd(155 * 128 / 255.0) + 128), 128, 64}));
    // DOTPRODUCT3 as a colour op writes alpha too.
    s.colorOp = TextureOp::DotProduct3;
    s.colorArg1 = arg::Texture;
    s.colorArg2 = arg::Texture;
    uint8_t d = dotProduct3(in.texture, in.texture);
    EXPECT_EQ(evaluateStage(s, in), (Rgba8{d, d, d, d}));
    // ALPHAOP DISABLE keeps the current alpha.
    s.colorOp = TextureOp::SelectArg1;
    s.alphaOp = TextureOp::Disable;
    EXPECT_EQ(evaluateStage(s, in).a, 40);
    // Combine's scale shifts saturate after the op.
    s.alphaOp = TextureOp::SelectArg1;
    s.colorScaleShift = 1;
    s.alphaScaleShift = 2;
    EXPECT_EQ(evaluateStage(s, in), (Rgba8{255, 255, 0, 255}));
}

// The alpha meanings docs/hardware.md pins where Direct3D 7 says nothing (docs/trace-format.md
// refers to them): ALPHAOP DISABLE and PREMODULATE pass CURRENT's alpha, and the alpha scale
// still applies to it; DOTPRODUCT3 as ALPHAOP is the dot product of the alpha arguments'
// RGB; DOTPRODUCT3 as COLOROP writes its result to alpha unscaled, whatever ALPHAOP and
// either scale say. Hand-computed from inputs(): CURRENT = (10, 20, 30 | 40).
TEST(StageEvaluate, PinnedAlphaMeaningsOfDisablePremodulateAndDotProduct3) {
    const StageInputs in = inputs();
    StageState s;
    s.colorOp = TextureOp::SelectArg1;
    s.colorArg1 = arg::Diffuse;
    for (TextureOp passes : {TextureOp::Disable, TextureOp::PreModulate}) {
        s.alphaOp = passes;
        s.alphaScaleShift = 0;
        EXPECT_EQ(evaluateStage(s, in), (Rgba8{200, 100, 50, 40})) << textureOpName(passes);
        s.alphaScaleShift = 1;
        EXPECT_EQ(evaluateStage(s, in).a, 80) << textureOpName(passes);
        s.alphaScaleShift = 2;
        EXPECT_EQ(evaluateStage(s, in).a, 160) << textureOpName(passes);
    }
    // DOTPRODUCT3 as ALPHAOP: DIFFUSE (200, 100, 50) · TEXTURE (255, 128, 0), both as
    // 2x − 255: 145·255 + (−55)·1 + (−155)·(−255) = 76,445, /255 = 299.8 → clamped 255;
    // with TFACTOR (9, 8, 7): (−237)(145) + (−239)(−55) + (−241)(−155) = 16,135 → 63.
    s.alphaScaleShift = 0;
    s.alphaOp = TextureOp::DotProduct3;
    s.alphaArg1 = arg::Diffuse;
    s.alphaArg2 = arg::Texture;
    EXPECT_EQ(evaluateStage(s, in), (Rgba8{200, 100, 50, 255}));
    s.alphaArg2 = arg::TFactor;
    EXPECT_EQ(evaluateStage(s, in).a, 63);
    // DOTPRODUCT3 as COLOROP: TFACTOR · DIFFUSE = 63 into r, g, b (scaled) and a (not).
    s.colorOp = TextureOp::DotProduct3;
    s.colorArg1 = arg::TFactor;
    s.colorArg2 = arg::Diffuse;
    s.alphaOp = TextureOp::SelectArg1;
    s.alphaArg1 = arg::Current;
    s.colorScaleShift = 1;
    s.alphaScaleShift = 2;
    EXPECT_EQ(evaluateStage(s, in), (Rgba8{126, 126, 126, 63}));
}

// OpenGL 1.2 Tables 3.18/3.19 written out independently (Cf current, Ct texture, Cc env).
Rgba8 glEnv(TexEnvMode mode, BaseFormat base, Rgba8 f, Rgba8 t, Rgba8 c) {
    auto mul = [](int a, int b) { return uint8_t(rnd(a * b / 255.0)); };
    auto mix = [](int cf, int cc, int ct) { return uint8_t(rnd((cf * (255.0 - ct) + cc * ct) / 255.0)); };
    Rgba8 o = f;
    const bool col = base != BaseFormat::Alpha;
    const bool alp = base == BaseFormat::Alpha || base == BaseFormat::LuminanceAlpha ||
                     base == BaseFormat::Intensity || base == BaseFormat::Rgba;
    for (int i = 0; i < 3; ++i) {
        uint8_t& oc = (&o.r)[i];
        int cf = (&f.r)[i], ct = (&t.r)[i], cc = (&c.r)[i];
        if (!col) continue;
        switch (mode) {
            case TexEnvMode::Replace: oc = uint8_t(ct); break;
            case TexEnvMode::Modulate: oc = mul(cf, ct); break;
            case TexEnvMode::Decal: oc = base == BaseFormat::Rgb ? uint8_t(ct) : mix(cf, ct, t.a); break;
            case TexEnvMode::Blend: oc = mix(cf, cc, ct); break;
            case TexEnvMode::Add: oc = uint8_t(std::min(255, cf + ct)); break;
        }
    }
    if (alp) {
        switch (mode) {
            case TexEnvMode::Replace: o.a = t.a; break;
            case TexEnvMode::Modulate: o.a = mul(f.a, t.a); break;
            case TexEnvMode::Decal: break;
            case TexEnvMode::Blend:
                o.a = base == BaseFormat::Intensity ? mix(f.a, c.a, t.a) : mul(f.a, t.a);
                break;
            case TexEnvMode::Add:
                o.a = base == BaseFormat::Intensity ? uint8_t(std::min(255, f.a + t.a)) : mul(f.a, t.a);
                break;
        }
    }
    return o;
}

TEST(TexEnv, OpenGLEnvironmentsPerBaseFormatMatchTheTables) {
    testing::Rng rng(99);
    const std::pair<TexelFormat, BaseFormat> formats[] = {
        {TexelFormat::A8, BaseFormat::Alpha},        {TexelFormat::L8, BaseFormat::Luminance},
        {TexelFormat::L8A8, BaseFormat::LuminanceAlpha}, {TexelFormat::I8, BaseFormat::Intensity},
        {TexelFormat::RGB8, BaseFormat::Rgb},        {TexelFormat::RGBA8, BaseFormat::Rgba}};
    for (auto [fmt, base] : formats)
        for (TexEnvMode mode : {TexEnvMode::Modulate, TexEnvMode::Replace, TexEnvMode::Decal,
                                TexEnvMode::Blend, TexEnvMode::Add}) {
            if (mode == TexEnvMode::Decal && base != BaseFormat::Rgb && base != BaseFormat::Rgba) {
                EXPECT_THROW(texEnvStage(mode, base), InvalidState);
                continue;
            }
            StageState st = texEnvStage(mode, base);
            for (int i = 0; i < 2000; ++i) {
                uint8_t raw[4] = {uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()),
                                  uint8_t(rng.next())};
                Rgba8 t = expandTexel8(fmt, raw);
                Rgba8 f{uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next())};
                Rgba8 c{uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next()), uint8_t(rng.next())};
                StageInputs in{f, {}, f, t, c};
                ASSERT_EQ(evaluateStage(st, in), glEnv(mode, base, f, t, c))
                    << "env " << int(mode) << " base " << baseFormatName(base);
            }
        }
}

TEST(TexEnv, CombineInterpolateAndScale) {
    CombineChannel rgb;
    rgb.func = CombineFunc::Interpolate;  // Arg0·Arg2 + Arg1·(1 − Arg2)
    rgb.source = {CombineSource::Texture, CombineSource::PrimaryColor, CombineSource::Constant};
    rgb.operand = {CombineOperand::SrcColor, CombineOperand::SrcColor, CombineOperand::SrcAlpha};
    CombineChannel alpha;
    alpha.func = CombineFunc::Subtract;
    alpha.source = {CombineSource::Texture, CombineSource::Previous, CombineSource::Constant};
    alpha.operand = {CombineOperand::SrcAlpha, CombineOperand::OneMinusSrcAlpha, CombineOperand::SrcAlpha};
    alpha.scale = 2;
    StageState st = combineStage(rgb, alpha);
    StageInputs in = inputs();  // texture (255,128,0,64), diffuse (200,100,50,128), tfactor a = 6
    Rgba8 o = evaluateStage(st, in);
    EXPECT_EQ(o.r, rnd((255 * 6 + 200 * 249) / 255.0));
    EXPECT_EQ(o.g, rnd((128 * 6 + 100 * 249) / 255.0));
    EXPECT_EQ(o.b, rnd((0 * 6 + 50 * 249) / 255.0));
    EXPECT_EQ(o.a, 0);  // 64 − (255 − 40) < 0 → 0, ×2 = 0
    alpha.operand[1] = CombineOperand::SrcAlpha;
    EXPECT_EQ(evaluateStage(combineStage(rgb, alpha), in).a, 48);  // (64 − 40)·2
    alpha.scale = 3;
    EXPECT_THROW(combineStage(rgb, alpha), InvalidState);
}

}  // namespace
}  // namespace rg::tex
