// Accel::surfaces eight hits at a time (AVX2, selected at run time; RETROGLASS_NO_AVX2
// keeps the SSE2 kernel). Lane for lane the operations of Accel::surface() in its order:
// every instruction used works per lane (add, sub, mul, div, sqrt, compares, bitwise
// selects) and rounds like its scalar twin; no FMA (target "avx2" only, -ffp-contract=off).
// Checked bit for bit against surface() by tests/raycore/test_accel.cpp.
//
// Data movement is the cost here, not arithmetic, so everything travels as 16-byte rows:
// lanes l and l+4 share a register (one row in each 128-bit half), and an in-half 4×4
// transpose turns four such registers into four fields of all eight hits. The results go
// back the same way, as the first 64 bytes of each SurfacePoint.
#include <immintrin.h>

#include <algorithm>
#include <cstddef>
#include <cstdlib>

#include "core/cpu.h"
#include "raycore/accel.h"

namespace rg::ray {

bool Accel::avx2Available() {
    return avx2Enabled();
}

namespace {

#define RG_AVX2 __attribute__((target("avx2"), always_inline)) inline

// The 16-byte rows at lo (lane l) and hi (lane l+4).
RG_AVX2 __m256 rows(const float* lo, const float* hi) {
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(lo)), _mm_loadu_ps(hi), 1);
}

// _MM_TRANSPOSE4_PS in each 128-bit half.
RG_AVX2 void transpose(__m256& a, __m256& b, __m256& c, __m256& d) {
    const __m256 t0 = _mm256_unpacklo_ps(a, b), t1 = _mm256_unpacklo_ps(c, d);
    const __m256 t2 = _mm256_unpackhi_ps(a, b), t3 = _mm256_unpackhi_ps(c, d);
    a = _mm256_shuffle_ps(t0, t1, 0x44);
    b = _mm256_shuffle_ps(t0, t1, 0xEE);
    c = _mm256_shuffle_ps(t2, t3, 0x44);
    d = _mm256_shuffle_ps(t2, t3, 0xEE);
}

RG_AVX2 __m256 add(__m256 a, __m256 b) { return _mm256_add_ps(a, b); }
RG_AVX2 __m256 mul(__m256 a, __m256 b) { return _mm256_mul_ps(a, b); }
// glm's order: (a.x·b.x + a.y·b.y) + a.z·b.z.
RG_AVX2 __m256 dot(const __m256* a, const __m256* b) {
    return add(add(mul(a[0], b[0]), mul(a[1], b[1])), mul(a[2], b[2]));
}

// Where a lane's hit and ray come from: a Hit and a Ray (surfaces), or the RTCRayHit
// Embree has just filled (intersectStreamSurfaces), whose org, dir, tfar, u and v are the
// very floats intersectStream would copy into the Ray and the Hit.
enum class Source { HitAndRay, EmbreeRayHit };

