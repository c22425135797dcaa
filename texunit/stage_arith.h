// Internal: the stage arithmetic as inline functions, so that the per-quad cascade in
// texture_units.cpp inlines it; stages.cpp exports the same functions for tests and
// applications (docs/hardware.md, "Texture stages").
#pragma once

#include <emmintrin.h>

#include <algorithm>
#include <array>
#include <cstring>

#include "core/arith8.h"
#include "texunit/stages.h"

namespace rg::tex::detail {

using namespace rg::arith8;

[[gnu::always_inline]] inline uint8_t lerp255(uint8_t a, uint8_t b, uint8_t w) {
    // a·w + b·(255 − w) ≤ 255·255, the range in which Blinn's divide-by-255 is exact.
    uint32_t t = uint32_t(a) * w + uint32_t(b) * (255u - w) + 128u;
    return uint8_t((t + (t >> 8)) >> 8);
}

inline uint8_t dotProduct3(Rgba8 a, Rgba8 b) {
    // 4·Σ(a−½)(b−½) = Σ(2a−1)(2b−1); in 8 bits Σ(2a−255)(2b−255)/255², times 255.
    // s/255 is never a half-integer (255 is odd), so ⌊(s + 127)/255⌋ rounds exactly.
    int32_t s = (2 * a.r - 255) * (2 * b.r - 255) + (2 * a.g - 255) * (2 * b.g - 255) +
                (2 * a.b - 255) * (2 * b.b - 255);
    if (s <= 0) return 0;
    return uint8_t(std::min<int32_t>(255, (s + 127) / 255));
}

[[gnu::always_inline]] inline uint8_t combineChannel(TextureOp op, uint8_t a1, uint8_t a2, uint8_t a0, uint8_t alpha) {
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
        case TextureOp::BlendCurrentAlpha: return detail::lerp255(a1, a2, alpha);
        case TextureOp::BlendTextureAlphaPM: return uint8_t(addSat(a1, mulDiv255(a2, 255u - alpha)));
        case TextureOp::Lerp: return detail::lerp255(a1, a2, a0);
        default: return a1;
    }
}

[[gnu::always_inline]] inline Rgba8 selectArg(uint8_t a, const StageInputs& in) {
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

[[gnu::always_inline]] inline uint8_t blendAlphaFor(TextureOp op, const StageInputs& in) {
    switch (op) {
        case TextureOp::BlendDiffuseAlpha: return in.diffuse.a;
        case TextureOp::BlendTextureAlpha:
        case TextureOp::BlendTextureAlphaPM: return in.texture.a;
        case TextureOp::BlendFactorAlpha: return in.tfactor.a;
        case TextureOp::BlendCurrentAlpha: return in.current.a;
        default: return 0;
    }
}

[[gnu::always_inline]] inline uint8_t scale(uint8_t v, uint8_t shift) {
    return shift == 0 ? v : uint8_t(std::min(uint32_t(v) << shift, 255u));
}

inline Rgba8 evaluateStage(const StageState& st, const StageInputs& in) {
    Rgba8 out = in.current;
    // ---- colour ----------------------------------------------------------------------
    const Rgba8 c1 = detail::selectArg(st.colorArg1, in), c2 = detail::selectArg(st.colorArg2, in);
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
            uint8_t d = detail::dotProduct3(c1, c2);
            out = {d, d, d, d};
            dot3 = true;
            break;
        }
        default: {
            const Rgba8 c0 = detail::selectArg(st.colorArg0, in);
            const uint8_t ba = blendAlphaFor(st.colorOp, in);
            out.r = detail::combineChannel(st.colorOp, c1.r, c2.r, c0.r, ba);
            out.g = detail::combineChannel(st.colorOp, c1.g, c2.g, c0.g, ba);
            out.b = detail::combineChannel(st.colorOp, c1.b, c2.b, c0.b, ba);
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
            const Rgba8 a1 = detail::selectArg(st.alphaArg1, in), a2 = detail::selectArg(st.alphaArg2, in);
            out.a = detail::dotProduct3(a1, a2);
            break;
        }
        default: {
            const uint8_t a1 = detail::selectArg(st.alphaArg1, in).a, a2 = detail::selectArg(st.alphaArg2, in).a;
            const uint8_t a0 = detail::selectArg(st.alphaArg0, in).a;
            out.a = detail::combineChannel(st.alphaOp, a1, a2, a0, blendAlphaFor(st.alphaOp, in));
            break;
        }
    }
    out.a = scale(out.a, st.alphaScaleShift);
    return out;
}


