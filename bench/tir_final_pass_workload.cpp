#include "tir_final_pass_workload.h"

#include "tir_final_pass_retroglass.h"
#include "tir_renderer.h"
#include "tir_scene.h"

namespace rg::bench::tir_final_pass {

namespace {

std::vector<glm::vec4> texels(const tex::Texture& t, int face) {
    const auto& size = t.levelSize(0);
    const glm::vec4* p = t.dataF(0, face);
    return std::vector<glm::vec4>(p, p + size_t(size[0]) * size_t(size[1]));
}

Inputs makeInputs() {
    Inputs in;
    const tir::TirScene scene = tir::makeTirScene("kitchen");
    tir::TirRenderer renderer(scene);
    tir::TirSettings s;  // the defaults: 3 bounces, back faces, 8/5/8 iterations, nearby on
    s.width = kWidth;
    s.height = kHeight;
    renderer.render(scene.camera, s);
    in.back = texels(renderer.backMap(), 0);
    in.front = texels(renderer.frontMap(), 0);
    in.nearby = texels(renderer.nearbyMap(), 0);
    const tex::Texture& env = renderer.environmentMap();
    in.envSize = env.levelSize(0)[0];
    for (int f = 0; f < 6; ++f) in.env[size_t(f)] = texels(env, f);
    in.vertices.assign(renderer.refractorVertices().begin(), renderer.refractorVertices().end());
    in.indices.assign(renderer.refractorIndices().begin(), renderer.refractorIndices().end());
    in.vp = renderer.eyeVP();
    in.k = renderer.constants();
    // The items: one frame of ours counts the program's invocations.
    TirFinalPassScene ours(in, 0);
    ours.device.beginFrame();
    ours.frame();
    in.fragmentsPerFrame = int64_t(ours.device.counters().fragmentInvocations);
    return in;
}

}  // namespace

const Inputs& inputs() {
    static const Inputs in = makeInputs();
    return in;
}

}  // namespace rg::bench::tir_final_pass