// surface() of eight hits from their rows: writes the first 48 bytes of dst[0..7] (p, ng,
// ns, uv, frontFace with zeroed padding) and, from Embree's records, the next 16 (object,
// part, triangle, a zero word); the caller writes the rest.
template <Source kSource>
RG_AVX2 void resolveRows(const float* const in[8], const float* const r[8],
                         const float* const ts[8], const float* const g[8], SurfacePoint* dst) {
    const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f);
    const __m256 sign = _mm256_set1_ps(-0.0f);
    const __m256 trueBits = _mm256_castsi256_ps(_mm256_set1_epi32(1));  // bool true, zero padding
    // Inputs, each a 4×4 transpose of 16-byte rows (unused outputs are dead code):
    //   Hit         t u v ·                 RTCRayHit  ox oy oz · | dx dy dz · | tfar · · ·
    //   Ray         ox oy oz dx | dy dz · ·            u v primID geomID (at byte 60)
    //   face normal x y z ·
    //   TriangleRecord n0 n1 n2 uv0 uv1 uv2 part (four rows; the face normal is its fifth)
    //
    // The shading normal's square root and division come first in program order: a group is
    // more instructions than the reorder buffer holds, so whatever follows them in the
    // source is what can run while they are in flight.
    static_assert(offsetof(RTCRayHit, ray.org_x) == 0 && offsetof(RTCRayHit, ray.dir_x) == 16 &&
                  offsetof(RTCRayHit, ray.tfar) == 32 && offsetof(RTCRayHit, hit.u) == 60 &&
                  offsetof(RTCRayHit, hit.v) == 64 && offsetof(RTCRayHit, hit.primID) == 68 &&
                  offsetof(RTCRayHit, hit.geomID) == 72);
    __m256 H[4], F[16];  // Hit rows (t u v ·) or Embree's (u v primID geomID); TriangleRecord
    for (int l = 0; l < 4; ++l) {
        H[l] = kSource == Source::HitAndRay ? rows(in[l], in[l + 4]) : rows(in[l] + 15, in[l + 4] + 15);
        for (int row = 0; row < 4; ++row) F[4 * row + l] = rows(ts[l] + 4 * row, ts[l + 4] + 4 * row);
    }
    transpose(H[0], H[1], H[2], H[3]);
    for (int row = 0; row < 4; ++row)  // F[f] is float f of TriangleRecord
        transpose(F[4 * row], F[4 * row + 1], F[4 * row + 2], F[4 * row + 3]);
    const int first = kSource == Source::HitAndRay ? 1 : 0;
    const __m256 U = H[first], V = H[first + 1];
    const __m256 b0 = _mm256_sub_ps(_mm256_sub_ps(one, U), V);
    __m256 NS[3];
    for (int c = 0; c < 3; ++c) NS[c] = add(add(mul(b0, F[c]), mul(U, F[3 + c])), mul(V, F[6 + c]));
    const __m256 len = _mm256_sqrt_ps(dot(NS, NS));
    const __m256 inv = _mm256_div_ps(one, len);

    // The rest of the inputs.
    __m256 T, O[3], D[3], ids[2];
    if constexpr (kSource == Source::HitAndRay) {
        __m256 R0[4], R1[4];
        for (int l = 0; l < 4; ++l) {
            R0[l] = rows(r[l], r[l + 4]);
            R1[l] = rows(r[l] + 4, r[l + 4] + 4);
        }
        transpose(R0[0], R0[1], R0[2], R0[3]);
        transpose(R1[0], R1[1], R1[2], R1[3]);
        T = H[0];
        O[0] = R0[0], O[1] = R0[1], O[2] = R0[2];
        D[0] = R0[3], D[1] = R1[0], D[2] = R1[1];
    } else {
        __m256 A[4], B[4], C[4];
        for (int l = 0; l < 4; ++l) {
            A[l] = rows(in[l], in[l + 4]);
            B[l] = rows(in[l] + 4, in[l + 4] + 4);
            C[l] = rows(in[l] + 8, in[l + 4] + 8);
        }
        transpose(A[0], A[1], A[2], A[3]);
        transpose(B[0], B[1], B[2], B[3]);
        transpose(C[0], C[1], C[2], C[3]);
        T = C[0];
        O[0] = A[0], O[1] = A[1], O[2] = A[2];
        D[0] = B[0], D[1] = B[1], D[2] = B[2];
        ids[0] = H[3], ids[1] = H[2];  // geomID = object, primID = triangle
    }
    __m256 G[4];
    for (int l = 0; l < 4; ++l) G[l] = rows(g[l], g[l + 4]);
    transpose(G[0], G[1], G[2], G[3]);
    __m256 P[3], UV[2];
    for (int c = 0; c < 3; ++c) P[c] = add(O[c], mul(T, D[c]));
    for (int c = 0; c < 2; ++c)
        UV[c] = add(add(mul(b0, F[9 + c]), mul(U, F[11 + c])), mul(V, F[13 + c]));
    const __m256 positive = _mm256_cmp_ps(len, zero, _CMP_GT_OQ);  // false for NaN, as in surface()
    for (int c = 0; c < 3; ++c) NS[c] = _mm256_blendv_ps(G[c], mul(NS[c], inv), positive);
    const __m256 flip = _mm256_and_ps(_mm256_cmp_ps(dot(NS, G), zero, _CMP_LT_OQ), sign);
    for (int c = 0; c < 3; ++c) NS[c] = _mm256_xor_ps(NS[c], flip);
    const __m256 front = _mm256_and_ps(_mm256_cmp_ps(dot(D, G), zero, _CMP_LT_OQ), trueBits);

    // Outputs: rows (px py pz gx), (gy gz nsx nsy), (nsz u v front) of each lane.
    __m256 O0[4] = {P[0], P[1], P[2], G[0]};
    __m256 O1[4] = {G[1], G[2], NS[0], NS[1]};
    __m256 O2[4] = {NS[2], UV[0], UV[1], front};
    transpose(O0[0], O0[1], O0[2], O0[3]);
    transpose(O1[0], O1[1], O1[2], O1[3]);
    transpose(O2[0], O2[1], O2[2], O2[3]);
    for (int l = 0; l < 4; ++l) {
        float* lo = reinterpret_cast<float*>(&dst[l]);
        float* hi = reinterpret_cast<float*>(&dst[l + 4]);
        _mm_storeu_ps(lo, _mm256_castps256_ps128(O0[l]));
        _mm_storeu_ps(hi, _mm256_extractf128_ps(O0[l], 1));
        _mm_storeu_ps(lo + 4, _mm256_castps256_ps128(O1[l]));
        _mm_storeu_ps(hi + 4, _mm256_extractf128_ps(O1[l], 1));
        _mm_storeu_ps(lo + 8, _mm256_castps256_ps128(O2[l]));
        _mm_storeu_ps(hi + 8, _mm256_extractf128_ps(O2[l], 1));
    }
    if constexpr (kSource == Source::EmbreeRayHit) {
        __m256 O3[4] = {ids[0], F[15], ids[1], zero};  // object, part, triangle, ·
        transpose(O3[0], O3[1], O3[2], O3[3]);
        for (int l = 0; l < 4; ++l) {
            _mm_storeu_ps(reinterpret_cast<float*>(&dst[l]) + 12, _mm256_castps256_ps128(O3[l]));
            _mm_storeu_ps(reinterpret_cast<float*>(&dst[l + 4]) + 12, _mm256_extractf128_ps(O3[l], 1));
        }
    }
}

}  // namespace

