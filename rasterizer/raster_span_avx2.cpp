// AVX2 twin of processQuadSse (fragment_quad_sse.h): two 2×2 quads side by side, one per
// 128-bit half of each 256-bit register. Every AVX2 instruction used here works lane by
// lane (floating add/mul/div/max/min/cvtt, 16-bit mullo/srli/add/min/subs, in-lane packs,
// unpacks and shuffles), so each half computes exactly what the SSE2 kernel computes for
// its quad; no FMA (only target "avx2", and -ffp-contract=off). Selected at run time.
#include "raster_span_avx2.h"

#include <immintrin.h>

#include <cstdlib>
#include <cstring>

#include "core/cpu.h"

namespace rg::raster::detail {

// RETROGLASS_NO_AVX2 (any value) selects the SSE2 kernels on an AVX2 machine, so that the
// differential test can hold them to the reference too (tests/rasterizer/CMakeLists.txt).
bool haveAvx2() {
    return avx2Enabled();
}

namespace {

#define RG_AVX2 __attribute__((target("avx2"), always_inline)) inline

RG_AVX2 __m256 both(__m128 v) { return _mm256_set_m128(v, v); }

RG_AVX2 __m256i broadcastAlpha(__m256i x) {
    return _mm256_shufflehi_epi16(_mm256_shufflelo_epi16(x, 0xFF), 0xFF);
}

RG_AVX2 __m256i mulDiv255(__m256i a, __m256i b) {
    __m256i t = _mm256_add_epi16(_mm256_mullo_epi16(a, b), _mm256_set1_epi16(128));
    return _mm256_srli_epi16(_mm256_add_epi16(t, _mm256_srli_epi16(t, 8)), 8);
}

RG_AVX2 __m256i factor(BlendFactor f, __m256i s, __m256i d) {
    const __m256i k255 = _mm256_set1_epi16(255);
    switch (f) {
        case BlendFactor::Zero: return _mm256_setzero_si256();
        case BlendFactor::One: return k255;
        case BlendFactor::SrcColor: return s;
        case BlendFactor::InvSrcColor: return _mm256_sub_epi16(k255, s);
        case BlendFactor::SrcAlpha:
        case BlendFactor::BothSrcAlpha: return broadcastAlpha(s);
        case BlendFactor::InvSrcAlpha:
        case BlendFactor::BothInvSrcAlpha: return _mm256_sub_epi16(k255, broadcastAlpha(s));
        case BlendFactor::DestAlpha: return broadcastAlpha(d);
        case BlendFactor::InvDestAlpha: return _mm256_sub_epi16(k255, broadcastAlpha(d));
        case BlendFactor::DestColor: return d;
        case BlendFactor::InvDestColor: return _mm256_sub_epi16(k255, d);
        case BlendFactor::SrcAlphaSat: {
            __m256i f3 = _mm256_min_epi16(broadcastAlpha(s), _mm256_sub_epi16(k255, broadcastAlpha(d)));
            const __m256i alphaLanes = _mm256_set_epi16(-1, 0, 0, 0, -1, 0, 0, 0, -1, 0, 0, 0, -1, 0, 0, 0);
            return _mm256_or_si256(_mm256_andnot_si256(alphaLanes, f3), _mm256_and_si256(alphaLanes, k255));
        }
    }
    return _mm256_setzero_si256();
}

RG_AVX2 __m256i blend4(BlendFactor srcF, BlendFactor dstF, BlendOp op, __m256i s, __m256i d) {
    switch (op) {
        case BlendOp::Min: return _mm256_min_epi16(s, d);
        case BlendOp::Max: return _mm256_max_epi16(s, d);
        default: break;
    }
    const BlendFactor df = effectiveDestFactor(srcF, dstF);
    __m256i sp = mulDiv255(s, factor(srcF, s, d));
    __m256i dp = mulDiv255(d, factor(df, s, d));
    switch (op) {
        case BlendOp::Add: return _mm256_min_epi16(_mm256_add_epi16(sp, dp), _mm256_set1_epi16(255));
        case BlendOp::Subtract: return _mm256_subs_epu16(sp, dp);
        case BlendOp::RevSubtract: return _mm256_subs_epu16(dp, sp);
        default: return sp;
    }
}

RG_AVX2 __m256i channelToInt(__m256 v) {
    v = _mm256_max_ps(v, _mm256_setzero_ps());
    v = _mm256_min_ps(v, _mm256_set1_ps(255.0f));
    return _mm256_cvttps_epi32(_mm256_add_ps(v, _mm256_set1_ps(0.5f)));
}

RG_AVX2 __m256i toPixels(__m256i r, __m256i g, __m256i b, __m256i a) {
    __m256i x = _mm256_packus_epi16(_mm256_packs_epi32(r, b), _mm256_packs_epi32(g, a));
    __m256i lo = _mm256_unpacklo_epi8(x, _mm256_srli_si256(x, 8));
    return _mm256_unpacklo_epi16(lo, _mm256_srli_si256(lo, 8));
}

template <bool kDepth, int kBlendMode>
__attribute__((target("avx2"), always_inline)) inline void pairOutputAvx2(
    const DrawContext& dc, const SetupTriangle& t, int qx, int qy, unsigned cov, __m256i src,
    RasterCounters& rc);

template <bool kDepth, int kBlendMode>
__attribute__((target("avx2"), always_inline)) inline void pairAvx2(const DrawContext& dc, const SetupTriangle& t,
                                              const __m256 (&c)[4], const __m256 (&dx)[4],
                                              const __m256 (&dyfy)[4], __m256 wc, __m256 wdx,
                                              __m256 wdyfy, bool perspective, bool flatW,
                                              __m256 flatR, int qx, int qy, unsigned cov,
                                              RasterCounters& rc) {
    // fx of the eight pixels: quad qx in the low half, quad qx + 2 in the high half.
    const __m256 fx = _mm256_sub_ps(
        _mm256_setr_ps(float(qx) + 0.5f, float(qx + 1) + 0.5f, float(qx) + 0.5f,
                       float(qx + 1) + 0.5f, float(qx + 2) + 0.5f, float(qx + 3) + 0.5f,
                       float(qx + 2) + 0.5f, float(qx + 3) + 0.5f),
        _mm256_set1_ps(t.x0));
    __m256 r = _mm256_set1_ps(1.0f);
    if (perspective) {
        if (flatW) {
            r = flatR;
        } else {
            __m256 w = _mm256_add_ps(_mm256_add_ps(wc, _mm256_mul_ps(wdx, fx)), wdyfy);
            r = _mm256_div_ps(_mm256_set1_ps(1.0f), w);
        }
    }
    __m256i ch[4];
    for (int a = 0; a < 4; ++a) {
        __m256 v = _mm256_add_ps(_mm256_add_ps(c[a], _mm256_mul_ps(dx[a], fx)), dyfy[a]);
        if (perspective) v = _mm256_mul_ps(v, r);
        ch[a] = channelToInt(v);
    }
    const __m256i src = toPixels(ch[0], ch[1], ch[2], ch[3]);  // quad 0 | quad 1, pixel-major
    pairOutputAvx2<kDepth, kBlendMode>(dc, t, qx, qy, cov, src, rc);
}

// The second half of pairAvx2 (quadOutputSse for two quads): alpha and depth tests, blend,
// write mask and store of the source pixels `src` (quad qx | quad qx + 2, pixel-major,
// specular already added); `cov`: bits 0..3 quad qx, 4..7 quad qx + 2.
template <bool kDepth, int kBlendMode>
__attribute__((target("avx2"), always_inline)) inline void pairOutputAvx2(
    const DrawContext& dc, const SetupTriangle& t, int qx, int qy, unsigned cov, __m256i src,
    RasterCounters& rc) {
    const PipelineState& st = dc.st;
    Framebuffer& fb = *dc.fb;
    const size_t width = size_t(fb.width());
    const size_t row0 = size_t(qy) * width + size_t(qx), row1 = row0 + width;
    unsigned passed = cov;  // bits 0..3 quad 0, 4..7 quad 1
    if (!kDepth && !st.alphaTest) {
        rc.generated += sse::kPopcount4[cov & 15] + sse::kPopcount4[cov >> 4];
    } else {
        alignas(32) uint8_t bytes[32];
        _mm256_store_si256(reinterpret_cast<__m256i*>(bytes), src);
        passed = 0;
        for (int k = 0; k < 8; ++k) {
            if (!(cov & (1u << k))) continue;
            ++rc.generated;
            if (st.alphaTest && !comparePasses(st.alphaFunc, bytes[4 * k + 3], st.alphaRef)) continue;
            if constexpr (kDepth) {
                const int i = k & 3, q = k >> 2;
                const int px = qx + 2 * q + (i & 1), py = qy + (i >> 1);
                const size_t idx = ((i >> 1) ? row1 : row0) + size_t(2 * q + (i & 1));
                double z = (t.zc + t.zdx * ((double(px) + 0.5) - double(t.x0))) +
                           t.zdy * ((double(py) + 0.5) - double(t.y0));
                uint32_t zq = quantizeDepth(z, dc.depthMax);
                uint32_t& stored = fb.depth()[idx];
                if (!comparePasses(st.depthFunc, zq, stored)) continue;
                if (st.depthWrite) stored = zq;
            }
            passed |= 1u << k;
        }
    }
    if (!passed) return;
    const int n = sse::kPopcount4[passed & 15] + sse::kPopcount4[passed >> 4];
    rc.written += uint64_t(n);

    // Destination: rows of both quads, rearranged to quad 0 | quad 1 like `src`.
    Rgba8* color = fb.color().data();
    const __m128i d0 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(color + row0));
    const __m128i d1 = _mm_loadu_si128(reinterpret_cast<const __m128i*>(color + row1));
    const __m256i dst = _mm256_set_m128i(_mm_unpackhi_epi64(d0, d1), _mm_unpacklo_epi64(d0, d1));
    __m256i out = src;
    if constexpr (kBlendMode != kBlendNone) {
        BlendFactor sf = st.srcBlend, df = st.dstBlend;
        BlendOp op = st.blendOp;
        if constexpr (kBlendMode == kBlendSrcAlphaInvSrcAlpha) {
            sf = BlendFactor::SrcAlpha, df = BlendFactor::InvSrcAlpha, op = BlendOp::Add;
        } else if constexpr (kBlendMode == kBlendOneOne) {
            sf = BlendFactor::One, df = BlendFactor::One, op = BlendOp::Add;
        }
        const __m256i zero = _mm256_setzero_si256();
        __m256i lo = blend4(sf, df, op, _mm256_unpacklo_epi8(src, zero), _mm256_unpacklo_epi8(dst, zero));
        __m256i hi = blend4(sf, df, op, _mm256_unpackhi_epi8(src, zero), _mm256_unpackhi_epi8(dst, zero));
        out = _mm256_packus_epi16(lo, hi);
        rc.blendOps += uint64_t(n);
    }
    if (!(passed == 0xFFu && st.colorWriteMask == kWriteRGBA)) {
        const uint32_t channels = sse::writeMaskBytes(st.colorWriteMask);
        alignas(32) uint32_t m[8];
        for (int k = 0; k < 8; ++k) m[k] = (passed & (1u << k)) ? channels : 0u;
        const __m256i mask = _mm256_load_si256(reinterpret_cast<const __m256i*>(m));
        out = _mm256_or_si256(_mm256_and_si256(mask, out), _mm256_andnot_si256(mask, dst));
    }
    const __m128i q0 = _mm256_castsi256_si128(out), q1 = _mm256_extracti128_si256(out, 1);
    _mm_storeu_si128(reinterpret_cast<__m128i*>(color + row0), _mm_unpacklo_epi64(q0, q1));
    _mm_storeu_si128(reinterpret_cast<__m128i*>(color + row1), _mm_unpackhi_epi64(q0, q1));
}

// pairOutputAvx2 of a pair shaded into `shaded` (quad qx, then quad qx + 2), with its
// specular colours for the specular add.
template <bool kDepth, int kBlendMode>
__attribute__((target("avx2"), always_inline)) inline void pairOutputPendingAvx2(
    const DrawContext& dc, const SetupTriangle& t, int qx, int qy, unsigned cov,
    const std::array<Rgba8, 8>& shaded, __m256i specular, RasterCounters& rc) {
    // Two 16-byte loads, as the cascade stored them (a 32-byte load would miss store
    // forwarding).
    __m256i src = _mm256_set_m128i(
        _mm_load_si128(reinterpret_cast<const __m128i*>(shaded.data() + 4)),
        _mm_load_si128(reinterpret_cast<const __m128i*>(shaded.data())));
    if (dc.st.specularEnable)  // addSpecular: rgb saturate-add, alpha untouched
        src = _mm256_adds_epu8(src, _mm256_and_si256(specular, _mm256_set1_epi32(0x00FFFFFF)));
    pairOutputAvx2<kDepth, kBlendMode>(dc, t, qx, qy, cov, src, rc);
}

template <bool kDepth, int kBlendMode>
__attribute__((target("avx2"), noinline)) void runAvx2(const DrawContext& dc,
                                                       const SetupTriangle& t,
                                                       const sse::Planes& planes,
                                                       const sse::RowTerms& row, int qy,
                                                       int qx0, int count,
                                                       const uint8_t* coverage,
                                                       RasterCounters& rc) {
    __m256 c[4], dx[4], dyfy[4];
    for (int a = 0; a < 4; ++a) {
        c[a] = both(planes.c[a]);
        dx[a] = both(planes.dx[a]);
        dyfy[a] = both(row.dyfy[a]);
    }
    const __m256 wc = both(planes.wc), wdx = both(planes.wdx), wdyfy = both(row.wdyfy);
    const bool perspective = dc.perspectiveColor && !planes.unitW;
    const __m256 flatR = both(planes.flatR);
    int k = 0;
    for (; k + 1 < count; k += 2) {
        const unsigned cov = unsigned(coverage[k]) | (unsigned(coverage[k + 1]) << 4);
        if (cov)
            pairAvx2<kDepth, kBlendMode>(dc, t, c, dx, dyfy, wc, wdx, wdyfy, perspective,
                                         planes.flatW, flatR, qx0 + 2 * k, qy, cov, rc);
    }
    if (k < count && coverage[k])
        processQuadSse<kDepth, kBlendMode>(dc, t, planes, row, qx0 + 2 * k, qy, coverage[k], rc);
}

// Four colour planes of two quads (sse::colors lane for lane).
RG_AVX2 __m256i colors8(const __m256* c, const __m256* dx, const __m256* dyfy, __m256 fx,
                        bool perspective, __m256 r) {
    __m256i ch[4];
    for (int a = 0; a < 4; ++a) {
        __m256 v = _mm256_add_ps(_mm256_add_ps(c[a], _mm256_mul_ps(dx[a], fx)), dyfy[a]);
        if (perspective) v = _mm256_mul_ps(v, r);
        ch[a] = channelToInt(v);
    }
    return toPixels(ch[0], ch[1], ch[2], ch[3]);
}

// Quads with texture stages, two per register: processTexturedQuadSse
// (fragment_quad_textured.h) lane for lane — fx, 1/w, the colours and the texture
// coordinates of both quads in 8-lane registers, each 128-bit half the SSE2 kernel's
// operations on its quad (the 4×4 transpose into per-pixel (s, t, r, q) works within
// halves); then shadeQuad per covered quad (a quad without coverage is not shaded, as in
// the scalar loop, so the fetch counts agree) and the fragment operations of both quads
// at once (pairOutputAvx2). `q`: two FragmentQuad scratch values of the triangle.
template <bool kDepth, int kBlendMode>
__attribute__((target("avx2"), noinline)) void texturedRunImpl(
    const DrawContext& dc, const SetupTriangle& t, const sse::Planes& planes,
    const sse::RowTerms& row, const sse::TexPlanes& tplanes, const sse::TexRowTerms& trow,
    int qy, int qx0, int count, const uint8_t* coverage, tex::FragmentQuad* q,
    RasterCounters& rc) {
    const PipelineState& st = dc.st;
    __m256 c[8], dx[8], dyfy[8];
    for (int a = 0; a < planes.count; ++a) {
        c[a] = both(planes.c[a]);
        dx[a] = both(planes.dx[a]);
        dyfy[a] = both(row.dyfy[a]);
    }
    constexpr int kMaxT = sse::TexPlanes::kMax;
    __m256 tc[kMaxT], tdx[kMaxT], tdyfy[kMaxT];
    for (int k = 0; k < tplanes.count; ++k) {
        tc[k] = both(tplanes.c[k]);
        tdx[k] = both(tplanes.dx[k]);
        tdyfy[k] = both(trow.dyfy[k]);
    }
    const __m256 wc = _mm256_set1_ps(t.invW.c), wdx = _mm256_set1_ps(t.invW.dx),
                 wdyfy = both(row.wdyfy);
    const bool perspective = dc.perspectiveColor && !planes.unitW;
    __m256i flatDiffuse = _mm256_setzero_si256(), flatSpecular = _mm256_setzero_si256();
    if (!dc.gouraud) {
        uint32_t bits;
        std::memcpy(&bits, &t.flatDiffuse, 4);
        flatDiffuse = _mm256_set1_epi32(int(bits));
        std::memcpy(&bits, &t.flatSpecular, 4);
        flatSpecular = _mm256_set1_epi32(int(bits));
    }
    // A compiled whole-quad cascade takes both quads as they are here, one component per
    // 8-lane register (FragmentQuadPair), with no transposes and one call per pair.
    const bool pairs = dc.path == Path::Fast && dc.tu->shadesPairs();
    const tex::TextureUnits::PairShader shadePair = pairs ? dc.tu->pairShader() : tex::TextureUnits::PairShader{};
    alignas(32) tex::FragmentQuadPair pair;
    uint64_t fetched = 0;  // of the pairs, added to the texture units' counter at the end
    // The fragment operations of a shaded pair wait until the next pair has been handed to
    // the texture units (or the run ends): its colours are then long stored, and the
    // texturing of the next pair overlaps them instead of the run stalling on the cascade's
    // result. Pairs cover disjoint pixels, and the counters are sums, so the order of the
    // outputs changes nothing.
    alignas(32) std::array<Rgba8, 8> shaded[2];
    int slot = 0;
    unsigned pendingCov = 0;
    int pendingQx = 0;
    __m256i pendingSpecular = _mm256_setzero_si256();
    // 1/w without slope (Planes::flatW): every pixel's (c + dx·fx) + dy·fy is c exactly
    // (both products are ±0, c is finite and non-zero), so its 1.0f/w is planes.flatR;
    // when that is 1 (unitW) the ·r of the texture coordinates is the identity.
    const bool flatW = planes.flatW, unitW = planes.unitW;
    const __m256 flatR = both(planes.flatR);
    // The pixel centres x + ½ of a pair, stepped by 4 per pair: multiples of ½ below 2^22,
    // so every sum is exact — the floats float(qx + i) + 0.5f (computed as such on a
    // framebuffer too wide for that).
    __m256 centre = _mm256_setr_ps(float(qx0) + 0.5f, float(qx0 + 1) + 0.5f, float(qx0) + 0.5f,
                                   float(qx0 + 1) + 0.5f, float(qx0 + 2) + 0.5f,
                                   float(qx0 + 3) + 0.5f, float(qx0 + 2) + 0.5f,
                                   float(qx0 + 3) + 0.5f);
    const __m256 x0 = _mm256_set1_ps(t.x0), four = _mm256_set1_ps(4.0f);
    const bool exactSteps = qx0 >= 0 && int64_t(qx0) + 2 * int64_t(count) + 4 <= (int64_t(1) << 22);
    int k = 0;
    for (; k + 1 < count; k += 2, centre = _mm256_add_ps(centre, four)) {
        const unsigned cov = unsigned(coverage[k]) | (unsigned(coverage[k + 1]) << 4);
        if (!cov) continue;
        const int qx = qx0 + 2 * k;
        const __m256 fx = _mm256_sub_ps(
            exactSteps ? centre
                       : _mm256_setr_ps(float(qx) + 0.5f, float(qx + 1) + 0.5f, float(qx) + 0.5f,
                                        float(qx + 1) + 0.5f, float(qx + 2) + 0.5f,
                                        float(qx + 3) + 0.5f, float(qx + 2) + 0.5f,
                                        float(qx + 3) + 0.5f),
            x0);
        const __m256 r =
            flatW ? flatR
                  : _mm256_div_ps(_mm256_set1_ps(1.0f),
                                  _mm256_add_ps(_mm256_add_ps(wc, _mm256_mul_ps(wdx, fx)), wdyfy));
        __m256i diffuse = flatDiffuse, specular = flatSpecular;
        if (dc.gouraud) {
            diffuse = colors8(c, dx, dyfy, fx, perspective, r);
            if (planes.count == 8)  // specularRead
                specular = colors8(c + 4, dx + 4, dyfy + 4, fx, perspective, r);
        }
        if (pairs) {
            pair.x = qx;
            pair.y = qy;
            pair.coverage = {uint8_t(cov & 0xFu), uint8_t(cov >> 4)};
            _mm256_store_si256(reinterpret_cast<__m256i*>(pair.diffuse.data()), diffuse);
            _mm256_store_si256(reinterpret_cast<__m256i*>(pair.specular.data()), specular);
            for (int set = 0; set < dc.numTexSets; ++set) {
                float(&dst)[4][8] = pair.texCoord[size_t(dc.texSets[size_t(set)])];
                for (int a = 0; a < 4; ++a) {
                    const int p = 4 * set + a;
                    __m256 v = _mm256_add_ps(_mm256_add_ps(tc[p], _mm256_mul_ps(tdx[p], fx)),
                                             tdyfy[p]);
                    if (!unitW) v = _mm256_mul_ps(v, r);
                    _mm256_store_ps(dst[a], v);
                }
            }
            fetched += shadePair(pair, shaded[slot]);
            if (pendingCov)
                pairOutputPendingAvx2<kDepth, kBlendMode>(dc, t, pendingQx, qy, pendingCov,
                                                          shaded[slot ^ 1], pendingSpecular, rc);
            slot ^= 1;
            pendingCov = cov;
            pendingQx = qx;
            pendingSpecular = specular;
            continue;
        }
        for (int h = 0; h < 2; ++h) {
            const unsigned qc = (cov >> (4 * h)) & 0xFu;
            q[h].x = qx + 2 * h;
            q[h].y = qy;
            q[h].coverage = uint8_t(qc);
        }
        _mm_storeu_si128(reinterpret_cast<__m128i*>(q[0].diffuse.data()), _mm256_castsi256_si128(diffuse));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(q[1].diffuse.data()), _mm256_extracti128_si256(diffuse, 1));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(q[0].specular.data()), _mm256_castsi256_si128(specular));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(q[1].specular.data()), _mm256_extracti128_si256(specular, 1));
        for (int set = 0; set < dc.numTexSets; ++set) {
            __m256 v[4];
            for (int a = 0; a < 4; ++a) {
                const int p = 4 * set + a;
                v[a] = _mm256_mul_ps(
                    _mm256_add_ps(_mm256_add_ps(tc[p], _mm256_mul_ps(tdx[p], fx)), tdyfy[p]), r);
            }
            // _MM_TRANSPOSE4_PS within each half.
            const __m256 t0 = _mm256_unpacklo_ps(v[0], v[1]), t1 = _mm256_unpacklo_ps(v[2], v[3]);
            const __m256 t2 = _mm256_unpackhi_ps(v[0], v[1]), t3 = _mm256_unpackhi_ps(v[2], v[3]);
            const __m256 px[4] = {_mm256_shuffle_ps(t0, t1, 0x44), _mm256_shuffle_ps(t0, t1, 0xEE),
                                  _mm256_shuffle_ps(t2, t3, 0x44), _mm256_shuffle_ps(t2, t3, 0xEE)};
            const size_t dst = size_t(dc.texSets[size_t(set)]);
            for (int i = 0; i < 4; ++i) {
                _mm_storeu_ps(&q[0].texCoord[dst][size_t(i)][0], _mm256_castps256_ps128(px[i]));
                _mm_storeu_ps(&q[1].texCoord[dst][size_t(i)][0], _mm256_extractf128_ps(px[i], 1));
            }
        }
        alignas(16) std::array<Rgba8, 4> shaded[2] = {};  // an unshaded quad: no pixel passes
        for (int h = 0; h < 2; ++h)
            if (q[h].coverage) dc.tu->shadeQuad(q[h], shaded[h], dc.path);
        __m256i src = _mm256_set_m128i(
            _mm_load_si128(reinterpret_cast<const __m128i*>(shaded[1].data())),
            _mm_load_si128(reinterpret_cast<const __m128i*>(shaded[0].data())));
        if (st.specularEnable)  // addSpecular: rgb saturate-add, alpha untouched
            src = _mm256_adds_epu8(src, _mm256_and_si256(specular, _mm256_set1_epi32(0x00FFFFFF)));
        pairOutputAvx2<kDepth, kBlendMode>(dc, t, qx, qy, cov, src, rc);
    }
    if (pendingCov)
        pairOutputPendingAvx2<kDepth, kBlendMode>(dc, t, pendingQx, qy, pendingCov,
                                                  shaded[slot ^ 1], pendingSpecular, rc);
    dc.tu->addFetches(fetched);
    if (k < count && coverage[k])
        processTexturedQuadSse<kDepth, kBlendMode>(dc, t, planes, row, tplanes, trow,
                                                   qx0 + 2 * k, qy, coverage[k], q[0], rc);
}

}  // namespace