// ---- the fast path: one stage on a whole quad --------------------------------------
// The op is a template argument, so each instantiation is the op's arithmetic alone
// (the switch leaves the pixel loop). Same functions, same order as evaluateStage():
// identical bytes (TextureUnits.ShadeQuadFastMatchesReferenceUnderRandomStates).
template <TextureOp kOp>
inline void colorQuad(const StageState& st, const std::array<StageInputs, 4>& in,
                      std::array<Rgba8, 4>& out) {
    for (int p = 0; p < 4; ++p) {
        const StageInputs& x = in[size_t(p)];
        const Rgba8 c1 = detail::selectArg(st.colorArg1, x), c2 = detail::selectArg(st.colorArg2, x);
        const Rgba8 c0 = kOp == TextureOp::Lerp ? detail::selectArg(st.colorArg0, x) : Rgba8{};
        const uint8_t ba = blendAlphaFor(kOp, x);
        Rgba8& o = out[size_t(p)];
        o = x.current;
        o.r = scale(detail::combineChannel(kOp, c1.r, c2.r, c0.r, ba), st.colorScaleShift);
        o.g = scale(detail::combineChannel(kOp, c1.g, c2.g, c0.g, ba), st.colorScaleShift);
        o.b = scale(detail::combineChannel(kOp, c1.b, c2.b, c0.b, ba), st.colorScaleShift);
    }
}

template <TextureOp kOp>
inline void alphaQuad(const StageState& st, const std::array<StageInputs, 4>& in,
                      std::array<Rgba8, 4>& out) {
    for (int p = 0; p < 4; ++p) {
        const StageInputs& x = in[size_t(p)];
        const uint8_t a1 = detail::selectArg(st.alphaArg1, x).a, a2 = detail::selectArg(st.alphaArg2, x).a;
        const uint8_t a0 = kOp == TextureOp::Lerp ? detail::selectArg(st.alphaArg0, x).a : uint8_t(0);
        out[size_t(p)].a = scale(detail::combineChannel(kOp, a1, a2, a0, blendAlphaFor(kOp, x)),
                                 st.alphaScaleShift);
    }
}

#define RG_TEX_CHANNEL_OPS(X)                                                              \
    X(SelectArg1) X(SelectArg2) X(Modulate) X(Modulate2x) X(Modulate4x) X(Add) X(AddSigned) \
    X(AddSigned2x) X(Subtract) X(AddSmooth) X(BlendDiffuseAlpha) X(BlendTextureAlpha)       \
    X(BlendFactorAlpha) X(BlendTextureAlphaPM) X(BlendCurrentAlpha) X(Lerp)

inline void evaluateStageQuad(const StageState& st, const std::array<StageInputs, 4>& in,
                              std::array<Rgba8, 4>& out) {
    switch (st.colorOp) {
#define RG_TEX_CASE(op) \
    case TextureOp::op: colorQuad<TextureOp::op>(st, in, out); break;
        RG_TEX_CHANNEL_OPS(RG_TEX_CASE)
#undef RG_TEX_CASE
        default:  // the ops that mix colour and alpha, and DOTPRODUCT3: per pixel
            for (int p = 0; p < 4; ++p) out[size_t(p)] = detail::evaluateStage(st, in[size_t(p)]);
            return;
    }
    switch (st.alphaOp) {
#define RG_TEX_CASE(op) \
    case TextureOp::op: alphaQuad<TextureOp::op>(st, in, out); break;
        RG_TEX_CHANNEL_OPS(RG_TEX_CASE)
#undef RG_TEX_CASE
        default:
            for (int p = 0; p < 4; ++p) out[size_t(p)].a = detail::evaluateStage(st, in[size_t(p)]).a;
            break;
    }
}
#undef RG_TEX_CHANNEL_OPS

