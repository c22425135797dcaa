// Figure 4's comparison search (demos/impostors/reproduce_impostors.cpp): [6]'s linear
// search before the secant steps, from outside. Not the frame's search, which is [5]'s
// (impostor_search.h's outsideSearch); included only by the reproduction and its tests,
// so the frame's kernels do not rebuild with it.
#pragma once

#include <algorithm>
#include <vector>

#include "impostor_search.h"

namespace rg::impostors {

// Figure 4's comparison, not the frame's search: 002 §3 "In [6] linear search is used to
// find the first undershooting and overshooting pair. Then secant search computes a more
// accurate result. We used the method described in [5], which uses only secant search" —
// the frame runs [5]'s (outsideSearch). Here `samples` points evenly along the ray's span
// in the box, from the far side, give the last undershoot (inside the object) and the
// sample after it (or the box's near side) the overshoot: the original ray's first
// crossing bracketed; `iterations` secant steps refine it and outsideSearch's ε test
// decides. No inside sample: a miss. Reads samples + iterations texels (one more where
// the last sample is inside).
template <class Fetch>
inline OutsideHit<float, bool> outsideSearchLinearFirst(
    const Vec3L<float>& y, const Vec3L<float>& R, const float (&lo)[3],
    const float (&hi)[3], float epsilon, int samples, int iterations, Fetch&& fetch) {
    OutsideHit<float, bool> h;
    const BoxSpan<float, bool> box = rayBox<float, bool>(y, R, lo, hi);
    h.boxHit = box.hit;
    h.valid = false;
    h.t = 0.0f;
    h.point = y;
    h.normal = R;
    if (!box.hit) return h;
    const Vec3L<float> x = y + R * box.tFar, back = R * -1.0f;
    const float span = box.tFar - std::max(box.tNear, 0.0f);
    Vec4L<float> texel(0.0f, 0.0f, 0.0f, 0.0f);
    auto ratioAt = [&](float d) {
        const Vec3L<float> p = x + back * d;
        texel = fetch(p, true);
        return distanceRatio(p, texel.w);
    };
    std::vector<float> d(static_cast<size_t>(samples)), a(static_cast<size_t>(samples));
    int last = -1;
    Vec4L<float> lastTexel = texel;
    for (int k = 0; k < samples; ++k) {
        d[size_t(k)] = span * (float(k) + 0.5f) / float(samples);
        a[size_t(k)] = ratioAt(d[size_t(k)]);
        if (a[size_t(k)] < 1.0f) last = k, lastTexel = texel;
    }
    if (last < 0) return h;
    float dU = d[size_t(last)], aU = a[size_t(last)], dO = span, aO;
    if (last + 1 < samples) {
        dO = d[size_t(last) + 1];
        aO = a[size_t(last) + 1];
    } else {
        aO = ratioAt(span);
    }
    // With no iteration the result is the last undershoot itself, read above.
    float dd = dU;
    texel = lastTexel;
    for (int i = 0; i < iterations; ++i) {
        dd = secantStep(dU, aU, dO, aO, 0.5f * (dU + dO));
        const float ad = ratioAt(dd);
        if (ad < 1.0f)
            dU = dd, aU = ad;
        else
            dO = dd, aO = ad;
    }
    const Vec3L<float> p = x + back * dd;
    const Vec3L<float> rel = normalize3(p) * texel.w - y;
    const Vec3L<float> off = rel - R * dot3(rel, R);
    h.t = box.tFar - dd;
    h.point = p;
    h.normal = normalize3(Vec3L<float>(texel.x, texel.y, texel.z));
    h.valid = dot3(off, off) <= epsilon * epsilon && h.t >= 0.0f;
    return h;
}

}  // namespace rg::impostors