__attribute__((target("avx2"))) void Accel::surfacesAvx2(const Ray* rays, const Hit* hits,
                                                         SurfacePoint* out, size_t n) const {
    static_assert(offsetof(SurfacePoint, p) == 0 && offsetof(SurfacePoint, ng) == 12 &&
                  offsetof(SurfacePoint, ns) == 24 && offsetof(SurfacePoint, uv) == 36 &&
                  offsetof(SurfacePoint, frontFace) == 44 && offsetof(SurfacePoint, object) == 48);
    static_assert(offsetof(Hit, t) == 0 && offsetof(Hit, u) == 4 && offsetof(Hit, v) == 8);
    static_assert(offsetof(Ray, origin) == 0 && offsetof(Ray, dir) == 12 && sizeof(Ray) == 32);
    static_assert(offsetof(TriangleRecord, uv) == 36 && offsetof(TriangleRecord, part) == 60 &&
                  offsetof(TriangleRecord, faceNormal) == 64);
    // Lanes without a hit (misses, the end of a partial group) read these harmless values
    // and become SurfacePoint() afterwards.
    static const Hit noHit{};
    static const Ray noRay{};
    static const TriangleRecord noShading{};
    alignas(16) static const float noNormal[4] = {0.0f, 1.0f, 0.0f, 0.0f};
    for (size_t base = 0; base < n; base += 8) {
        const size_t m = std::min<size_t>(8, n - base);
        const float* h[8];
        const float* r[8];
        const float* ts[8];
        const float* g[8];
        bool valid[8];
        for (size_t l = 0; l < 8; ++l) {
            valid[l] = l < m && hits[base + l].valid();
            const Hit& hit = valid[l] ? hits[base + l] : noHit;
            const TriangleRecord* rec =
                valid[l] ? &record(hit.object, hit.triangle) : &noShading;
            h[l] = &hit.t;
            r[l] = valid[l] ? &rays[base + l].origin.x : &noRay.origin.x;
            ts[l] = &rec->normal[0].x;
            g[l] = valid[l] ? &rec->faceNormal.x : noNormal;
        }
        auto finish = [&](SurfacePoint* dst) {
            for (size_t l = 0; l < m; ++l) {
                SurfacePoint& s = dst[l];
                if (!valid[l]) {
                    s = SurfacePoint();
                    continue;
                }
                const Hit& hit = hits[base + l];
                s.object = hit.object;
                s.part = record(hit.object, hit.triangle).part;
                s.triangle = hit.triangle;
                s.material = geometries_[hit.object].material;
            }
        };
        if (m == 8) {
            resolveRows<Source::HitAndRay>(h, r, ts, g, out + base);
            finish(out + base);
        } else {  // a partial group: all eight lanes written to a scratch group
            SurfacePoint partial[8];
            resolveRows<Source::HitAndRay>(h, r, ts, g, partial);
            finish(partial);
            std::copy(partial, partial + m, out + base);
        }
    }
}