// ---- the fast path in SSE2: one stage on a whole quad, 16 bytes at a time --------------
// A register holds the four pixels' RGBA (pixel p in bytes 4p..4p+3, as std::array<Rgba8,
// 4> lies in memory). Every operation is the scalar one applied per byte: mulDiv255 and
// lerp255 on 16-bit lanes (a·b + 128 ≤ 65153 and t + (t >> 8) ≤ 65407 stay below 2^16),
// addSat/subSat as the saturating byte adds, clamp255 as packus, the 2×/4× scales as
// saturating doublings (min(2·min(2v, 255), 255) = min(4v, 255)). The alpha op runs on all
// four bytes and only its alpha byte is kept, which is the scalar alpha op on .a.
// Identical bytes: TextureUnits.ShadeQuadFastMatchesReferenceUnderRandomStates.
namespace quad {

// The stage inputs, indexed by their D3DTA source value (selectArg is one indexed load;
// setStage refuses sources above arg::Specular).
struct Regs {
    __m128i src[5];
    __m128i& operator[](uint8_t source) { return src[source]; }
    const __m128i& operator[](uint8_t source) const { return src[source]; }
};

[[gnu::always_inline]] inline __m128i load(const std::array<Rgba8, 4>& v) {
    return _mm_loadu_si128(reinterpret_cast<const __m128i*>(v.data()));
}
// The same 16 bytes as four 4-byte loads: for data the rasterizer has just written pixel by
// pixel, where one 16-byte load would wait for the stores to retire (no store forwarding
// from several smaller stores into one wider load).
[[gnu::always_inline]] inline __m128i loadPixels(const std::array<Rgba8, 4>& v) {
    auto px = [&](int p) {
        int32_t x;
        std::memcpy(&x, &v[size_t(p)], 4);
        return _mm_cvtsi32_si128(x);
    };
    return _mm_unpacklo_epi64(_mm_unpacklo_epi32(px(0), px(1)), _mm_unpacklo_epi32(px(2), px(3)));
}
[[gnu::always_inline]] inline void store(std::array<Rgba8, 4>& v, __m128i x) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(v.data()), x);
}
[[gnu::always_inline]] inline __m128i splat(Rgba8 c) {
    uint32_t x = uint32_t(c.r) | uint32_t(c.g) << 8 | uint32_t(c.b) << 16 | uint32_t(c.a) << 24;
    return _mm_set1_epi32(int32_t(x));
}
[[gnu::always_inline]] inline __m128i ones() { return _mm_set1_epi32(-1); }
[[gnu::always_inline]] inline __m128i alphaBroadcast(__m128i v) {
    const __m128i a = _mm_srli_epi32(v, 24);
    const __m128i a2 = _mm_or_si128(a, _mm_slli_epi32(a, 8));
    return _mm_or_si128(a2, _mm_slli_epi32(a2, 16));
}
[[gnu::always_inline]] inline __m128i selectArg(uint8_t a, const Regs& in) {
    const uint8_t source = a & arg::SourceMask;
    __m128i v = in[source <= arg::Specular ? source : arg::Current];
    if (a & arg::AlphaReplicate) v = alphaBroadcast(v);
    if (a & arg::Complement) v = _mm_xor_si128(v, ones());
    return v;
}
// round(a·b/255) per byte (Blinn), as arith8::mulDiv255.
[[gnu::always_inline]] inline __m128i mulDiv255Half(__m128i a, __m128i b) {
    const __m128i t = _mm_add_epi16(_mm_mullo_epi16(a, b), _mm_set1_epi16(128));
    return _mm_srli_epi16(_mm_add_epi16(t, _mm_srli_epi16(t, 8)), 8);
}
[[gnu::always_inline]] inline __m128i mulDiv255(__m128i a, __m128i b) {
    const __m128i z = _mm_setzero_si128();
    return _mm_packus_epi16(
        mulDiv255Half(_mm_unpacklo_epi8(a, z), _mm_unpacklo_epi8(b, z)),
        mulDiv255Half(_mm_unpackhi_epi8(a, z), _mm_unpackhi_epi8(b, z)));
}
// (a·w + b·(255 − w) + 128) then Blinn's divide, per byte, as lerp255.
[[gnu::always_inline]] inline __m128i lerp255Half(__m128i a, __m128i b, __m128i w) {
    const __m128i iw = _mm_sub_epi16(_mm_set1_epi16(255), w);
    const __m128i t = _mm_add_epi16(_mm_add_epi16(_mm_mullo_epi16(a, w), _mm_mullo_epi16(b, iw)),
                                    _mm_set1_epi16(128));
    return _mm_srli_epi16(_mm_add_epi16(t, _mm_srli_epi16(t, 8)), 8);
}
[[gnu::always_inline]] inline __m128i lerp255(__m128i a, __m128i b, __m128i w) {
    const __m128i z = _mm_setzero_si128();
    return _mm_packus_epi16(
        lerp255Half(_mm_unpacklo_epi8(a, z), _mm_unpacklo_epi8(b, z), _mm_unpacklo_epi8(w, z)),
        lerp255Half(_mm_unpackhi_epi8(a, z), _mm_unpackhi_epi8(b, z), _mm_unpackhi_epi8(w, z)));
}
// clamp255(k·(a1 + a2 − 128)) per byte, k = 1 or 2 (ADDSIGNED, ADDSIGNED2X).
template <int kShift>
[[gnu::always_inline]] inline __m128i addSigned(__m128i a, __m128i b) {
    const __m128i z = _mm_setzero_si128(), k = _mm_set1_epi16(128);
    auto half = [&](__m128i x, __m128i y) {
        return _mm_slli_epi16(_mm_sub_epi16(_mm_add_epi16(x, y), k), kShift);
    };
    return _mm_packus_epi16(half(_mm_unpacklo_epi8(a, z), _mm_unpacklo_epi8(b, z)),
                            half(_mm_unpackhi_epi8(a, z), _mm_unpackhi_epi8(b, z)));
}
[[gnu::always_inline]] inline __m128i scale(__m128i v, uint8_t shift) {
    for (uint8_t i = 0; i < shift; ++i) v = _mm_adds_epu8(v, v);
    return v;
}
[[gnu::always_inline]] inline __m128i blendAlphaFor(TextureOp op, const Regs& in) {
    switch (op) {
        case TextureOp::BlendDiffuseAlpha: return alphaBroadcast(in[arg::Diffuse]);
        case TextureOp::BlendTextureAlpha:
        case TextureOp::BlendTextureAlphaPM: return alphaBroadcast(in[arg::Texture]);
        case TextureOp::BlendFactorAlpha: return alphaBroadcast(in[arg::TFactor]);
        case TextureOp::BlendCurrentAlpha: return alphaBroadcast(in[arg::Current]);
        default: return _mm_setzero_si128();
    }
}
// combineChannel per byte for the channel ops (isChannelOp).
[[gnu::always_inline]] inline __m128i combine(TextureOp op, __m128i a1, __m128i a2, __m128i a0, const Regs& in) {
    switch (op) {
        case TextureOp::SelectArg1: return a1;
        case TextureOp::SelectArg2: return a2;
        case TextureOp::Modulate: return mulDiv255(a1, a2);
        case TextureOp::Modulate2x: {
            const __m128i m = mulDiv255(a1, a2);
            return _mm_adds_epu8(m, m);
        }
        case TextureOp::Modulate4x: {
            const __m128i m = mulDiv255(a1, a2), m2 = _mm_adds_epu8(m, m);
            return _mm_adds_epu8(m2, m2);
        }
        case TextureOp::Add: return _mm_adds_epu8(a1, a2);
        case TextureOp::AddSigned: return addSigned<0>(a1, a2);
        case TextureOp::AddSigned2x: return addSigned<1>(a1, a2);
        case TextureOp::Subtract: return _mm_subs_epu8(a1, a2);
        case TextureOp::AddSmooth: return _mm_add_epi8(a1, mulDiv255(a2, _mm_xor_si128(a1, ones())));
        case TextureOp::BlendDiffuseAlpha:
        case TextureOp::BlendTextureAlpha:
        case TextureOp::BlendFactorAlpha:
        case TextureOp::BlendCurrentAlpha: return lerp255(a1, a2, blendAlphaFor(op, in));
        case TextureOp::BlendTextureAlphaPM:
            return _mm_adds_epu8(a1, mulDiv255(a2, _mm_xor_si128(blendAlphaFor(op, in), ones())));
        case TextureOp::Lerp: return lerp255(a1, a2, a0);
        default: return a1;
    }
}
[[gnu::always_inline]] inline bool isChannelOp(TextureOp op) {
    return (op >= TextureOp::SelectArg1 && op <= TextureOp::BlendCurrentAlpha) || op == TextureOp::Lerp;
}
// The states evaluate() takes: a channel colour op and a channel (or DISABLE/PREMODULATE)
// alpha op; the rest (DOTPRODUCT3, the MODULATE*ADD* ops) go through evaluateStageQuad.
[[gnu::always_inline]] inline bool supported(const StageState& st) {
    return isChannelOp(st.colorOp) &&
           (isChannelOp(st.alphaOp) || st.alphaOp == TextureOp::Disable ||
            st.alphaOp == TextureOp::PreModulate);
}
// evaluateStageQuad for a supported() state: the new CURRENT of the four pixels. kColor /
// kAlpha fix the ops at compile time for the common states (TextureOp::Count: read them
// from `st`), which leaves the op's arithmetic alone in the instantiation.
template <TextureOp kColor = TextureOp::Count, TextureOp kAlpha = TextureOp::Count>
[[gnu::always_inline]] inline __m128i evaluate(const StageState& st, const Regs& in) {
    const TextureOp colorOp = kColor == TextureOp::Count ? st.colorOp : kColor;
    const TextureOp alphaOp = kAlpha == TextureOp::Count ? st.alphaOp : kAlpha;
    const __m128i c0 = colorOp == TextureOp::Lerp ? selectArg(st.colorArg0, in) : _mm_setzero_si128();
    __m128i color = combine(colorOp, selectArg(st.colorArg1, in), selectArg(st.colorArg2, in), c0, in);
    if (st.colorScaleShift) color = scale(color, st.colorScaleShift);
    // The same op on the same arguments with the same scale for alpha (GL MODULATE and
    // REPLACE, the PEM stages): every byte of `color` is already the op on that channel.
    if (alphaOp == colorOp && st.alphaArg1 == st.colorArg1 && st.alphaArg2 == st.colorArg2 &&
        st.alphaScaleShift == st.colorScaleShift &&
        (colorOp != TextureOp::Lerp || st.alphaArg0 == st.colorArg0))
        return color;
    __m128i alpha;
    if (alphaOp == TextureOp::Disable || alphaOp == TextureOp::PreModulate) {
        alpha = in[arg::Current];  // CURRENT's alpha passes, and is still scaled (evaluateStage)
    } else {
        const __m128i a0 = alphaOp == TextureOp::Lerp ? selectArg(st.alphaArg0, in) : _mm_setzero_si128();
        alpha = combine(alphaOp, selectArg(st.alphaArg1, in), selectArg(st.alphaArg2, in), a0, in);
    }
    if (st.alphaScaleShift) alpha = scale(alpha, st.alphaScaleShift);
    const __m128i alphaMask = _mm_set1_epi32(int32_t(0xff000000u));
    return _mm_or_si128(_mm_andnot_si128(alphaMask, color), _mm_and_si128(alphaMask, alpha));
}

