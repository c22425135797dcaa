// Figure 6's choice measured against the reference (tir_choice.h).
#include "tir_choice.h"

#include <algorithm>
#include <memory>

#include "raycore/accel.h"
#include "raycore/tracer_refract_tir.h"
#include "tir_search.h"

namespace rg::tir {

namespace {

// A point-sampled read of an RGBA16F map as the final pass reads it (sampleLevel at level
// 0, NEAREST, clamped to the edge): the texel under (u, v).
struct MapReader {
    const tex::Texture& map;
    Vec4L<float> operator()(float u, float v, bool live) const {
        if (!live) return {0.0f, 0.0f, 0.0f, 1.0f};
        const auto& size = map.levelSize(0);
        const int x = std::clamp(int(std::floor(u * float(size[0]))), 0, size[0] - 1);
        const int y = std::clamp(int(std::floor(v * float(size[1]))), 0, size[1] - 1);
        const glm::vec4 t = map.texelFloat(0, 0, x, y, 0, 0);
        return {t.x, t.y, t.z, t.w};
    }
};

}  // namespace

ChoiceAnalysis analyseFrontBackChoice(TirRenderer& renderer, const TirScene& scene, const ray::Camera& camera,
                                      int size, int bounces) {
    TirSettings s;
    s.width = s.height = size;
    s.bounces = bounces;
    s.frontAndBack = true;
    renderer.render(camera, s);
    const SearchConstants& k = renderer.constants();
    const MapReader back{renderer.backMap()}, front{renderer.frontMap()};

    // The reference: one pixel-centre path per pixel, through the refractor only (what
    // happens after the glass does not matter here).
    ray::Scene without = scene.scene;
    without.objects.erase(without.objects.begin() + scene.refractor);
    ray::Accel accel(scene.scene);
    std::unique_ptr<ray::Accel> accelWithout;
    if (!without.objects.empty()) accelWithout = std::make_unique<ray::Accel>(without);
    ray::TirPathOptions po;
    po.refractor = scene.refractor;
    po.maxSegments = bounces;

    ChoiceAnalysis a;
    a.bounces.resize(size_t(bounces));
    a.image = ray::Image(size * bounces, size, 3);
    const glm::vec3 green(0.1f, 0.8f, 0.2f), blue(0.2f, 0.4f, 1.0f), red(1.0f, 0.1f, 0.1f), yellow(1.0f, 0.9f, 0.1f),
        grey(0.35f);
    ray::RayCounts counts;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const float u = (float(x) + 0.5f) / float(size), v = (float(y) + 0.5f) / float(size);
            const Vec4L<float> f = front(u, v, true);
            const ray::TirPath ref =
                ray::traceTirPath(accel, accelWithout.get(), ray::primaryRay(camera, size, size, u * float(size), v * float(size)),
                                  po, counts);
            if (f.w >= 1.0f || !ref.hitRefractor) continue;  // no refractor, or something stands before it
            ++a.pixels;
            const Vec3L<float> p = unproject(k, u, v, f.w);
            traceInside<float, bool>(k, p, Vec3L<float>(f.x, f.y, f.z), true, back, front,
                                     [&](const BounceChoice<float, bool>& c) {
                                         if (!c.searching) return;
                                         BounceAgreement& b = a.bounces[size_t(c.bounce)];
                                         glm::vec3 colour = grey;
                                         ++b.searching;
                                         if (!c.backValid && !c.frontValid) {
                                             ++b.missed;
                                             colour = yellow;
                                         } else if (ref.insideHits > c.bounce) {
                                             const bool refBack = (ref.backFacing >> c.bounce) & 1u;
                                             const bool right = c.useFront != refBack;
                                             ++b.compared;
                                             b.agree += right;
                                             b.backIsRight += refBack;
                                             b.frontChosen += c.useFront;
                                             b.frontCaught += c.useFront && !refBack;
                                             colour = !right ? red : c.useFront ? blue : green;
                                         }
                                         a.image.setRgb(c.bounce * size + x, y, colour);
                                     });
        }
    return a;
}

}  // namespace rg::tir
