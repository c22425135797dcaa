// The texture-stage cascade's 8-bit arithmetic (docs/hardware.md, "Texture stages").
//
// Direct3D 7 defines each D3DTOP by a real-valued formula on [0, 1]; the GeForce 256's
// register-combiner rounding is not documented. We follow two rules, pinned in the docs:
// every product is rounded once, exactly (arith8::mulDiv255 = round(a·b/255), so each op is
// its real formula rounded to 8 bits, with the blender's multiply), and every sum
// saturates (arith8::addSat), as the combiners' clamped output mapping does. The 2× and 4× scales are the combiners'
// output shifts applied after the rounded product.
#include <array>
#include <string>

#include "core/arith8.h"
#include "core/error.h"
#include "stage_arith.h"
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

uint8_t lerp255(uint8_t a, uint8_t b, uint8_t w) { return detail::lerp255(a, b, w); }
uint8_t dotProduct3(Rgba8 a, Rgba8 b) { return detail::dotProduct3(a, b); }
uint8_t combineChannel(TextureOp op, uint8_t a1, uint8_t a2, uint8_t a0, uint8_t alpha) {
    return detail::combineChannel(op, a1, a2, a0, alpha);
}
Rgba8 selectArg(uint8_t a, const StageInputs& in) { return detail::selectArg(a, in); }
Rgba8 evaluateStage(const StageState& st, const StageInputs& in) {
    return detail::evaluateStage(st, in);
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
