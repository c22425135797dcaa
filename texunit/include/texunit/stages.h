// The texture-stage cascade: Direct3D 7 COLOROP/ALPHAOP over 8-bit arguments, with the
// OpenGL texture environments expressed on the same machinery
// (docs/hardware.md, "Texture stages").
#pragma once

#include <array>
#include <cstdint>
#include <type_traits>

#include "core/color.h"
#include "texunit/format.h"

namespace rg::tex {

// D3DTEXTUREOP (Direct3D 7, same order) plus Lerp (D3DTOP_LERP of Direct3D 8, which is
// ARB_texture_env_combine's INTERPOLATE and the engine of GL's BLEND environment).
enum class TextureOp : uint8_t {
    Disable, SelectArg1, SelectArg2, Modulate, Modulate2x, Modulate4x, Add, AddSigned,
    AddSigned2x, Subtract, AddSmooth, BlendDiffuseAlpha, BlendTextureAlpha, BlendFactorAlpha,
    BlendTextureAlphaPM, BlendCurrentAlpha, PreModulate, ModulateAlphaAddColor,
    ModulateColorAddAlpha, ModulateInvAlphaAddColor, ModulateInvColorAddAlpha, DotProduct3,
    Lerp, Count
};
std::string_view textureOpName(TextureOp op);
// The ops Direct3D 7 defines for colour only (D3DTOP_MODULATEALPHA_ADDCOLOR and the other
// MODULATE…ADD… ops): their formulas mix a colour with an alpha, so as ALPHAOP they mean
// nothing. TextureUnits::setStage refuses them there, and so does the trace reader.
constexpr bool colourOnlyOp(TextureOp op) {
    return op == TextureOp::ModulateAlphaAddColor || op == TextureOp::ModulateColorAddAlpha ||
           op == TextureOp::ModulateInvAlphaAddColor || op == TextureOp::ModulateInvColorAddAlpha;
}

// D3DTA_* values exactly: a source in the low bits, modifier flags above.
namespace arg {
constexpr uint8_t Diffuse = 0, Current = 1, Texture = 2, TFactor = 3, Specular = 4;
constexpr uint8_t SourceMask = 0x0f;
constexpr uint8_t Complement = 0x10;      // D3DTA_COMPLEMENT: 255 − x
constexpr uint8_t AlphaReplicate = 0x20;  // D3DTA_ALPHAREPLICATE: a into r, g, b
}  // namespace arg

// One stage (D3DTSS_*). Defaults are the Direct3D 7 defaults of stages 1..7; stage 0
// also starts disabled here (see TextureUnits).
struct StageState {
    TextureOp colorOp = TextureOp::Disable;
    uint8_t colorArg1 = arg::Texture, colorArg2 = arg::Current;
    uint8_t colorArg0 = arg::Current;  // third argument of Lerp (the weight)
    TextureOp alphaOp = TextureOp::Disable;
    uint8_t alphaArg1 = arg::Texture, alphaArg2 = arg::Current;
    uint8_t alphaArg0 = arg::Current;
    uint8_t texCoordIndex = 0;         // D3DTSS_TEXCOORDINDEX (the set, not the TCI flags)
    // ARB_texture_env_combine RGB_SCALE / ALPHA_SCALE as a left shift (0, 1, 2) applied
    // with saturation after the operation.
    uint8_t colorScaleShift = 0, alphaScaleShift = 0;
    friend bool operator==(const StageState&, const StageState&) = default;
};
static_assert(std::has_unique_object_representations_v<StageState>);

// ---- the arithmetic of one channel --------------------------------------------------
// Per op, the one-line formula of docs/hardware.md. `a1`, `a2`, `a0` are the arguments'
// channel values; `blendAlpha` is the alpha the Blend*Alpha ops weight with (diffuse,
// texture, TFACTOR or current alpha as the op names). The ops whose definition mixes
// colour and alpha (Modulate*Add*, DotProduct3) are handled in evaluateStage().
uint8_t combineChannel(TextureOp op, uint8_t a1, uint8_t a2, uint8_t a0, uint8_t blendAlpha);
// round(a·w + b·(255 − w)) / 255 exactly.
uint8_t lerp255(uint8_t a, uint8_t b, uint8_t w);
// DOTPRODUCT3 over the RGB of two arguments: clamp(round(Σ(2a−255)(2b−255)/255)).
uint8_t dotProduct3(Rgba8 a, Rgba8 b);

// The inputs a stage can read.
struct StageInputs {
    Rgba8 diffuse, specular, current, texture, tfactor;
};
// One stage on one pixel: the selected arguments, the colour and alpha operations, the
// scale. Returns the new current colour.
Rgba8 evaluateStage(const StageState& st, const StageInputs& in);
Rgba8 selectArg(uint8_t a, const StageInputs& in);

// ---- OpenGL texture environments on the same machinery -------------------------------
enum class TexEnvMode : uint8_t { Modulate, Replace, Decal, Blend, Add };
// GL 1.2 Table 3.18/3.19 (plus EXT_texture_env_add) per base format of the texture as a
// stage: Cf = CURRENT (the previous colour), Ct = TEXTURE, Cc = TFACTOR (the
// TEXTURE_ENV_COLOR). Throws rg::InvalidState for DECAL on a format GL leaves undefined.
StageState texEnvStage(TexEnvMode mode, BaseFormat base, uint8_t texCoordIndex = 0);

// ARB_texture_env_combine as a stage.
enum class CombineFunc : uint8_t { Replace, Modulate, Add, AddSigned, Interpolate, Subtract };
enum class CombineSource : uint8_t { Texture, Constant, PrimaryColor, Previous };
enum class CombineOperand : uint8_t { SrcColor, OneMinusSrcColor, SrcAlpha, OneMinusSrcAlpha };
struct CombineChannel {
    CombineFunc func = CombineFunc::Modulate;
    std::array<CombineSource, 3> source{CombineSource::Texture, CombineSource::Previous,
                                        CombineSource::Constant};
    std::array<CombineOperand, 3> operand{CombineOperand::SrcColor, CombineOperand::SrcColor,
                                          CombineOperand::SrcAlpha};
    int scale = 1;  // 1, 2 or 4
};
StageState combineStage(const CombineChannel& rgb, const CombineChannel& alpha,
                        uint8_t texCoordIndex = 0);

}  // namespace rg::tex
