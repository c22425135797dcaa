// The texture-stage cascade's 8-bit arithmetic (docs/hardware.md, "Texture stages").
//
// Direct3D 7 defines each D3DTOP by a real-valued formula on [0, 1]; the GeForce 256's
// register-combiner rounding is not documented. We follow two rules, pinned in the docs:
// every product is rounded once, exactly (arith8::mulDiv255, the round(a·b/255) of the
// D3D reference rasterizer's float-then-round), and every sum saturates (arith8::addSat),
// as the combiners' clamped output mapping does. The 2× and 4× scales are the combiners'
// output shifts applied after the rounded product.
#include <array>
#include <string>

#include "core/arith8.h"
#include "core/error.h"
#include "texunit/stages.h"

namespace rg::tex {

using namespace rg::arith8;

std::string_view textureOpName(TextureOp op) {
    static constexpr std::array<std::string_view, size_t(TextureOp::Count)> names = {
        "DISABLE", "SELECTARG1", "SELECTARG2", "MODULATE", "MODULATE2X", "MODULATE4X", "ADD",
        "ADDSIGNED", "ADDSIGNED2X", "SUBTRACT", "ADDSMOOTH", "BLENDDIFFUSEALPHA",
        "BLENDTEXTUREALPHA", "BLENDFACTORALPHA", "BLENDTEXTUREALPHAPM", "BLENDCURRENTALPHA",
        "PREMODULATE", "MODULATEALPHA_ADDCOLOR", "MODULATECOLOR_ADDALPHA",
        "MODULATEINVALPHA_ADDCOLOR", "MODULATEINVCOLOR_ADDALPHA", "DOTPRODUCT3", "LERP"};
    return names.at(size_t(op));
}

uint8_t lerp255(uint8_t a, uint8_t b, uint8_t w) {
    // a·w + b·(255 − w) ≤ 255·255, the range in which Blinn's divide-by-255 is exact.
    uint32_t t = uint32_t(a) * w + uint32_t(b) * (255u - w) + 128u;
    return uint8_t((t + (t >> 8)) >> 8);
}

uint8_t dotProduct3(Rgba8 a, Rgba8 b) {
    // 4·Σ(a−½)(b−½) = Σ(2a−1)(2b−1); in 8 bits Σ(2a−255)(2b−255)/255², times 255.
    // s/255 is never a half-integer (255 is odd), so ⌊(s + 127)/255⌋ rounds exactly.
    int32_t s = (2 * a.r - 255) * (2 * b.r - 255) + (2 * a.g - 255) * (2 * b.g - 255) +
                (2 * a.b - 255) * (2 * b.b - 255);
    if (s <= 0) return 0;
    return uint8_t(std::min<int32_t>(255, (s + 127) / 255));
}

uint8_t combineChannel(TextureOp op, uint8_t a1, uint8_t a2, uint8_t a0, uint8_t alpha) {
    switch (op) {
        case TextureOp::SelectArg1: return a1;
        case TextureOp::SelectArg2: return a2;
        case TextureOp::Modulate: return uint8_t(mulDiv255(a1, a2));
        case TextureOp::Modulate2x: return uint8_t(std::min(mulDiv255(a1, a2) << 1, 255u));
        case TextureOp::Modulate4x: return uint8_t(std::min(mulDiv255(a1, a2) << 2, 255u));
        case TextureOp::Add: return uint8_t(addSat(a1, a2));
        case TextureOp::AddSigned: return uint8_t(clamp255(int32_t(a1) + a2 - 128));
        case TextureOp::AddSigned2x: return uint8_t(clamp255(2 * (int32_t(a1) + a2 - 128)));
        case TextureOp::Subtract: return uint8_t(subSat(a1, a2));
        case TextureOp::AddSmooth: return uint8_t(a1 + mulDiv255(a2, 255u - a1));
        case TextureOp::BlendDiffuseAlpha:
        case TextureOp::BlendTextureAlpha:
        case TextureOp::BlendFactorAlpha:
        case TextureOp::BlendCurrentAlpha: return lerp255(a1, a2, alpha);
        case TextureOp::BlendTextureAlphaPM: return uint8_t(addSat(a1, mulDiv255(a2, 255u - alpha)));
        case TextureOp::Lerp: return lerp255(a1, a2, a0);
        default: return a1;
    }
}

Rgba8 selectArg(uint8_t a, const StageInputs& in) {
    Rgba8 v;
    switch (a & arg::SourceMask) {
        case arg::Diffuse: v = in.diffuse; break;
        case arg::Current: v = in.current; break;
        case arg::Texture: v = in.texture; break;
        case arg::TFactor: v = in.tfactor; break;
        case arg::Specular: v = in.specular; break;
        default: v = in.current; break;
    }
    if (a & arg::AlphaReplicate) v = {v.a, v.a, v.a, v.a};
    if (a & arg::Complement)
        v = {uint8_t(255 - v.r), uint8_t(255 - v.g), uint8_t(255 - v.b), uint8_t(255 - v.a)};
    return v;
}

namespace {

uint8_t blendAlphaFor(TextureOp op, const StageInputs& in) {
    switch (op) {
        case TextureOp::BlendDiffuseAlpha: return in.diffuse.a;
        case TextureOp::BlendTextureAlpha:
        case TextureOp::BlendTextureAlphaPM: return in.texture.a;
        case TextureOp::BlendFactorAlpha: return in.tfactor.a;
        case TextureOp::BlendCurrentAlpha: return in.current.a;
        default: return 0;
    }
}

uint8_t scale(uint8_t v, uint8_t shift) {
    return shift == 0 ? v : uint8_t(std::min(uint32_t(v) << shift, 255u));
}

}  // namespace

Rgba8 evaluateStage(const StageState& st, const StageInputs& in) {
    Rgba8 out = in.current;
    // ---- colour ----------------------------------------------------------------------
    const Rgba8 c1 = selectArg(st.colorArg1, in), c2 = selectArg(st.colorArg2, in);
    bool dot3 = false;
    switch (st.colorOp) {
        case TextureOp::Disable:
        case TextureOp::PreModulate: break;  // colour passes; the texture premultiplies the next stage's
        case TextureOp::ModulateAlphaAddColor:
            out.r = uint8_t(addSat(c1.r, mulDiv255(c1.a, c2.r)));
            out.g = uint8_t(addSat(c1.g, mulDiv255(c1.a, c2.g)));
            out.b = uint8_t(addSat(c1.b, mulDiv255(c1.a, c2.b)));
            break;
        case TextureOp::ModulateColorAddAlpha:
            out.r = uint8_t(addSat(mulDiv255(c1.r, c2.r), c1.a));
            out.g = uint8_t(addSat(mulDiv255(c1.g, c2.g), c1.a));
            out.b = uint8_t(addSat(mulDiv255(c1.b, c2.b), c1.a));
            break;
        case TextureOp::ModulateInvAlphaAddColor:
            out.r = uint8_t(addSat(c1.r, mulDiv255(255u - c1.a, c2.r)));
            out.g = uint8_t(addSat(c1.g, mulDiv255(255u - c1.a, c2.g)));
            out.b = uint8_t(addSat(c1.b, mulDiv255(255u - c1.a, c2.b)));
            break;
        case TextureOp::ModulateInvColorAddAlpha:
            out.r = uint8_t(addSat(mulDiv255(255u - c1.r, c2.r), c1.a));
            out.g = uint8_t(addSat(mulDiv255(255u - c1.g, c2.g), c1.a));
            out.b = uint8_t(addSat(mulDiv255(255u - c1.b, c2.b), c1.a));
            break;
        case TextureOp::DotProduct3: {
            // Direct3D 7: the dot product is replicated to all four channels, alpha too,
            // whatever ALPHAOP says.
            uint8_t d = dotProduct3(c1, c2);
            out = {d, d, d, d};
            dot3 = true;
            break;
        }
        default: {
            const Rgba8 c0 = selectArg(st.colorArg0, in);
            const uint8_t ba = blendAlphaFor(st.colorOp, in);
            out.r = combineChannel(st.colorOp, c1.r, c2.r, c0.r, ba);
            out.g = combineChannel(st.colorOp, c1.g, c2.g, c0.g, ba);
            out.b = combineChannel(st.colorOp, c1.b, c2.b, c0.b, ba);
            break;
        }
    }
    out.r = scale(out.r, st.colorScaleShift);
    out.g = scale(out.g, st.colorScaleShift);
    out.b = scale(out.b, st.colorScaleShift);
    if (dot3) return out;

    // ---- alpha -----------------------------------------------------------------------
    // ALPHAOP DISABLE with COLOROP enabled keeps the current alpha (D3D7 leaves it open).
    switch (st.alphaOp) {
        case TextureOp::Disable:
        case TextureOp::PreModulate: out.a = in.current.a; break;
        case TextureOp::DotProduct3: {
            const Rgba8 a1 = selectArg(st.alphaArg1, in), a2 = selectArg(st.alphaArg2, in);
            out.a = dotProduct3(a1, a2);
            break;
        }
        default: {
            const uint8_t a1 = selectArg(st.alphaArg1, in).a, a2 = selectArg(st.alphaArg2, in).a;
            const uint8_t a0 = selectArg(st.alphaArg0, in).a;
            out.a = combineChannel(st.alphaOp, a1, a2, a0, blendAlphaFor(st.alphaOp, in));
            break;
        }
    }
    out.a = scale(out.a, st.alphaScaleShift);
    return out;
}

// ---- OpenGL environments -------------------------------------------------------------

namespace {
StageState select(uint8_t colorArg, uint8_t alphaArg, uint8_t set) {
    StageState s;
    s.colorOp = TextureOp::SelectArg1;
    s.colorArg1 = colorArg;
    s.alphaOp = TextureOp::SelectArg1;
    s.alphaArg1 = alphaArg;
    s.texCoordIndex = set;
    return s;
}
}  // namespace

StageState texEnvStage(TexEnvMode mode, BaseFormat base, uint8_t set) {
    const bool col = hasColor(base), alp = hasAlpha(base);
    StageState s = select(arg::Current, arg::Current, set);
    s.colorArg2 = arg::Current;
    s.alphaArg2 = arg::Current;
    switch (mode) {
        case TexEnvMode::Replace:  // C = Ct (or Cf), A = At (or Af)
            if (col) s.colorArg1 = arg::Texture;
            if (alp) s.alphaArg1 = arg::Texture;
            break;
        case TexEnvMode::Modulate:  // C = Cf·Ct, A = Af·At
            if (col) { s.colorOp = TextureOp::Modulate; s.colorArg1 = arg::Texture; }
            if (alp) { s.alphaOp = TextureOp::Modulate; s.alphaArg1 = arg::Texture; }
            break;
        case TexEnvMode::Decal:  // RGB: C = Ct; RGBA: C = Cf(1−At) + Ct·At; A = Af
            if (base == BaseFormat::Rgb) {
                s.colorArg1 = arg::Texture;
            } else if (base == BaseFormat::Rgba) {
                s.colorOp = TextureOp::BlendTextureAlpha;
                s.colorArg1 = arg::Texture;
            } else {
                throw InvalidState("GL_DECAL is undefined for base format " +
                                   std::string(baseFormatName(base)));
            }
            break;
        case TexEnvMode::Blend:  // C = Cf(1−Ct) + Cc·Ct; A: LA/A/RGBA Af·At, I like C
            if (col) {
                s.colorOp = TextureOp::Lerp;
                s.colorArg1 = arg::TFactor;
                s.colorArg2 = arg::Current;
                s.colorArg0 = arg::Texture;
            }
            if (base == BaseFormat::Intensity) {
                s.alphaOp = TextureOp::Lerp;
                s.alphaArg1 = arg::TFactor;
                s.alphaArg2 = arg::Current;
                s.alphaArg0 = arg::Texture;
            } else if (alp) {
                s.alphaOp = TextureOp::Modulate;
                s.alphaArg1 = arg::Texture;
            }
            break;
        case TexEnvMode::Add:  // EXT_texture_env_add: C = Cf + Ct; A = Af·At, I: Af + At
            if (col) { s.colorOp = TextureOp::Add; s.colorArg1 = arg::Texture; }
            if (base == BaseFormat::Intensity) {
                s.alphaOp = TextureOp::Add;
                s.alphaArg1 = arg::Texture;
            } else if (alp) {
                s.alphaOp = TextureOp::Modulate;
                s.alphaArg1 = arg::Texture;
            }
            break;
    }
    return s;
}

namespace {
uint8_t combineArg(CombineSource src, CombineOperand op) {
    uint8_t a = 0;
    switch (src) {
        case CombineSource::Texture: a = arg::Texture; break;
        case CombineSource::Constant: a = arg::TFactor; break;
        case CombineSource::PrimaryColor: a = arg::Diffuse; break;
        case CombineSource::Previous: a = arg::Current; break;
    }
    switch (op) {
        case CombineOperand::SrcColor: break;
        case CombineOperand::OneMinusSrcColor: a |= arg::Complement; break;
        case CombineOperand::SrcAlpha: a |= arg::AlphaReplicate; break;
        case CombineOperand::OneMinusSrcAlpha: a |= arg::AlphaReplicate | arg::Complement; break;
    }
    return a;
}
TextureOp combineOp(CombineFunc f) {
    switch (f) {
        case CombineFunc::Replace: return TextureOp::SelectArg1;
        case CombineFunc::Modulate: return TextureOp::Modulate;
        case CombineFunc::Add: return TextureOp::Add;
        case CombineFunc::AddSigned: return TextureOp::AddSigned;
        case CombineFunc::Interpolate: return TextureOp::Lerp;
        case CombineFunc::Subtract: return TextureOp::Subtract;
    }
    return TextureOp::SelectArg1;
}
uint8_t scaleShift(int scale) {
    if (scale == 1) return 0;
    if (scale == 2) return 1;
    if (scale == 4) return 2;
    throw InvalidState("combine scale " + std::to_string(scale) + " is not 1, 2 or 4");
}
}  // namespace

StageState combineStage(const CombineChannel& rgb, const CombineChannel& alpha, uint8_t set) {
    StageState s;
    // INTERPOLATE = Arg0·Arg2 + Arg1·(1 − Arg2) → Lerp(arg1 = Arg0, arg2 = Arg1, weight Arg2).
    s.colorOp = combineOp(rgb.func);
    s.colorArg1 = combineArg(rgb.source[0], rgb.operand[0]);
    s.colorArg2 = combineArg(rgb.source[1], rgb.operand[1]);
    s.colorArg0 = combineArg(rgb.source[2], rgb.operand[2]);
    s.alphaOp = combineOp(alpha.func);
    s.alphaArg1 = combineArg(alpha.source[0], alpha.operand[0]);
    s.alphaArg2 = combineArg(alpha.source[1], alpha.operand[1]);
    s.alphaArg0 = combineArg(alpha.source[2], alpha.operand[2]);
    s.colorScaleShift = scaleShift(rgb.scale);
    s.alphaScaleShift = scaleShift(alpha.scale);
    s.texCoordIndex = set;
    return s;
}

}  // namespace rg::tex
