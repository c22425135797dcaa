#include "impostor_peers_workload.h"

#include "core/error.h"
#include "impostor_peers_retroglass.h"
#include "impostor_renderer.h"
#include "impostor_scene.h"

namespace rg::bench::impostor_peers {

namespace {

Cube cubeOf(const tex::Texture& t) {
    Cube c;
    c.size = t.levelSize(0)[0];
    for (int f = 0; f < 6; ++f) {
        const glm::vec4* p = t.dataF(0, f);
        c.faces[size_t(f)].assign(p, p + size_t(c.size) * size_t(c.size));
    }
    return c;
}

Inputs makeInputs(Exit exit) {
    Inputs in;
    in.exit = exit;
    const impostors::ImpostorScene scene = impostors::makeChessScene();
    impostors::ImpostorRenderer renderer(scene);
    impostors::ImpostorSettings s;  // §8's 600², DEPTH 2, 8 iterations, 256² refractor maps
    s.width = kWidth;
    s.height = kHeight;
    s.envSize = kEnvSize;
    s.iterations = kIterations;
    s.mode = impostors::Mode::Static;
    s.exit = exit == Exit::Height ? impostors::Exit::HeightMap : impostors::Exit::DistanceMap;
    renderer.render(scene.camera, s);

    const Rgba8* frame = const_cast<tex::Texture&>(renderer.frameTexture()).renderData8(0, 0);
    in.rendererFrame.assign(reinterpret_cast<const uint8_t*>(frame),
                            reinterpret_cast<const uint8_t*>(frame) + size_t(kWidth) * kHeight * 4);
    const float* depth = renderer.frameDepthTexture().dataR(0, 0);
    in.rendererDepth.assign(depth, depth + size_t(kWidth) * kHeight);
    in.viewProj = renderer.lastViewProj();
    for (int c = 0; c < 3; ++c) in.eye[c] = scene.camera.eye[c];
    in.iterations = s.iterations;
    for (int m = 0; m < renderer.refractorMaps(); ++m) {
        if (exit == Exit::Secant) {
            in.refractors.push_back(cubeOf(renderer.refractorTexture(m)));
        } else {
            const tex::Texture& t = renderer.heightTexture(m);
            HeightMap h;
            h.size = t.levelSize(0)[0];
            h.texels.assign(t.dataF(0, 0), t.dataF(0, 0) + size_t(h.size) * size_t(h.size));
            h.frame = renderer.heightFrame(m);
            in.heights.push_back(std::move(h));
        }
    }
    for (int i : renderer.lastGlassOrder()) {
        Draw d;
        d.frame = renderer.frames().at(size_t(i));
        if (d.frame.mirror) throw Error("impostor peers: the chess scene has a mirror; the GLSL twins have no mirror path");
        d.env = int(in.env.size());
        in.env.push_back(cubeOf(renderer.impostorTexture(i)));
        d.refractor = renderer.refractorOf(i);
        const auto v = renderer.glassVertices(i);
        const auto idx = renderer.glassIndices(i);
        d.firstVertex = uint32_t(in.vertices.size());
        d.vertexCount = uint32_t(v.size());
        d.firstIndex = uint32_t(in.indices.size());
        d.indexCount = uint32_t(idx.size());
        in.vertices.insert(in.vertices.end(), v.begin(), v.end());
        in.indices.insert(in.indices.end(), idx.begin(), idx.end());
        in.draws.push_back(d);
    }
    // The items: one frame of ours counts the programs' invocations.
    ImpostorPeerScene ours(in, 0);
    ours.device.beginFrame();
    ours.frame();
    in.fragmentsPerFrame = int64_t(ours.device.counters().fragmentInvocations);
    return in;
}

}  // namespace

const char* workloadName(Exit e) { return e == Exit::Height ? "impostor_height" : "impostor_secant"; }

const Inputs& inputs(Exit e) {
    if (e == Exit::Height) {
        static const Inputs height = makeInputs(Exit::Height);
        return height;
    }
    static const Inputs secant = makeInputs(Exit::Secant);
    return secant;
}

}  // namespace rg::bench::impostor_peers