// Which evaluate() instantiation a stage uses, chosen when the state is set.
enum class StageKernel : uint8_t {
    Scalar,  // not supported(): evaluateStageQuad per pixel
    Any,     // evaluate<>: ops read from the state
    // The fixed-function states of real frames (GL REPLACE/MODULATE/DECAL, the PEM passes).
    SelectSelect, ModulateModulate, ModulateSelect1, ModulateSelect2, SelectModulate,
    BlendFactorBlendFactor, BlendTextureDisable,
};
inline StageKernel stageKernel(const StageState& st) {
    using O = TextureOp;
    if (!supported(st)) return StageKernel::Scalar;
    const O c = st.colorOp, a = st.alphaOp;
    if (c == O::SelectArg1 && a == O::SelectArg1) return StageKernel::SelectSelect;
    if (c == O::Modulate && a == O::Modulate) return StageKernel::ModulateModulate;
    if (c == O::Modulate && a == O::SelectArg1) return StageKernel::ModulateSelect1;
    if (c == O::Modulate && a == O::SelectArg2) return StageKernel::ModulateSelect2;
    if (c == O::SelectArg1 && a == O::Modulate) return StageKernel::SelectModulate;
    if (c == O::BlendFactorAlpha && a == O::BlendFactorAlpha) return StageKernel::BlendFactorBlendFactor;
    if (c == O::BlendTextureAlpha && a == O::Disable) return StageKernel::BlendTextureDisable;
    return StageKernel::Any;
}
// evaluate() through the kernel chosen by stageKernel() (not for StageKernel::Scalar).
[[gnu::always_inline]] inline __m128i evaluateKernel(StageKernel k, const StageState& st,
                                                     const Regs& in) {
    using O = TextureOp;
    switch (k) {
        case StageKernel::SelectSelect: return evaluate<O::SelectArg1, O::SelectArg1>(st, in);
        case StageKernel::ModulateModulate: return evaluate<O::Modulate, O::Modulate>(st, in);
        case StageKernel::ModulateSelect1: return evaluate<O::Modulate, O::SelectArg1>(st, in);
        case StageKernel::ModulateSelect2: return evaluate<O::Modulate, O::SelectArg2>(st, in);
        case StageKernel::SelectModulate: return evaluate<O::SelectArg1, O::Modulate>(st, in);
        case StageKernel::BlendFactorBlendFactor:
            return evaluate<O::BlendFactorAlpha, O::BlendFactorAlpha>(st, in);
        case StageKernel::BlendTextureDisable: return evaluate<O::BlendTextureAlpha, O::Disable>(st, in);
        default: return evaluate<>(st, in);
    }
}

}  // namespace quad

}  // namespace rg::tex::detail