template <bool kDepth, int kBlendMode>
void texturedRunAvx2(const DrawContext& dc, const SetupTriangle& t, const sse::Planes& planes,
                     const sse::RowTerms& row, const sse::TexPlanes& tplanes,
                     const sse::TexRowTerms& trow, int qy, int qx0, int count,
                     const uint8_t* coverage, tex::FragmentQuad* q, RasterCounters& rc) {
    texturedRunImpl<kDepth, kBlendMode>(dc, t, planes, row, tplanes, trow, qy, qx0, count,
                                        coverage, q, rc);
}

template <bool kDepth, int kBlendMode>
void quadRunAvx2(const DrawContext& dc, const SetupTriangle& t, const sse::Planes& planes,
                 const sse::RowTerms& row, int qy, int qx0, int count, const uint8_t* coverage,
                 RasterCounters& rc) {
    runAvx2<kDepth, kBlendMode>(dc, t, planes, row, qy, qx0, count, coverage, rc);
}

#define RG_INSTANTIATE(D, B)                                                                 \
    template void quadRunAvx2<D, B>(const DrawContext&, const SetupTriangle&,             \
                                    const sse::Planes&, const sse::RowTerms&, int, int, int, \
                                    const uint8_t*, RasterCounters&);
RG_INSTANTIATE(false, kBlendNone)
RG_INSTANTIATE(false, kBlendGeneric)
RG_INSTANTIATE(false, kBlendSrcAlphaInvSrcAlpha)
RG_INSTANTIATE(false, kBlendOneOne)
RG_INSTANTIATE(true, kBlendNone)
RG_INSTANTIATE(true, kBlendGeneric)
RG_INSTANTIATE(true, kBlendSrcAlphaInvSrcAlpha)
RG_INSTANTIATE(true, kBlendOneOne)
#undef RG_INSTANTIATE
#define RG_INSTANTIATE(D, B)                                                                 \
    template void texturedRunAvx2<D, B>(                                                     \
        const DrawContext&, const SetupTriangle&, const sse::Planes&, const sse::RowTerms&,  \
        const sse::TexPlanes&, const sse::TexRowTerms&, int, int, int, const uint8_t*,       \
        tex::FragmentQuad*, RasterCounters&);
RG_INSTANTIATE(false, kBlendNone)
RG_INSTANTIATE(false, kBlendGeneric)
RG_INSTANTIATE(false, kBlendSrcAlphaInvSrcAlpha)
RG_INSTANTIATE(false, kBlendOneOne)
RG_INSTANTIATE(true, kBlendNone)
RG_INSTANTIATE(true, kBlendGeneric)
RG_INSTANTIATE(true, kBlendSrcAlphaInvSrcAlpha)
RG_INSTANTIATE(true, kBlendOneOne)
#undef RG_INSTANTIATE

}  // namespace rg::raster::detail