__attribute__((target("avx2"))) void Accel::resolveStreamAvx2(const RTCRayHit* rh, SurfacePoint* out,
                                                              size_t n, bool prefetchAhead) const {
    static_assert(offsetof(SurfacePoint, part) == 52 && offsetof(SurfacePoint, triangle) == 56 &&
                  offsetof(SurfacePoint, material) == 64 && sizeof(SurfacePoint) == 72);
    static const TriangleRecord noShading{};
    alignas(16) static const float noNormal[4] = {0.0f, 1.0f, 0.0f, 0.0f};
    // The records of the hits four groups ahead are requested before each group is
    // resolved: after a stream's traversal they are no longer in L1 (primary rays) or
    // never were (secondary). Measured (in-process A/B, modes rotated between rounds,
    // minimum of 12 rounds per quarter of the bench's rays, ns per ray of
    // intersectStreamSurfaces, primary / secondary): none 41.1 / 132.5, 32 ahead
    // 38.6 / 130.7 (24: 39.9 / 135.0 against 42.2 / 136.8 in another run, 48: 39.4 /
    // 133.8), where the bare rtcIntersect1M loop took 33.9 / 121.0.
    auto prefetch = [&](size_t i) {
        if (i < n) prefetchRecord(rh[i]);
    };
    // (intersectSurfaces has prefetched each record as Embree returned it: prefetchAhead
    // false.)
    const size_t ahead = prefetchAhead ? 32 : 0;
    for (size_t i = 0; i < ahead; ++i) prefetch(i);
    for (size_t base = 0; base < n; base += 8) {
        const size_t m = std::min<size_t>(8, n - base);
        if (prefetchAhead)
            for (size_t i = base + ahead; i < base + ahead + 8; ++i) prefetch(i);
        const float* in[8];
        const float* ts[8];
        const float* g[8];
        const Material* material[8];
        bool valid[8];
        for (size_t l = 0; l < 8; ++l) {
            const RTCRayHit& x = rh[base + (l < m ? l : 0)];  // past the end: any record
            valid[l] = l < m && x.hit.geomID != RTC_INVALID_GEOMETRY_ID;
            const Geometry* geo = valid[l] ? &geometries_[x.hit.geomID] : nullptr;
            const TriangleRecord* rec = valid[l] ? &records_[geo->base + x.hit.primID] : &noShading;
            in[l] = &x.ray.org_x;
            ts[l] = &rec->normal[0].x;
            g[l] = valid[l] ? &rec->faceNormal.x : noNormal;
            material[l] = valid[l] ? geo->material : nullptr;
        }
        auto finish = [&](SurfacePoint* dst) {
            for (size_t l = 0; l < m; ++l) {
                if (valid[l])
                    dst[l].material = material[l];
                else
                    dst[l] = SurfacePoint();
            }
        };
        if (m == 8) {
            resolveRows<Source::EmbreeRayHit>(in, nullptr, ts, g, out + base);
            finish(out + base);
        } else {
            SurfacePoint partial[8];
            resolveRows<Source::EmbreeRayHit>(in, nullptr, ts, g, partial);
            finish(partial);
            std::copy(partial, partial + m, out + base);
        }
    }
}

}  // namespace rg::ray
