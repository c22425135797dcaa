// The lightfield reproduction: Figures 3, 4, 5 and colour plates 1–3 of Heidrich et al. 1999
// against the ray tracer, the frame rates of §3–§4, the memory of §5, the claims, the report.
#include "reproduce_lightfield.h"

#include <glm/gtc/matrix_transform.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "core/error.h"
#include "core/progress.h"
#include "figure6.h"
#include "figures.h"
#include "gortler_renderer.h"
#include "lf4d_renderer.h"
#include "lightfield_demo.h"
#include "lightfield_scene.h"
#include "lf_capture.h"
#include "lookup.h"
#include "raycore/accel.h"
#include "raycore/fresnel.h"
#include "raycore/image.h"
#include "raycore/metrics.h"
#include "raycore/scene_json.h"
#include "raycore/shapes.h"
#include "rasterizer/trace.h"
#include "report.h"
#include "vq.h"

namespace fs = std::filesystem;

namespace rg::lightfield {

namespace {

using Clock = std::chrono::steady_clock;
using demos::num;

// Margins of the claims (docs/reports.md, "Margins"). The renders are deterministic; a margin
// is the size a difference must have to be the paper's effect rather than a rounding
// accident or the choice of view.
// - PSNR orderings, 0.5 dB. This reproduction evaluates one view, so it has no spread of its
//   own across views; the same measurement in hybrid and tir moves by at most 0.2 dB under a
//   change that should not matter (hybrid's multi-layer frame from the sample's view to
//   between samples; tir's front-face search added where it changes few pixels),
//   and the emulated passes themselves
//   add far less here (the all-halved VQ frame against its own decoded light field drawn the
//   uncompressed way: 46 dB at quick quality, a change of under 0.01 dB at 19 dB). Every
//   PSNR ordering of the paper uses the one margin (colour plate 3's (u, v) against all
//   halved had 0.25 dB and the lighting 1 dB before, neither from a measured spread).
constexpr double kMarginDb = 0.5;
// - "About four times" the cost: colour-pass fragments are exact counts, so the tolerance
//   is the word "about": ±0.5×, an eighth of the ratio.
constexpr double kCostTolerance = 0.5;
// - The Gortler weights: three 8-bit vertex weights, each rounded by up to ½ LSB, sum in the
//   blender with its own rounding: up to 2 LSB from rounding alone.
constexpr double kWeightToleranceLsb = 2.0;

double seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }

template <class F>
void parallelRowsOf(int threads, int n, F&& f) {
    tbb::task_arena arena(threads > 0 ? threads : tbb::this_task_arena::max_concurrency());
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, n), [&](const tbb::blocked_range<int>& r) {
            for (int y = r.begin(); y != r.end(); ++y) f(y);
        });
    });
}

// A ray-traced reference: per pixel n×n camera rays, colour(ray, &hit) averaged; the mask
// is 1 where every sample hit the object.
struct Truth {
    ray::Image color, mask;
};
Truth traceTruth(const ray::Camera& cam, int size, int n, int threads,
                 const std::function<glm::vec3(const ray::Ray&, bool&)>& colour) {
    Truth t{ray::Image(size, size, 3), ray::Image(size, size, 1)};
    parallelRowsOf(threads, size, [&](int y) {
        for (int x = 0; x < size; ++x) {
            glm::vec3 sum(0.0f);
            int hits = 0;
            for (int sy = 0; sy < n; ++sy)
                for (int sx = 0; sx < n; ++sx) {
                    const glm::vec2 p = ray::samplePosition(x, y, sx, sy, n);
                    bool hit = false;
                    sum += colour(ray::primaryRay(cam, size, size, p.x, p.y), hit);
                    hits += hit;
                }
            t.color.setRgb(x, y, sum / float(n * n));
            t.mask.at(x, y, 0) = hits == n * n ? 1.0f : 0.0f;
        }
    });
    return t;
}

ray::Image imageOf(const std::vector<Rgba8>& px, int w, int h) {
    ray::Image im(w, h, 3);
    for (int i = 0; i < w * h; ++i) {
        im.pixels[size_t(3 * i)] = px[size_t(i)].r / 255.0f;
        im.pixels[size_t(3 * i + 1)] = px[size_t(i)].g / 255.0f;
        im.pixels[size_t(3 * i + 2)] = px[size_t(i)].b / 255.0f;
    }
    return im;
}

std::string sha(const std::vector<Rgba8>& px) { return raster::sha256Hex(px.data(), px.size() * sizeof(Rgba8)); }

nlohmann::json scoreJson(const ray::MaskedScore& s) { return {{"psnr_db", s.psnr}, {"ssim", s.ssim}, {"pixels", s.pixels}}; }

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

// One frame of a route on a device of `profile` at size², timed.
struct Frame {
    std::vector<Rgba8> pixels;   // the final framebuffer
    std::vector<Rgba8> coords;   // the read-back (colour-coded coordinates)
    GortlerStats gortler;
    double ms = 0, gortlerMs = 0, readMs = 0, lookupMs = 0, writeMs = 0;
    uint64_t uploadBytes = 0, bytesReadBack = 0, fragments = 0;
};

}  // namespace

LightfieldSettings lightfieldSettingsFor(demos::Quality quality) {
    LightfieldSettings s;
    if (quality == demos::Quality::Paper) {
        s.imageSize = 400;
        s.truthSpp = 3;
        s.timingFrames = 20;
        s.geoS = 32;
        s.geoU = 128;
        s.radS = 32;
        s.radU = 128;
        s.vqK = 65536;           // §5: "the table size as 2^16"
        s.vqKOther = 65536;      // the same for the (s, t)- and (u, v)-halved variants: plate 3 compares equal codebooks
                                 // (their 2^22 blocks encode in about 4.5 min each on 2 loaded cores, docs/performance.md)
        s.vqTraining = 131072;   // an eighth of the 2^20 blocks, 2 per codeword
        s.vqIterations = 3;
        s.glossySize = 128;
    }
    return s;
}

nlohmann::json runLightfield(const LightfieldSettings& S, const demos::ReproduceOptions& options) {
    const auto tStart = Clock::now();
    const fs::path out = options.outDir;
    fs::create_directories(out);
    const int threads = S.threads;
    const Path rasterPath = options.referencePath ? Path::Reference : Path::Fast;
    const raster::DeviceOptions devOpt{rasterPath, threads};
    const Profile& octane = profile(ProfileId::SgiOctaneMxe);
    const Profile& o2 = profile(ProfileId::SgiO2);
    demos::Report rep(lightfieldReproduction(), options.quality);
    nlohmann::json r;
    Progress progress("lightfield", 7);

    // ---- scene, environments, the geometry light field ------------------------------------
    const LfScene sc = makeScene(options.scene);
    const ray::Accel accel(sc.scene);
    const float expA = autoExposure(sc.envA), expB = autoExposure(sc.envB);
    auto t0 = Clock::now();
    const ParaboloidMap envA = makeParaboloidMap(sc.envA, S.envSize, expA, 2);
    const ParaboloidMap envB = makeParaboloidMap(sc.envB, S.envSize, expB, 2);
    const double envSeconds = seconds(t0);
    LightSlab gslab = geometrySlab(S.geoS, S.geoU);
    validateSlab(gslab, sc.bounds, "lightfield: the geometry slab");
    t0 = Clock::now();
    LightField geo = captureParaboloidField(accel, sc.object, gslab, sc.mode, sc.ior, threads);
    geo.objectBounds = sc.bounds;
    const double geoSeconds = seconds(t0);
    // The parameter file, written and read back (the data the renderers use is the read one).
    writeLightField(out / "geometry_lightfield.json", geo);
    geo = readLightField(out / "geometry_lightfield.json");
    progress.advance();

    const int N = S.imageSize;
    const ray::Camera cam = evalCamera(0);
    // ---- §4: the two routes, environment A then B, against the ray tracer -----------------
    auto octaneMem = std::make_shared<tex::TextureMemory>(octane);
    auto envTexA = uploadParaboloidMap(*octaneMem, envA);
    SliceTextures geoSlices(octaneMem, geo);
    const HostTexture hostA = hostParaboloidMap(envA), hostB = hostParaboloidMap(envB);
    const SoftwareLookup swA(hostA, true), swB(hostB, true);

    auto pixelTextureFrame = [&](raster::Device& dev, SliceTextures& slices, std::shared_ptr<const tex::Texture> env,
                                 const ray::Camera& c) {
        Frame f;
        const auto a = Clock::now();
        dev.beginFrame();
        dev.beginPass("geometry light field (Gortler)");
        f.gortler = renderGortler(dev, slices, geo, c);
        const auto b = Clock::now();
        dev.beginPass("read back");
        f.coords = dev.readPixels(0, 0, dev.framebuffer().width(), dev.framebuffer().height());
        const auto d = Clock::now();
        dev.beginPass("pixel texture lookup");
        pixelTextureLookup(dev, env, tex::PixelTexGenMode::Rgb, f.coords);
        dev.endFrame();
        const auto e = Clock::now();
        f.gortlerMs = std::chrono::duration<double, std::milli>(b - a).count();
        f.readMs = std::chrono::duration<double, std::milli>(d - b).count();
        f.lookupMs = std::chrono::duration<double, std::milli>(e - d).count();
        f.ms = std::chrono::duration<double, std::milli>(e - a).count();
        f.pixels = dev.readPixels(0, 0, dev.framebuffer().width(), dev.framebuffer().height());
        f.uploadBytes = dev.textureUnits().counters().uploadBytes;
        f.fragments = dev.counters().fragmentsGenerated;
        return f;
    };
    auto softwareFrame = [&](raster::Device& dev, SliceTextures& slices, const SoftwareLookup& sw, const ray::Camera& c) {
        Frame f;
        const auto a = Clock::now();
        dev.beginFrame();
        dev.beginPass("geometry light field (Gortler)");
        f.gortler = renderGortler(dev, slices, geo, c);
        const auto b = Clock::now();
        f.coords = dev.readPixels(0, 0, dev.framebuffer().width(), dev.framebuffer().height());
        const auto d = Clock::now();
        std::vector<Rgba8> px = f.coords;
        sw.apply(px, threads);
        const auto e = Clock::now();
        dev.beginPass("write back");
        dev.drawPixels(0, 0, dev.framebuffer().width(), dev.framebuffer().height(), px);
        dev.endFrame();
        const auto g = Clock::now();
        f.gortlerMs = std::chrono::duration<double, std::milli>(b - a).count();
        f.readMs = std::chrono::duration<double, std::milli>(d - b).count();
        f.lookupMs = std::chrono::duration<double, std::milli>(e - d).count();
        f.writeMs = std::chrono::duration<double, std::milli>(g - e).count();
        f.ms = std::chrono::duration<double, std::milli>(g - a).count();
        f.pixels = std::move(px);
        f.uploadBytes = dev.textureUnits().counters().uploadBytes;
        return f;
    };

    raster::Device octDev(octane, N, N, raster::DepthFormat::D24, devOpt);
    octDev.textureUnits().setTextureMemory(octaneMem);
    const Frame ptA = pixelTextureFrame(octDev, geoSlices, envTexA, cam);
    auto o2Mem = std::make_shared<tex::TextureMemory>(o2);
    SliceTextures geoSlicesO2(o2Mem, geo);
    raster::Device o2Dev(o2, N, N, raster::DepthFormat::D24, devOpt);
    o2Dev.textureUnits().setTextureMemory(o2Mem);
    const Frame swFrameA = softwareFrame(o2Dev, geoSlicesO2, swA, cam);
    // Environment B: the same light field, only the map is uploaded.
    const uint64_t residentBefore = octaneMem->residentBytes();
    octaneMem->resetFrameCounters();
    envTexA.reset();
    auto envTexB = uploadParaboloidMap(*octaneMem, envB);
    const uint64_t swapUpload = octaneMem->uploadBytes();
    const Frame ptB = pixelTextureFrame(octDev, geoSlices, envTexB, cam);
    const Frame swFrameB = softwareFrame(o2Dev, geoSlicesO2, swB, cam);
    size_t routeDiff = 0;
    for (size_t i = 0; i < ptA.pixels.size(); ++i) {
        routeDiff += !(ptA.pixels[i] == swFrameA.pixels[i]);
        routeDiff += !(ptB.pixels[i] == swFrameB.pixels[i]);
    }
    // Truth: the exact exit ray of each sample, looked up in the same 8-bit map.
    auto envTruth = [&](const ParaboloidMap& map) {
        return traceTruth(cam, N, S.truthSpp, threads, [&](const ray::Ray& ry, bool& hit) {
            const ExitRay x = traceExit(accel, sc.object, ry, sc.mode, sc.ior);
            hit = x.hit;
            return sampleParaboloidMap(map, x.dir);
        });
    };
    const Truth truthA = envTruth(envA), truthB = envTruth(envB);
    const std::string objName = "lightfield: the object '" + sc.scene.objects[sc.object].name + "'";
    const ray::MaskedScore scoreA = ray::compareMasked(truthA.color, imageOf(ptA.pixels, N, N), truthA.mask, objName + " (environment A)");
    const ray::MaskedScore scoreB = ray::compareMasked(truthB.color, imageOf(ptB.pixels, N, N), truthB.mask, objName + " (environment B)");
    // The Gortler weights: an RGB light field's alpha after the reconstruction is Σ weights.
    int maxWeightError = 0;
    int64_t hullPixels = 0;
    {
        // Pixels whose camera ray crosses the (s, t) plane inside the eye-point grid (and
        // not within a pixel of its edge).
        for (int y = 0; y < N; ++y)
            for (int x = 0; x < N; ++x) {
                const ray::Ray ry = ray::primaryRay(cam, N, N, x + 0.5f, y + 0.5f);
                const auto st = gslab.intersect(ry.origin, ry.dir);
                const float m = 0.02f * (gslab.stMax.x - gslab.stMin.x);
                if (!st || st->x < gslab.stMin.x + m || st->x > gslab.stMax.x - m || st->y < gslab.stMin.y + m || st->y > gslab.stMax.y - m)
                    continue;
                ++hullPixels;
                maxWeightError = std::max(maxWeightError, std::abs(int(ptA.coords[size_t(y) * N + x].a) - 255));
            }
    }
    // The broken triangulation, for the figure: Σ weights with per-eye-point diagonals.
    std::vector<Rgba8> brokenCoords;
    {
        octDev.beginFrame();
        GortlerOptions go;
        go.triangulation = Triangulation::PerEyePointDiagonals;
        renderGortler(octDev, geoSlices, geo, cam, go);
        octDev.endFrame();
        brokenCoords = octDev.readPixels(0, 0, N, N);
    }
    r["environment_route"] = {
        {"environment_a", sc.envAName}, {"environment_b", sc.envBName},
        {"exposure_a", expA}, {"exposure_b", expB},
        {"psnr_vs_raytracer_a", scoreJson(scoreA)}, {"psnr_vs_raytracer_b", scoreJson(scoreB)},
        {"pixel_texture_sha256_a", sha(ptA.pixels)}, {"software_sha256_a", sha(swFrameA.pixels)},
        {"pixel_texture_sha256_b", sha(ptB.pixels)}, {"software_sha256_b", sha(swFrameB.pixels)},
        {"differing_pixels", routeDiff},
        {"environment_swap_upload_bytes", swapUpload},
        // The light field's bytes uploaded in the frames before and after the swap: 0 when it
        // is resident, every slice each frame when it does not fit (swap or not).
        {"environment_swap_light_field_upload_bytes", ptB.uploadBytes},
        {"light_field_upload_bytes_per_frame_before_swap", ptA.uploadBytes},
        {"light_field_recompute_seconds", geoSeconds},
        {"environment_resample_seconds", envSeconds},
        {"octane_texture_bytes_resident", residentBefore},
        {"light_field_resident_on_octane", geoSlices.resident()},
        {"gortler_weight_max_error_lsb", maxWeightError}, {"gortler_hull_pixels", hullPixels},
        {"read_back_bytes_per_frame_400", uint64_t(S.timingSize) * S.timingSize * 4}};
    // Figure 3 / colour plate 1.
    {
        std::vector<demos::Cell> cells = {
            {imageOf(ptA.coords, N, N), "colour-coded (s, t, side)"},
            {imageOf(ptA.pixels, N, N), "final, " + sc.envAName},
            {imageOf(ptB.pixels, N, N), "final, " + sc.envBName + " (same light field)"},
            {demos::masked(truthA.color, truthA.mask), "ray traced, " + sc.envAName},
            {imageOf(swFrameA.pixels, N, N), "O2 software route, " + sc.envAName},
            {demos::masked(truthB.color, truthB.mask), "ray traced, " + sc.envBName}};
        ray::writeImage(out / "figure3.png", demos::labelledGrid(cells, 3));
        ray::Image sum(N, N, 3), broken(N, N, 3);
        for (int i = 0; i < N * N; ++i) {
            const float a = ptA.coords[size_t(i)].a / 255.0f, b = brokenCoords[size_t(i)].a / 255.0f;
            sum.setRgb(i % N, i / N, glm::vec3(a));
            broken.setRgb(i % N, i / N, b > 1.0f - 1e-6f ? glm::vec3(1, 0.2f, 0.2f) : glm::vec3(b));
        }
        ray::writeImage(out / "triangulation.png",
                        demos::labelledGrid({{sum, "sum of weights, one fixed diagonal"}, {broken, "sum of weights, diagonals per eye point (red: saturated)"}}, 2));
    }
    progress.advance();

    // ---- frame rates at 400×400 (§4: Octane 15–20 fps, O2 about 10) ------------------------
    nlohmann::json fps;
    {
        const int T = S.timingSize;
        raster::Device od(octane, T, T, raster::DepthFormat::None, devOpt);
        od.textureUnits().setTextureMemory(octaneMem);
        raster::Device sd(o2, T, T, raster::DepthFormat::None, devOpt);
        sd.textureUnits().setTextureMemory(o2Mem);
        const ray::Camera tc = evalCamera(1);
        auto timeRoute = [&](const std::function<Frame()>& f) {
            f();  // warm-up
            std::vector<double> ms, g, rd, lk;
            Frame last;
            for (int k = 0; k < S.timingFrames; ++k) {
                last = f();
                ms.push_back(last.ms);
                g.push_back(last.gortlerMs);
                rd.push_back(last.readMs);
                lk.push_back(last.lookupMs + last.writeMs);
            }
            const double m = median(ms);
            return nlohmann::json{{"fps", 1000.0 / m}, {"frame_ms", m}, {"gortler_ms", median(g)}, {"read_back_ms", median(rd)},
                                  {"lookup_ms", median(lk)}, {"upload_bytes_per_frame", last.uploadBytes},
                                  {"eye_points", last.gortler.eyePoints}};
        };
        fps["pixel_texture_sgi_octane_mxe"] = timeRoute([&] { return pixelTextureFrame(od, geoSlices, envTexB, tc); });
        fps["software_sgi_o2"] = timeRoute([&] { return softwareFrame(sd, geoSlicesO2, swB, tc); });
        fps["threads"] = threads > 0 ? threads : int(std::thread::hardware_concurrency());
        fps["size"] = T;
    }
    r["frame_rates_400"] = fps;
    progress.advance();

    // ---- §4.2, Fig. 4: glossy reflection + refraction, each weighted by Fresnel -----------
    nlohmann::json fig4;
    {
        t0 = Clock::now();
        const ParaboloidMap glossy = prefilterPhong(envA, S.glossySize, S.glossyExponent, threads);
        const double prefilterSeconds = seconds(t0);
        auto glossyTex = uploadParaboloidMap(*octaneMem, glossy);
        auto envTexA2 = uploadParaboloidMap(*octaneMem, envA);
        const ray::Mesh mesh = sc.scene.worldMesh(sc.object);
        // Per vertex: position, the reflection direction's paraboloid coordinates (s, t, side)
        // and the Fresnel weight from the camera.
        auto meshVertices = [&](bool reflection) {
            std::vector<raster::Vertex> vs;
            vs.reserve(mesh.indices.size());
            for (uint32_t idx : mesh.indices) {
                raster::Vertex v;
                const glm::vec3 p = mesh.positions[idx];
                glm::vec3 n = glm::normalize(mesh.normals[idx]);
                const glm::vec3 d = glm::normalize(p - cam.eye);
                if (glm::dot(n, d) > 0) n = -n;
                const float F = ray::FresnelDielectric(std::max(0.0f, -glm::dot(d, n)), 1.0f, sc.ior);
                v.position = glm::vec4(p, 1.0f);
                const uint8_t f8 = uint8_t(std::lround(255.0f * (reflection ? F : 1.0f - F)));
                v.diffuse = {f8, f8, f8, f8};
                const ParaboloidCoord pc = toParaboloid(ray::reflectDir(d, n));
                v.tex[0] = glm::vec4(pc.s, pc.t, float(pc.side), 1.0f);
                vs.push_back(v);
            }
            return vs;
        };
        const std::vector<raster::Vertex> reflV = meshVertices(true), refrV = meshVertices(false);
        auto drawMesh = [&](raster::Device& dev, bool reflectionPart) {
            // Depth pre-pass, then the weight pass (refraction: rgb ·= 1 − F) or the
            // reflection pass (rgb += F·glossy), depth EQUAL so each pixel's front surface
            // is drawn once.
            tex::TextureUnits& tu = dev.textureUnits();
            raster::PipelineState st;
            st.cull = raster::CullMode::None;
            st.depthFunc = raster::CompareFunc::Less;
            st.colorWriteMask = 0;
            dev.clear(false, {}, true, 1.0f);
            dev.setState(st);
            tu.setStage(0, tex::StageState{});  // untextured
            dev.beginPass("mesh depth");
            dev.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed, refrV);
            st.depthFunc = raster::CompareFunc::Equal;
            st.depthWrite = 0;
            st.blend = 1;
            st.colorWriteMask = raster::kWriteR | raster::kWriteG | raster::kWriteB;
            if (!reflectionPart) {
                st.srcBlend = raster::BlendFactor::Zero;
                st.dstBlend = raster::BlendFactor::SrcAlpha;
                dev.setState(st);
                dev.beginPass("refraction × (1 − F)");
                dev.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed, refrV);
            } else {
                st.srcBlend = raster::BlendFactor::One;
                st.dstBlend = raster::BlendFactor::One;
                dev.setState(st);
                tex::SamplerState s;
                s.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge};
                tu.setSampler(0, s);
                tu.setTexture(0, glossyTex);
                tex::TexGenState tg;
                tg.projected = true;
                tu.setTexGen(0, tg);
                tu.setStage(0, tex::texEnvStage(tex::TexEnvMode::Modulate, tex::BaseFormat::Rgb));
                dev.beginPass("F × glossy reflection");
                dev.draw(raster::Primitive::TriangleList, raster::VertexSpace::Untransformed, reflV);
                tu.setStage(0, tex::StageState{});
            }
        };
        raster::Device dev(octane, N, N, raster::DepthFormat::D24, devOpt);
        dev.textureUnits().setTextureMemory(octaneMem);
        dev.setTransforms(glm::mat4(1.0f), viewMatrix(cam), projectionMatrix(cam, N, N));
        // Left: the reflection part alone.
        dev.beginFrame();
        dev.clear(true, {0, 0, 0, 0}, true, 1.0f);
        drawMesh(dev, true);
        dev.endFrame();
        const std::vector<Rgba8> left = dev.readPixels(0, 0, N, N);
        // Centre: the refraction route, weighted.
        Frame refr = pixelTextureFrame(dev, geoSlices, envTexA2, cam);
        dev.setTransforms(glm::mat4(1.0f), viewMatrix(cam), projectionMatrix(cam, N, N));
        drawMesh(dev, false);
        const std::vector<Rgba8> centre = dev.readPixels(0, 0, N, N);
        // Right: both.
        drawMesh(dev, true);
        const int passes = int(dev.passes().size());
        const std::vector<Rgba8> right = dev.readPixels(0, 0, N, N);
        // The ray-traced composite: F at the first hit × glossy(reflection) + (1 − F) × env(exit).
        const Truth truth = traceTruth(cam, N, S.truthSpp, threads, [&](const ray::Ray& ry, bool& hit) {
            const ExitRay x = traceExit(accel, sc.object, ry, sc.mode, sc.ior);
            hit = x.hit;
            if (!x.hit) return sampleParaboloidMap(envA, ry.dir);
            return x.fresnel * sampleParaboloidMap(glossy, ray::reflectDir(ry.dir, x.normal)) +
                   (1.0f - x.fresnel) * sampleParaboloidMap(envA, x.dir);
        });
        const ray::MaskedScore s4 = ray::compareMasked(truth.color, imageOf(right, N, N), truth.mask, objName + " (Fig. 4 composite)");
        ray::writeImage(out / "figure4.png",
                        demos::labelledGrid({{imageOf(left, N, N), "glossy reflection x F (mesh, prefiltered map)"},
                                             {imageOf(centre, N, N), "refraction light field x (1 - F)"},
                                             {imageOf(right, N, N), "sum"},
                                             {demos::masked(truth.color, truth.mask), "ray traced composite"}},
                                            4));
        fig4 = {{"psnr_vs_raytracer", scoreJson(s4)}, {"passes", passes}, {"prefilter_seconds", prefilterSeconds},
                {"glossy_exponent", S.glossyExponent}, {"glossy_size", S.glossySize}};
    }
    r["figure4_fresnel"] = fig4;
    progress.advance();

    // ---- §4.1: lighting from a second light field (4D pixel texture) ---------------------
    nlohmann::json lit;
    {
        // A near backdrop: a checkered wall at z = −3 and three boxes in front of it, lit by
        // ambient light and one direction (no shadows: the ray tracer and both maps agree).
        ray::Scene back;
        ray::Material m;
        m.type = ray::MaterialType::Diffuse;
        const uint32_t wall = back.addMesh(ray::makeCube(1.0f));
        const uint32_t mw = back.addMaterial(m);
        back.addObject("wall", wall, mw, glm::translate(glm::mat4(1.0f), glm::vec3(0, 0, -3.2f)) * glm::scale(glm::mat4(1.0f), glm::vec3(8, 8, 0.2f)));
        const glm::vec3 boxPos[3] = {{-1.1f, 0.6f, -2.3f}, {0.9f, -0.7f, -2.0f}, {0.4f, 1.1f, -2.6f}};
        for (int k = 0; k < 3; ++k)
            back.addObject("box" + std::to_string(k), wall, mw, glm::translate(glm::mat4(1.0f), boxPos[k]) * glm::scale(glm::mat4(1.0f), glm::vec3(0.35f)));
        const ray::Accel backAccel(back);
        const glm::vec3 boxColor[3] = {{0.9f, 0.2f, 0.15f}, {0.2f, 0.75f, 0.25f}, {0.25f, 0.35f, 0.95f}};
        const glm::vec3 light = glm::normalize(glm::vec3(0.4f, 0.6f, 1.0f));
        auto backdrop = [&](const ray::Ray& ry) -> glm::vec3 {
            const ray::SurfacePoint sp = backAccel.intersectSurface(ry);
            if (sp.object == ray::kNoHit) return glm::vec3(0.0f);
            glm::vec3 albedo;
            if (sp.object == 0) {
                const int cx = int(std::floor(sp.p.x * 2.0f)), cy = int(std::floor(sp.p.y * 2.0f));
                albedo = ((cx + cy) & 1) ? glm::vec3(0.85f, 0.8f, 0.6f) : glm::vec3(0.15f, 0.12f, 0.2f);
            } else {
                albedo = boxColor[sp.object - 1];
            }
            glm::vec3 n = sp.ns;
            if (glm::dot(n, ry.dir) > 0) n = -n;
            return albedo * (0.35f + 0.65f * std::max(0.0f, glm::dot(n, light)));
        };
        LightSlab lslab;
        lslab.stZ = -1.45f;
        lslab.uvZ = -3.1f;
        lslab.stMin = glm::vec2(-2.0f);
        lslab.stMax = glm::vec2(2.0f);
        lslab.uvMin = glm::vec2(-4.0f);
        lslab.uvMax = glm::vec2(4.0f);
        lslab.S = lslab.T = S.lightS;
        lslab.U = lslab.V = S.lightU;
        t0 = Clock::now();
        const LightField lighting = captureRadianceField(lslab, backdrop, threads);
        LightSlab g2 = geometrySlab(S.lightGeoS, S.lightGeoU);
        const LightField geo4 = captureSlabField(accel, sc.object, g2, lslab, sc.mode, sc.ior, threads);
        const double lfSeconds = seconds(t0);
        // The environment-map alternative: the backdrop seen from the object's centre.
        const glm::vec3 centre = sc.bounds.center();
        const ParaboloidMap nearMap = makeParaboloidMap(
            [&](glm::vec3 d) {
                ray::Ray ry;
                ry.origin = centre;
                ry.dir = d;
                return backdrop(ry);
            },
            S.envSize, 2, threads);
        // On the Octane: both light fields resident (RGBA8 geometry + RGB8 4D lighting).
        auto mem = std::make_shared<tex::TextureMemory>(octane);
        auto lightTex = mem->create({tex::TextureTarget::Texture4D, tex::TexelFormat::RGB8, lslab.U, lslab.V, lslab.S, lslab.T, 1});
        {
            // The 4D texture's texel (x, y, z, w) = (u, v, s, t): the light field's own order.
            mem->upload(*lightTex, 0, 0, lighting.data);
        }
        SliceTextures slices(mem, geo4);
        raster::Device dev(octane, N, N, raster::DepthFormat::None, devOpt);
        dev.textureUnits().setTextureMemory(mem);
        dev.beginFrame();
        dev.beginPass("geometry light field (u, v, s, t)");
        renderGortler(dev, slices, geo4, cam);
        const std::vector<Rgba8> coords4 = dev.readPixels(0, 0, N, N);
        dev.beginPass("pixel texture into the 4D lighting light field");
        pixelTextureLookup(dev, lightTex, tex::PixelTexGenMode::Rgba, coords4);
        dev.endFrame();
        const std::vector<Rgba8> viaLf = dev.readPixels(0, 0, N, N);
        const HostTexture host4 = hostLightField4D(lighting);
        const SoftwareLookup sw4(host4, false);
        std::vector<Rgba8> viaSw = coords4;
        sw4.apply(viaSw, threads);
        size_t diff4 = 0;
        for (size_t i = 0; i < viaSw.size(); ++i) diff4 += !(viaSw[i].r == viaLf[i].r && viaSw[i].g == viaLf[i].g && viaSw[i].b == viaLf[i].b);
        routeDiff += diff4;
        // The same object lit by the environment map of the backdrop.
        auto mem2 = std::make_shared<tex::TextureMemory>(octane);
        auto nearTex = uploadParaboloidMap(*mem2, nearMap);
        SliceTextures geoSlices2(mem2, geo);
        raster::Device dev2(octane, N, N, raster::DepthFormat::None, devOpt);
        dev2.textureUnits().setTextureMemory(mem2);
        const Frame viaEnv = pixelTextureFrame(dev2, geoSlices2, nearTex, cam);
        const Truth truth = traceTruth(cam, N, S.truthSpp, threads, [&](const ray::Ray& ry, bool& hit) {
            const ExitRay x = traceExit(accel, sc.object, ry, sc.mode, sc.ior);
            hit = x.hit;
            ray::Ray o;
            o.origin = x.origin;
            o.dir = x.dir;
            return backdrop(o);
        });
        const ray::MaskedScore sLf = ray::compareMasked(truth.color, imageOf(viaLf, N, N), truth.mask, objName + " (light-field lighting)");
        const ray::MaskedScore sEnv = ray::compareMasked(truth.color, imageOf(viaEnv.pixels, N, N), truth.mask, objName + " (environment-map lighting)");
        ray::writeImage(out / "plate_lighting_lightfield.png",
                        demos::labelledGrid({{imageOf(coords4, N, N), "(u, v, s, t) as RGB (A: t)"},
                                             {imageOf(viaLf, N, N), "lit by the light field (4D pixel texture)"},
                                             {imageOf(viaEnv.pixels, N, N), "lit by an environment map from the centre"},
                                             {truth.color, "ray traced"}},
                                            4));
        lit = {{"lighting_light_field", {{"S", lslab.S}, {"U", lslab.U}, {"bytes", lighting.bytes()}}},
               {"geometry_light_field", {{"S", g2.S}, {"U", g2.U}, {"bytes", geo4.bytes()}}},
               {"octane_resident_bytes", mem->residentBytes()},
               {"capture_seconds", lfSeconds},
               {"light_field_lighting", scoreJson(sLf)},
               {"environment_map_lighting", scoreJson(sEnv)},
               {"software_4d_differing_pixels", diff4}};
    }
    r["lighting_from_light_field"] = lit;
    progress.advance();

    // ---- §5: vector quantization, colour plate 3 -----------------------------------------
    nlohmann::json vqj;
    {
        LightSlab rslab = geometrySlab(S.radS, S.radU);
        t0 = Clock::now();
        const LightField rad = captureRadianceField(rslab, [&](const ray::Ray& ry) {
            return sampleParaboloidMap(envA, traceExit(accel, sc.object, ry, sc.mode, sc.ior).dir);
        }, threads);
        const double radSeconds = seconds(t0);
        const Truth truth = traceTruth(cam, N, S.truthSpp, threads, [&](const ray::Ray& ry, bool& hit) {
            const ExitRay x = traceExit(accel, sc.object, ry, sc.mode, sc.ior);
            hit = x.hit;
            return sampleParaboloidMap(envA, x.dir);
        });
        // Uncompressed on the Octane: does not fit, swapped per eye point.
        auto mem = std::make_shared<tex::TextureMemory>(octane);
        SliceTextures slices(mem, rad);
        raster::Device dev(octane, N, N, raster::DepthFormat::None, devOpt);
        dev.textureUnits().setTextureMemory(mem);
        auto a = Clock::now();
        dev.beginFrame();
        const GortlerStats gs = renderGortler(dev, slices, rad, cam);
        dev.endFrame();
        const double uncMs = std::chrono::duration<double, std::milli>(Clock::now() - a).count();
        const uint64_t uncFragments = dev.counters().fragmentsGenerated;
        const uint64_t uncUpload = dev.textureUnits().counters().uploadBytes;
        const std::vector<Rgba8> unc = dev.readPixels(0, 0, N, N);
        const ray::Image uncImg = imageOf(unc, N, N);
        nlohmann::json variants;
        std::vector<demos::Cell> cells{{uncImg, "uncompressed (" + num(double(rad.bytes()) / 1048576.0, 1) + " MiB, swapped)"}};
        std::map<std::string, double> psnrTruth;
        psnrTruth["uncompressed"] = ray::compareMasked(truth.color, uncImg, truth.mask, objName + " (uncompressed)").psnr;
        double colourRatio = 0;
        std::vector<Rgba8> basisAlpha;
        uint64_t vqTextureBytes = 0;
        int tableLoadsSt = 0, tableLoadsAll = 0;
        std::optional<VqLightField> allHalvedVq;  // for the 4D-texture route below (the same codebook)
        ray::Image allHalvedImg;
        struct V { std::string name; BlockShape shape; };
        for (const V& v : {V{"st_halved", {2, 2, 1, 1}}, V{"uv_halved", {1, 1, 2, 2}}, V{"all_halved", {2, 2, 2, 2}}}) {
            VqOptions vo;
            // The paper's configuration (all four halved, §5) K = vqK, the other two plate-3
            // variants K = vqKOther: equal at quick and paper quality (2^16 at paper), so the
            // plate compares equal codebooks; a test sets them apart.
            vo.codebookSize = v.name == "all_halved" ? S.vqK : S.vqKOther;
            vo.trainingBlocks = S.vqTraining;
            vo.iterations = S.vqIterations;
            vo.threads = threads;
            const VqLightField vq = quantize(rad, v.shape, vo);
            auto vmem = std::make_shared<tex::TextureMemory>(octane);
            const VqTextures vt(vmem, vq);
            raster::Device vd(octane, N, N, raster::DepthFormat::None, devOpt);
            vd.textureUnits().setTextureMemory(vmem);
            a = Clock::now();
            vd.beginFrame();
            const VqStats st = renderVq(vd, vt, vq, cam);
            vd.endFrame();
            const double ms = std::chrono::duration<double, std::milli>(Clock::now() - a).count();
            const ray::Image img = imageOf(vd.readPixels(0, 0, N, N), N, N);
            // The decoded light field drawn the uncompressed way: what the passes should equal.
            const LightField dec = decode(vq);
            auto dmem = std::make_shared<tex::TextureMemory>(o2);
            SliceTextures dslices(dmem, dec);
            raster::Device dd(o2, N, N, raster::DepthFormat::None, devOpt);
            dd.beginFrame();
            GortlerOptions dgo;
            if (!v.shape.uvHalved()) dgo.filter = tex::FilterMode::Nearest;
            renderGortler(dd, dslices, dec, cam, dgo);
            dd.endFrame();
            const ray::Image decImg = imageOf(dd.readPixels(0, 0, N, N), N, N);
            const ray::MaskedScore sT = ray::compareMasked(truth.color, img, truth.mask, objName + " (" + v.name + ")");
            const ray::MaskedScore sU = ray::compareMasked(uncImg, img, truth.mask, objName + " (" + v.name + " vs uncompressed)");
            const ray::MaskedScore sD = ray::compareMasked(decImg, img, truth.mask, objName + " (" + v.name + " vs its decoded light field)");
            psnrTruth[v.name] = sT.psnr;
            const double nominal = double(v.shape.samples() * 3) / double(vq.indexBytes());
            const double withBook = double(rad.bytes()) / double(vq.indexTextureBytes() + vq.codebookBytes());
            variants[v.name] = {{"block", {v.shape.s, v.shape.t, v.shape.u, v.shape.v}},
                                {"codebook_entries", vq.K},
                                {"index_bytes", vq.indexBytes()},
                                {"psnr_vs_raytracer", scoreJson(sT)},
                                {"psnr_vs_uncompressed", scoreJson(sU)},
                                {"psnr_vs_decoded_light_field", scoreJson(sD)},
                                {"compression_nominal", nominal},
                                {"compression_with_codebook", withBook},
                                {"index_texture_bytes", vq.indexTextureBytes()},
                                {"codebook_bytes", vq.codebookBytes()},
                                {"octane_texture_bytes", vmem->residentBytes()},
                                // Swapped index textures leave little resident: fits means all of them are.
                                {"fits_octane", vt.resident()},
                                {"index_textures_swapped", !vt.resident()},
                                {"upload_bytes_per_frame", vd.textureUnits().counters().uploadBytes},
                                {"table_loads_per_frame", st.tableLoads},
                                {"colour_passes", st.colorPasses},
                                {"basis_passes", st.basisPasses},
                                {"colour_fragments", st.colorFragments},
                                {"basis_fragments", st.basisFragments},
                                {"frame_ms", ms},
                                {"train_seconds", vq.trainSeconds},
                                {"encode_seconds", vq.encodeSeconds}};
            if (v.name == "all_halved") {
                colourRatio = double(st.colorFragments) / double(uncFragments);
                allHalvedVq = vq;
                allHalvedImg = img;
                // What the variant needs resident (all its index textures and the basis),
                // whether or not they were swapped.
                vqTextureBytes = vt.resident() ? vmem->residentBytes() : vq.indexTextureBytes() + vt.basis()->bytes();
                tableLoadsAll = st.tableLoads;
            }
            if (v.name == "st_halved") tableLoadsSt = st.tableLoads;
            cells.push_back({img, v.name + " (K = " + std::to_string(vq.K) + ", " + num(sT.psnr, 1) + " dB)"});
        }
        cells.push_back({demos::masked(truth.color, truth.mask), "ray traced"});
        ray::writeImage(out / "plate3_vq.png", demos::labelledGrid(cells, 5));
        vqj = {{"radiance_light_field", {{"S", rslab.S}, {"U", rslab.U}, {"bytes", rad.bytes()}, {"capture_seconds", radSeconds}}},
               {"uncompressed", {{"psnr_vs_raytracer", psnrTruth["uncompressed"]}, {"frame_ms", uncMs}, {"fragments", uncFragments},
                                 {"upload_bytes_per_frame", uncUpload}, {"swapped", !slices.resident()}, {"eye_points", gs.eyePoints}}},
               {"variants", variants},
               {"colour_fragment_ratio_all_halved", colourRatio},
               {"octane_texture_memory", octane.textureMemoryBytes},
               {"vq_texture_bytes_all_halved", vqTextureBytes},
               {"table_loads_st_halved", tableLoadsSt},
               {"table_loads_all_halved", tableLoadsAll}};
        // Figure 5: the 2×2 texture and the basis functions of one table.
        {
            const int M = 96;
            ray::Image texImg(M, M, 3), basis(M, M, 3);
            for (int y = 0; y < M; ++y)
                for (int x = 0; x < M; ++x) {
                    texImg.setRgb(x, y, glm::vec3((x < M / 2 && y < M / 2) ? 1.0f : 0.0f));
                    // Bilinear filtering of the replicated texture over 4 repetitions.
                    auto hat = [](float c) {
                        const float u = c * 8.0f - 0.5f;  // texel coordinate (2 texels a repetition)
                        const float f = u - std::floor(u);
                        const int i0 = int(std::floor(u));
                        const float w0 = (i0 & 1) == 0 ? 1.0f - f : 0.0f, w1 = ((i0 + 1) & 1) == 0 ? f : 0.0f;
                        return w0 + w1;
                    };
                    basis.setRgb(x, y, glm::vec3(hat((x + 0.5f) / M) * hat((y + 0.5f) / M)));
                }
            ray::writeImage(out / "figure5.png", demos::labelledGrid({{texImg, "the 2x2 texture"}, {basis, "basis functions of one table (4x4 repetitions, bilinear)"}}, 2));
        }
        // ---- §5 "4D VQ": the all-halved codebook through 4D textures; Figure 6 -------------
        // The same VqLightField as the alpha-basis route above, drawn as one window polygon
        // per pass on the Octane (the O2 has no 4D textures: VqTextures4D refuses it).
        {
            nlohmann::json v4;
            auto mem4 = std::make_shared<tex::TextureMemory>(octane);
            const VqTextures4D tx4(mem4, *allHalvedVq);
            raster::Device d4(octane, N, N, raster::DepthFormat::None, devOpt);
            d4.textureUnits().setTextureMemory(mem4);
            std::vector<double> frameMs;
            VqStats st4;
            for (int f = 0; f < 2; ++f) {  // a warm-up frame, then the timed one
                const auto a4 = Clock::now();
                d4.beginFrame();
                st4 = renderVq4D(d4, tx4, *allHalvedVq, cam);
                d4.endFrame();
                frameMs.push_back(std::chrono::duration<double, std::milli>(Clock::now() - a4).count());
            }
            const ray::Image img4 = imageOf(d4.readPixels(0, 0, N, N), N, N);
            const ray::MaskedScore s4T = ray::compareMasked(truth.color, img4, truth.mask, objName + " (4D VQ)");
            const ray::MaskedScore s4U = ray::compareMasked(uncImg, img4, truth.mask, objName + " (4D VQ vs uncompressed)");
            const ray::MaskedScore s42 = ray::compareMasked(allHalvedImg, img4, truth.mask, objName + " (4D VQ vs alpha-basis VQ)");
            // Σ basis of the frame itself (each basis pass's alpha read back), under both
            // readings, over the pixels whose ray crosses the window half a sample inside.
            std::vector<size_t> windowPx;
            for (int y = 0; y < N; ++y)
                for (int x = 0; x < N; ++x) {
                    const ray::Ray ry = ray::primaryRay(cam, N, N, x + 0.5f, y + 0.5f);
                    const auto stuv = rslab.intersect(ry.origin, ry.dir);
                    if (!stuv) continue;
                    const glm::vec4 c = rslab.textureCoords(*stuv);
                    const float m = 0.5f / float(rslab.U);
                    if (c.x > m && c.x < 1 - m && c.y > m && c.y < 1 - m) windowPx.push_back(size_t(y) * size_t(N) + size_t(x));
                }
            nlohmann::json sums;
            std::vector<demos::Cell> cells4{{uncImg, "uncompressed (Gortler, swapped)"},
                                            {allHalvedImg, "all halved, alpha basis (2D textures)"}};
            for (BasisReading reading : {BasisReading::OneHot, BasisReading::TwoPixels}) {
                auto pm = std::make_shared<tex::TextureMemory>(octane);
                const VqTextures4D ptx(pm, *allHalvedVq, reading);
                raster::Device pd(octane, N, N, raster::DepthFormat::None, devOpt);
                pd.textureUnits().setTextureMemory(pm);
                Vq4DProbe probe;
                pd.beginFrame();
                renderVq4D(pd, ptx, *allHalvedVq, cam, &probe);
                pd.endFrame();
                const int want = reading == BasisReading::OneHot ? 255 : 510;
                int lo = 1 << 30, hi = 0, worst = 0;
                for (size_t i : windowPx) {
                    lo = std::min(lo, probe.basisSum[i]);
                    hi = std::max(hi, probe.basisSum[i]);
                    worst = std::max(worst, std::abs(probe.basisSum[i] - want));
                }
                const std::string key = reading == BasisReading::OneHot ? "one_hot" : "two_pixels_one_per_class";
                sums[key] = {{"sum_min", lo}, {"sum_max", hi}, {"expected", want}, {"max_error_lsb", worst},
                             {"pixels", windowPx.size()}};
                const ray::Image pimg = imageOf(pd.readPixels(0, 0, N, N), N, N);
                const ray::MaskedScore ps = ray::compareMasked(truth.color, pimg, truth.mask, objName + " (4D VQ, " + basisReadingName(reading) + ")");
                sums[key]["psnr_vs_raytracer"] = scoreJson(ps);
                cells4.push_back({pimg, std::string("4D textures, ") + basisReadingName(reading) + " basis (" + num(ps.psnr, 1) + " dB)"});
            }
            cells4.push_back({demos::masked(truth.color, truth.mask), "ray traced"});
            ray::writeImage(out / "plate3_vq4d.png", demos::labelledGrid(cells4, 5));
            const Figure6 fig6 = makeFigure6(octane);
            ray::writeImage(out / "figure6.png", fig6.image);
            v4 = {{"block", {2, 2, 2, 2}},
                  {"codebook_entries", allHalvedVq->K},
                  {"basis_reading", "one-hot"},
                  {"frame_ms", frameMs.back()},
                  {"frame_ms_alpha_basis_route", variants["all_halved"]["frame_ms"]},
                  {"uncompressed_frame_ms", uncMs},
                  {"table_loads_per_frame", st4.tableLoads},
                  {"colour_passes", st4.colorPasses},
                  {"basis_passes", st4.basisPasses},
                  {"colour_fragments", st4.colorFragments},
                  {"basis_fragments", st4.basisFragments},
                  {"uncompressed_fragments", uncFragments},
                  {"colour_fragment_ratio_vs_uncompressed", double(st4.colorFragments) / double(uncFragments)},
                  {"colour_fragment_ratio_vs_uncompressed_4d_polygon", double(st4.colorPasses)},
                  {"index_texture_bytes", tx4.indexTexture()->bytes()},
                  {"octane_texture_bytes", mem4->residentBytes()},
                  {"fits_octane", mem4->residentBytes() <= octane.textureMemoryBytes},
                  {"uncompressed_4d_texture_bytes", rad.bytes()},
                  {"uncompressed_4d_fits_octane", rad.bytes() <= octane.textureMemoryBytes},
                  {"psnr_vs_raytracer", scoreJson(s4T)},
                  {"psnr_vs_uncompressed", scoreJson(s4U)},
                  {"psnr_vs_alpha_basis_vq", scoreJson(s42)},
                  {"frame_basis_sums", sums},
                  {"o2_refused", ""}};
            try {
                VqTextures4D refused(std::make_shared<tex::TextureMemory>(o2), *allHalvedVq);
            } catch (const UnsupportedFeature& e) {
                v4["o2_refused"] = e.what();  // the profile has no SGIS_texture4D: named, never a fallback
            }
            vqj["vq_4d"] = v4;
            r["figure6"] = fig6.sums;
        }
        // ---- why plate 3's ordering is thin against the ray tracer (issue 18) ---------------
        // The rendering of a VQ light field carries two errors: the light field's own (its
        // sampling of the object, the uncompressed rendering's error against the ray tracer)
        // and the codebook's (the variant against the uncompressed rendering). Were they
        // independent their MSEs would add; the prediction beside the measurement shows how
        // far the second can move the first. The passes themselves are checked against the
        // decoded light field drawn the uncompressed way (misread blocks or tables would show
        // there, not here).
        {
            nlohmann::json an;
            const double mseUnc = std::pow(10.0, -psnrTruth["uncompressed"] / 10.0);  // peak 1
            an["uncompressed_mse_vs_raytracer"] = mseUnc;
            // The codebook MSE that would open a gap of g dB: (10^(g/10) − 1)·MSE_unc.
            an["codebook_psnr_needed_for_0_5_db_gap"] = psnrTruth["uncompressed"] - 10.0 * std::log10(std::pow(10.0, 0.05) - 1.0);
            for (const char* n : {"st_halved", "uv_halved", "all_halved"}) {
                const auto& v = variants[n];
                const double c = v["psnr_vs_uncompressed"]["psnr_db"].get<double>();
                const double mseC = std::pow(10.0, -c / 10.0);
                an[n] = {{"psnr_vs_raytracer", psnrTruth[n]},
                         {"psnr_vs_uncompressed", c},
                         {"psnr_vs_decoded_light_field", v["psnr_vs_decoded_light_field"]["psnr_db"]},
                         {"codebook_mse_over_light_field_mse", mseC / mseUnc},
                         {"predicted_psnr_vs_raytracer_if_independent", -10.0 * std::log10(mseUnc + mseC)}};
            }
            vqj["plate3_ordering_analysis"] = an;
        }
        rep.claim(demos::claimAtLeast("uncompressed_beats_uv_halved", "§5, colour plate 3",
                                      "The uncompressed light field renders better than the one with reduced resolution on the (u, v)-plane",
                                      "uncompressed", psnrTruth["uncompressed"], "uv_halved", psnrTruth["uv_halved"], kMarginDb, "dB"));
        rep.claim(demos::claimAtLeast("uv_halved_beats_all_halved", "§5, colour plate 3",
                                      "Reducing the resolution in all 4 dimensions costs more quality than on the (u, v)-plane alone",
                                      "uv_halved", psnrTruth["uv_halved"], "all_halved", psnrTruth["all_halved"], kMarginDb, "dB"));
        rep.claim(demos::claimWithin("vq_colour_passes_cost_4x", "§5",
                                     "The cost of rendering the VQ light field is about four times that of an uncompressed one (colour-pass fragments)",
                                     "vq_over_uncompressed", colourRatio, "paper", 4.0, kCostTolerance, "×"));
        // The same ordering measured against the uncompressed light field (the compression's
        // own error, what colour plate 3 shows side by side).
        rep.claim(demos::claimAtLeast("uv_halved_beats_all_halved_vs_uncompressed", "§5, colour plate 3",
                                      "Against the uncompressed light field, reducing all 4 dimensions loses more than reducing (u, v) alone",
                                      "uv_halved", variants["uv_halved"]["psnr_vs_uncompressed"]["psnr_db"].get<double>(), "all_halved",
                                      variants["all_halved"]["psnr_vs_uncompressed"]["psnr_db"].get<double>(), kMarginDb, "dB"));
        demos::Claim c;
        c.id = "uncompressed_overflows_compressed_fits";
        c.section = "§5";
        c.statement = "The uncompressed light field does not fit the Octane's texture RAM and must be swapped every frame; the vector-quantized one fits";
        c.test = "uncompressed bytes > texture memory and swapped; VQ index textures ≤ texture memory";
        c.measured = {{"uncompressed_bytes", rad.bytes()}, {"texture_memory", octane.textureMemoryBytes},
                      {"upload_bytes_per_frame", uncUpload}, {"vq_bytes", vqTextureBytes}};
        c.holds = rad.bytes() > octane.textureMemoryBytes && !slices.resident() && vqTextureBytes <= octane.textureMemoryBytes;
        rep.claim(c);
    }
    r["vector_quantization"] = vqj;
    progress.advance();

    // ---- claims ---------------------------------------------------------------------------
    rep.claim(demos::claimWithin("pixel_texture_equals_software", "§4",
                                 "The pixel-texture lookup (Octane) and the software lookup (O2) compute the same image",
                                 "differing_pixels", double(routeDiff), "none", 0.0, 0.0, "pixels"));
    rep.claim(demos::claimAtLeast("light_field_lighting_beats_environment_map", "§4.1",
                                  "Illumination from a second light field handles objects close to the refractor, which an environment map cannot",
                                  "light_field", lit["light_field_lighting"]["psnr_db"].get<double>(), "environment_map",
                                  lit["environment_map_lighting"]["psnr_db"].get<double>(), kMarginDb, "dB"));
    {
        demos::Claim c;
        c.id = "environment_swap_needs_no_recompute";
        c.section = "§1, §4";
        c.statement = "Geometry and illumination are decoupled: the environment is exchanged without touching the light field";
        // Whether the light field fits the texture memory is a memory limit, not a recompute:
        // one that does not fit is streamed in every frame, swap or not. The test is that the
        // swap costs the map's upload and nothing of the light field; residency is reported.
        c.test = "switching environments uploads the new map and nothing else: the swap's uploads are the map's bytes, and the "
                 "frame after it uploads exactly the light-field bytes the frame before it did (0 when the light field is "
                 "resident; when it does not fit the texture memory its slices are streamed in every frame, swap or not: "
                 "reported as light_field_resident and the bytes per frame, not counted against the claim); each render's "
                 "PSNR against its own ray tracer is reported beside it";
        c.measured = {{"map_upload_bytes", swapUpload}, {"map_bytes", uint64_t(S.envSize) * S.envSize * 2 * 3},
                      {"light_field_upload_bytes_before_swap", ptA.uploadBytes},
                      {"light_field_upload_bytes_after_swap", ptB.uploadBytes},
                      {"psnr_a", scoreA.psnr}, {"psnr_b", scoreB.psnr}, {"light_field_resident", geoSlices.resident()},
                      {"light_field_recompute_seconds_avoided", geoSeconds}};
        c.holds = swapUpload == uint64_t(S.envSize) * S.envSize * 2 * 3 && ptB.uploadBytes == ptA.uploadBytes;
        rep.claim(c);
    }
    rep.claim(demos::claimWithin("gortler_weights_sum_to_one", "§3 (derived)",
                                 "The alpha-weighted eye points reconstruct: their weights sum to one wherever the eye points cover the ray",
                                 "max_error_lsb", double(maxWeightError), "zero", 0.0, kWeightToleranceLsb, "LSB"));
    {
        const double ptFps = fps["pixel_texture_sgi_octane_mxe"]["fps"].get<double>();
        const double swFps = fps["software_sgi_o2"]["fps"].get<double>();
        rep.claim(demos::claimAtLeast("interactive_at_400", "§4",
                                      "Both routes run at interactive rates at 400×400 (paper: 15–20 fps Octane, about 10 fps O2)",
                                      "slower_route_fps", std::min(ptFps, swFps), "paper_o2_fps", 10.0, 0.0, "fps"));
    }

    // ---- report -----------------------------------------------------------------------------
    std::ostringstream& md = rep.md();
    md << "Heidrich, Lensch, Cohen & Seidel, *Light Field Techniques for Reflections and Refractions*, EGWR 1999, "
          "on the emulated `sgi-octane-mxe` (pixel texture, texture colour tables with 16-bit indices, 4D textures) "
          "and `sgi-o2` (no pixel texture: the lookup runs in software). Object: " << sc.description << ".\n\n"
       << "Quality `" << demos::qualityName(options.quality) << "`: images " << N << "² against ray-traced references with "
       << S.truthSpp << "×" << S.truthSpp << " samples per pixel; frame rates at " << S.timingSize << "² (median of "
       << S.timingFrames << " frames) on " << fps["threads"].get<int>() << " thread(s).\n\n";
    rep.heading("§4: lighting from an environment map (Figure 3, colour plate 1)");
    rep.figure("figure3.png", "Figure 3 analogue. Top: the colour-coded paraboloid coordinates read back from the geometry light field "
                              "(R, G = (s, t), B = the back map), the final image through pixel texture with " + sc.envAName +
                              ", and with " + sc.envBName + " from the same light field. Bottom: ray traced with " + sc.envAName +
                              ", the O2's software route (the same bytes), ray traced with " + sc.envBName + ".");
    {
        demos::Table t{{"", "paper", "ours"}, {}};
        t.rows.push_back({"Octane MXE, pixel texture, 400×400", "15–20 fps", num(fps["pixel_texture_sgi_octane_mxe"]["fps"].get<double>(), 1) + " fps"});
        t.rows.push_back({"O2 (R10k 175 MHz), software lookup, 400×400", "about 10 fps", num(fps["software_sgi_o2"]["fps"].get<double>(), 1) + " fps"});
        t.rows.push_back({"read-back per frame", "—", std::to_string(S.timingSize * S.timingSize * 4) + " bytes"});
        t.rows.push_back({"PSNR vs ray tracer, " + sc.envAName, "—", num(scoreA.psnr) + " dB (SSIM " + num(scoreA.ssim, 3) + ")"});
        t.rows.push_back({"PSNR vs ray tracer, " + sc.envBName, "—", num(scoreB.psnr) + " dB (SSIM " + num(scoreB.ssim, 3) + ")"});
        t.rows.push_back({"pixel texture = software (differing pixels)", "same images", std::to_string(routeDiff)});
        t.rows.push_back({"swapping the environment", "no recompute", std::to_string(swapUpload) + " bytes uploaded; the light field took " + num(geoSeconds, 1) + " s to trace" +
                                      (geoSlices.resident() ? std::string(" (resident)")
                                                            : " (not resident: " + std::to_string(ptB.uploadBytes) +
                                                                  " bytes streamed in every frame, swap or not)")});
        rep.table(t);
    }
    md << "Per frame (pixel texture, ms): Gortler " << num(fps["pixel_texture_sgi_octane_mxe"]["gortler_ms"].get<double>()) << ", read-back "
       << num(fps["pixel_texture_sgi_octane_mxe"]["read_back_ms"].get<double>()) << ", lookup "
       << num(fps["pixel_texture_sgi_octane_mxe"]["lookup_ms"].get<double>()) << "; software route: Gortler "
       << num(fps["software_sgi_o2"]["gortler_ms"].get<double>()) << ", lookup and write-back "
       << num(fps["software_sgi_o2"]["lookup_ms"].get<double>()) << ". The paper's rates are of 1997 machines; ours are the "
       "emulation on this host's cores (context, not a comparison).\n\n";
    rep.heading("§3: the Gortler reconstruction");
    rep.figure("triangulation.png", "Σ of the eye points' weights (the alpha of an RGB light field after reconstruction): one fixed "
                                    "diagonal for every eye point sums to one (largest error " + std::to_string(maxWeightError) +
                                    " LSB over " + std::to_string(hullPixels) + " pixels); diagonals through each eye point do not.");
    rep.heading("§4.2: Fresnel-weighted reflection and refraction (Figure 4, colour plate 2)");
    rep.figure("figure4.png", "Figure 4 analogue: the glossy reflection (the mesh with a Phong-prefiltered paraboloid map, exponent " +
                              num(S.glossyExponent, 0) + ") weighted by F, the refraction light field weighted by 1 − F, their sum, "
                              "and the ray-traced composite. " + std::to_string(fig4["passes"].get<int>()) + " passes; PSNR " +
                              num(fig4["psnr_vs_raytracer"]["psnr_db"].get<double>()) + " dB.");
    rep.heading("§4.1: lighting from a second light field");
    rep.figure("plate_lighting_lightfield.png", "The object before a near backdrop (a wall at z = −3.2 and three boxes), lit through "
                                                "a second light field (RGBA = (u, v, s, t) → 4D texture by pixel texture) and by an "
                                                "environment map of the backdrop taken at the object's centre; ray traced.");
    {
        demos::Table t{{"lighting", "PSNR (dB)", "SSIM"}, {}};
        t.rows.push_back({"second light field (4D pixel texture)", num(lit["light_field_lighting"]["psnr_db"].get<double>()),
                          num(lit["light_field_lighting"]["ssim"].get<double>(), 3)});
        t.rows.push_back({"environment map from the centre", num(lit["environment_map_lighting"]["psnr_db"].get<double>()),
                          num(lit["environment_map_lighting"]["ssim"].get<double>(), 3)});
        rep.table(t);
    }
    rep.heading("§5: vector-quantized light fields (Figure 5, colour plate 3)");
    rep.figure("plate3_vq.png", "Colour plate 3 analogue: uncompressed (swapped through the Octane's 4 MiB texture memory), "
                                "(s, t) halved, (u, v) halved, all four halved; ray traced.");
    rep.figure("figure5.png", "Figure 5: the 2×2 texture with one texel one, and the basis functions for one colour table.");
    {
        demos::Table t{{"variant", "paper", "PSNR vs ray tracer", "PSNR vs uncompressed", "compression (nominal / with codebook)",
                        "index textures", "table loads / frame", "colour fragments"}, {}};
        t.rows.push_back({"uncompressed", "plate 3 left", num(vqj["uncompressed"]["psnr_vs_raytracer"].get<double>()), "—", "1:1",
                          std::to_string(vqj["radiance_light_field"]["bytes"].get<uint64_t>()) + " B (swapped, " +
                              std::to_string(vqj["uncompressed"]["upload_bytes_per_frame"].get<uint64_t>()) + " B uploaded / frame)",
                          "—", std::to_string(vqj["uncompressed"]["fragments"].get<uint64_t>())});
        for (const char* n : {"st_halved", "uv_halved", "all_halved"}) {
            const auto& v = vqj["variants"][n];
            t.rows.push_back({n, std::string(n) == "all_halved" ? "1:24 (2-byte indices, 2^16 codebook)" : "—",
                              num(v["psnr_vs_raytracer"]["psnr_db"].get<double>()), num(v["psnr_vs_uncompressed"]["psnr_db"].get<double>()),
                              "1:" + num(v["compression_nominal"].get<double>(), 0) + " / 1:" + num(v["compression_with_codebook"].get<double>(), 1),
                              std::to_string(v["index_texture_bytes"].get<uint64_t>()) + " B",
                              std::to_string(v["table_loads_per_frame"].get<int>()),
                              std::to_string(v["colour_fragments"].get<uint64_t>())});
        }
        rep.table(t);
    }
    {
        const auto& v = vqj["variants"];
        md << "Against the ray tracer the uncompressed, (u, v)-halved and all-halved renderings score "
           << num(vqj["uncompressed"]["psnr_vs_raytracer"].get<double>()) << ", "
           << num(v["uv_halved"]["psnr_vs_raytracer"]["psnr_db"].get<double>()) << " and "
           << num(v["all_halved"]["psnr_vs_raytracer"]["psnr_db"].get<double>())
           << " dB: the light field's own sampling error (its " << S.radS << "·" << S.radS << "·" << S.radU << "·" << S.radU
           << " samples of a refracting object) is larger than the codebook's, so the ordering of colour plate 3 shows "
              "against the ray tracer only by the margins above, if at all. Against the uncompressed light field (the "
              "compression's own error, what the plate puts side by side) the (u, v)-halved variant scores "
           << num(v["uv_halved"]["psnr_vs_uncompressed"]["psnr_db"].get<double>()) << " dB and the all-halved "
           << num(v["all_halved"]["psnr_vs_uncompressed"]["psnr_db"].get<double>()) << " dB.\n\n";
    }
    md << (S.vqK == S.vqKOther ? "Codebook of every variant: K = " + std::to_string(S.vqK)
                                : "Codebook of the all-halved (paper's) variant: K = " + std::to_string(S.vqK) +
                                      "; the (s, t)- and (u, v)-halved variants K = " + std::to_string(S.vqKOther))
       << " (" << (S.vqK > 256 ? "2-byte I16 indices through 65,536-entry-capable colour tables" : "1-byte indices")
       << "), LBG / k-means on " << S.vqTraining << " random blocks, " << S.vqIterations << " iterations, distances by Eigen matrix "
       "products. The (s, t)-halved variant samples its full-resolution index textures NEAREST (filtering precedes the colour "
       "table), so it loses the bilinear (u, v) interpolation the paper's \"trivial extension\" keeps silent about.\n\n";
    // ---- §5 "4D VQ" and Figure 6 (report) -------------------------------------------------
    if (vqj.contains("vq_4d")) {
        const auto& v4 = vqj["vq_4d"];
        const auto& f6 = r["figure6"];
        rep.heading("§5: vector-quantized light fields through 4D textures (Figure 6)");
        md << "The paper: \"Since 4D texture mapping does not treat the (u, v)-plane differently from the (s, t)-plane ... What "
              "remains is the concept of using the alpha channel to render basis functions for the different lookup tables. This "
              "time, however, the basis functions are generated by 4D textures of resolution 2^4. In each of these textures, "
              "exactly two pixels are one and the others are zero. Fig. 6 illustrates this for a 2-dimensional \"light field\".\"\n\n"
           << "Ours: the (u, v) window drawn as one polygon carrying each corner ray's 4D coordinates (u, v, s, t); per parity "
              "class (16) a basis pass (a 2^4 A8 4D texture, quadrilinear, WRAP, coordinates × N/2, shifted one texel on odd axes) "
              "into the destination alpha and a colour pass (one 4D I16 index texture of the all-halved codebook, NEAREST, ½ sample "
              "towards the hat's block, through that class's table) blended DESTALPHA·src + ONE·dst. The existing 4D texture unit, "
              "unchanged. On `sgi-o2`: \"" << v4["o2_refused"].get<std::string>() << "\".\n\n";
        rep.figure("figure6.png", "Figure 6 analogue, the 2D (u, s) light field (8 samples per axis, 2×2 blocks). Each cell: the "
                                  "2×2 basis texture shifted onto its parity class (u right, s up), its bilinear basis functions over "
                                  "(u, s) from the emulated texture unit, and the rays it corresponds to (eye points s_i on top, window "
                                  "samples u_k below). Top row: one-hot (one texel one); middle: the paper's literal \"two pixels\" "
                                  "(texel 0 and the opposite corner), which covers two parity classes at once; bottom: Σ of the basis "
                                  "functions (mid grey = one, white = two).");
        {
            demos::Table t{{"reading", "textures", "Σ basis, 2D (u, s)", "Σ basis, 4D (sampler, random points)",
                            "Σ basis, 4D (the frame's basis passes)", "partition of unity"}, {}};
            auto range = [](const nlohmann::json& j) {
                return std::to_string(j["sum_min"].get<int>()) + "–" + std::to_string(j["sum_max"].get<int>()) + " (" +
                       num(double(j["sum_min"].get<int>()) / 255.0, 3) + "–" + num(double(j["sum_max"].get<int>()) / 255.0, 3) + ")";
            };
            t.rows.push_back({"one-hot, one texture per parity class", "4 / 16", range(f6["2d"]["one_hot"]), range(f6["4d"]["one_hot"]),
                              range(v4["frame_basis_sums"]["one_hot"]), "yes"});
            t.rows.push_back({"two pixels, one texture per parity class", "4 / 16", range(f6["2d"]["two_pixels_one_per_class"]),
                              range(f6["4d"]["two_pixels_one_per_class"]), range(v4["frame_basis_sums"]["two_pixels_one_per_class"]),
                              "no: Σ = 2"});
            t.rows.push_back({"two pixels, the distinct textures only", "2 / 8", range(f6["2d"]["two_pixels_distinct"]),
                              range(f6["4d"]["two_pixels_distinct"]), "—",
                              "yes, but each basis spans two parity classes whose colours no single table returns"});
            rep.table(t);
        }
        md << "So with one colour table per parity class (\"16 different tables\") only the one-hot reading reconstructs: the "
              "\"two pixels\" textures, one per class, double every colour (" << num(v4["frame_basis_sums"]["two_pixels_one_per_class"]["psnr_vs_raytracer"]["psnr_db"].get<double>())
           << " dB against the ray tracer, saturated; `plate3_vq4d.png`), and the 8 distinct ones sum to one only by pairing classes "
              "that hold different codeword samples. We render one-hot; the deviations from 255 are the basis passes' own rounding "
              "(one ½-LSB rounding per pass, 16 passes: bound 8 LSB).\n\n";
        rep.figure("plate3_vq4d.png", "The all-halved light field (the same codebook) through 4D textures beside the 2D alpha-basis route "
                                      "and the uncompressed rendering; the \"two pixels\" reading sums its basis to two.");
        {
            demos::Table t{{"", "uncompressed (Gortler)", "VQ, 2D alpha basis", "VQ, 4D textures (one-hot)"}, {}};
            const auto& ah = vqj["variants"]["all_halved"];
            t.rows.push_back({"PSNR vs ray tracer (dB)", num(vqj["uncompressed"]["psnr_vs_raytracer"].get<double>()),
                              num(ah["psnr_vs_raytracer"]["psnr_db"].get<double>()), num(v4["psnr_vs_raytracer"]["psnr_db"].get<double>())});
            t.rows.push_back({"PSNR vs uncompressed (dB)", "—", num(ah["psnr_vs_uncompressed"]["psnr_db"].get<double>()),
                              num(v4["psnr_vs_uncompressed"]["psnr_db"].get<double>())});
            t.rows.push_back({"PSNR 4D vs 2D route (dB)", "—", "—", num(v4["psnr_vs_alpha_basis_vq"]["psnr_db"].get<double>())});
            t.rows.push_back({"frame (ms, " + std::to_string(N) + "², one frame)", num(v4["uncompressed_frame_ms"].get<double>(), 1),
                              num(ah["frame_ms"].get<double>(), 1), num(v4["frame_ms"].get<double>(), 1)});
            t.rows.push_back({"colour passes / table loads", std::to_string(vqj["uncompressed"]["eye_points"].get<int>()) + " eye points / —",
                              std::to_string(ah["colour_passes"].get<int>()) + " / " + std::to_string(ah["table_loads_per_frame"].get<int>()),
                              std::to_string(v4["colour_passes"].get<int>()) + " / " + std::to_string(v4["table_loads_per_frame"].get<int>())});
            t.rows.push_back({"colour-pass fragments", std::to_string(vqj["uncompressed"]["fragments"].get<uint64_t>()),
                              std::to_string(ah["colour_fragments"].get<uint64_t>()) + " (" + num(vqj["colour_fragment_ratio_all_halved"].get<double>(), 2) + "×)",
                              std::to_string(v4["colour_fragments"].get<uint64_t>()) + " (" + num(v4["colour_fragment_ratio_vs_uncompressed"].get<double>(), 2) + "×)"});
            t.rows.push_back({"texture bytes on the Octane", std::to_string(vqj["radiance_light_field"]["bytes"].get<uint64_t>()) + " (swapped; as one 4D texture it does not fit)",
                              std::to_string(ah["octane_texture_bytes"].get<uint64_t>()), std::to_string(v4["octane_texture_bytes"].get<uint64_t>())});
            rep.table(t);
        }
        md << "The paper's \"about four times\" is the 2D route's count (4 (u, v) parities per eye point). The 4D route draws 16 "
              "colour passes of one window polygon: 16× an uncompressed 4D rendering of the same polygon (which the Octane cannot "
              "hold: " << vqj["radiance_light_field"]["bytes"].get<uint64_t>() << " bytes), and "
           << num(v4["colour_fragment_ratio_vs_uncompressed"].get<double>(), 2) << "× the uncompressed Gortler rendering, whose "
              "hexagons put 3 fragments on a pixel (16/3 where the window fills the frame). Its frame time is the reference 4D "
              "sampler's (16 taps a basis fragment; no fast path for 4D textures). The two VQ routes differ in the (s, t) "
              "interpolant: the hexagon's barycentric hat against the 4D texture's bilinear tent; they agree exactly on data affine "
              "in (s, t) (test: within 8 LSB, mean 1.3), here to " << num(v4["psnr_vs_alpha_basis_vq"]["psnr_db"].get<double>()) << " dB.\n\n";
    }
    if (vqj.contains("plate3_ordering_analysis")) {
        const auto& an = vqj["plate3_ordering_analysis"];
        rep.heading("§5: why the orderings against the ray tracer are thin");
        md << "The claims `uncompressed_beats_uv_halved` and `uv_halved_beats_all_halved` compare against the ray tracer. "
              "Two errors add there: the light field's own sampling of the object (the uncompressed rendering scores "
           << num(an["uncompressed_mse_vs_raytracer"].is_number() ? -10.0 * std::log10(an["uncompressed_mse_vs_raytracer"].get<double>()) : 0.0) << " dB) and the codebook's (each variant against the uncompressed rendering). "
              "The passes are not the cause: each variant reproduces its own decoded light field, drawn the uncompressed way, "
              "to " << num(an["uv_halved"]["psnr_vs_decoded_light_field"].get<double>()) << " dB ((u, v) halved) and "
           << num(an["all_halved"]["psnr_vs_decoded_light_field"].get<double>()) << " dB (all halved), where a wrong "
              "½-sample offset or table order costs tens of LSB (tests `VqPasses`, `Vq4DPasses`).\n\n";
        demos::Table t{{"variant", "vs ray tracer (dB)", "vs uncompressed (dB)", "codebook MSE ÷ light-field MSE",
                        "predicted vs ray tracer if the errors were independent (dB)"}, {}};
        for (const char* n : {"uv_halved", "all_halved"})
            t.rows.push_back({n, num(an[n]["psnr_vs_raytracer"].get<double>()), num(an[n]["psnr_vs_uncompressed"].get<double>()),
                              num(an[n]["codebook_mse_over_light_field_mse"].get<double>(), 3),
                              num(an[n]["predicted_psnr_vs_raytracer_if_independent"].get<double>())});
        rep.table(t);
        md << "The codebook's error is a few percent of the light field's, so it moves the score against the ray tracer by "
              "tenths of a dB, as the independent-error prediction says. A 0.5 dB gap needs a codebook scoring at most "
           << num(an["codebook_psnr_needed_for_0_5_db_gap"].get<double>()) << " dB against the uncompressed light field. "
              "This is a property of the setting (a refracting object sampled at " << S.radS << "·" << S.radS << "·" << S.radU
           << "·" << S.radU << "), not of the passes or the training: against the uncompressed light field, the comparison "
              "colour plate 3 makes side by side, the ordering holds (`uv_halved_beats_all_halved_vs_uncompressed`).\n\n";
    }
    rep.heading("Choices where the paper is silent");
    md << "- **Slabs.** One slab; eye points at grid vertices over [−1, 1]² at z = 6, the window over [−2, 2]² at z = 0 through the "
          "object (validated to hold its shadow from every eye point); window samples at texel centres; slices CLAMP_TO_EDGE.\n"
       << "- **Triangulation.** One fixed diagonal for every eye point (Gortler's hexagon): the weights then sum to one; weights "
          "ride in the vertex colour (w, w, w, w), GL MODULATE, blending ONE/ONE; perspective-correct Gouraud.\n"
       << "- **Geometry path.** Refraction (IOR " << num(sc.ior, 2) << ") with total internal reflection as the single new direction, "
          "at most 8 segments; rays missing the object store their own direction. One ray per sample (coordinates are not averaged).\n"
       << "- **Paraboloid coordinates.** Both hemispheres: the side in B (0 front, 255 back) selects the slice of a 256×256×2 "
          "3D texture (the Octane has 3D textures); each map continues past its rim. Coordinates round(255·s).\n"
       << "- **HDR to 8 bits.** Exposure mapping each world's mean luminance to 0.3, clipped at 1.\n"
       << "- **Truth.** The exact exit ray of each sample looked up in the same 8-bit map (the light field's error alone).\n"
       << "- **§4.1 coordinates.** RGBA = (u, v, s, t) of the lighting slab as 4D texture coordinates (eye point i at texel "
          "centre (i + ½)/S), clamped; the lighting slab lies between the object and the backdrop.\n"
       << "- **§4.2.** F exact dielectric per mesh vertex from the camera; glossy reflection: the paraboloid map prefiltered "
          "with a cos^" << num(S.glossyExponent, 0) << " lobe, coordinates per vertex (side interpolated at the seam); passes: "
          "refraction route, mesh depth, rgb ·= 1 − F (ZERO, SRCALPHA), rgb += F·glossy (ONE, ONE), depth EQUAL.\n"
       << "- **VQ.** K = " << S.vqK << " at this quality; index texels scaled so that round(v·(N − 1)) returns the index; the "
          "index lookup offset by ½ sample towards the hat's block; basis passes write destination alpha, colour passes "
          "blend DESTALPHA·src + ONE·dst. The \"about four times\" claim is decided on colour-pass fragments (deterministic); "
          "frame times are reported beside it.\n"
       << "- **4D VQ basis.** One-hot 2^4 textures (one texel one), one per parity class: the reading of §5's \"exactly two "
          "pixels\" under which the basis sums to one with 16 tables (Figure 6 shows both readings); the window polygon "
          "clipped by nothing, so rays outside the eye-point hull take the edge eye points' indices (CLAMP_TO_EDGE) with "
          "wrapped basis weights.\n"
       << "- **Claims' margins.** Every PSNR ordering by " << num(kMarginDb, 1) << " dB: one view is evaluated here, and the "
          "same measurement in hybrid and tir moves by at most 0.2 dB under a change that should not matter (hybrid's multi-layer "
          "frame from the sample's view to between samples), while "
          "the emulated passes add under 0.01 dB (the all-halved frame against its decoded light field: 46 dB). The 4× cost "
          "within ±" << num(kCostTolerance, 1) << " (exact fragment counts; the tolerance is the paper's \"about\"); the "
          "Gortler weights within " << num(kWeightToleranceLsb, 0) << " LSB (three 8-bit weights and the blender, each "
          "rounding by up to ½ LSB); the two routes equal to the byte; the slower route at least the paper's 10 fps "
          "(a timing on this machine).\n\n";
    rep.heading("Left out");
    md << "- Nothing of §3–§5's techniques. One view is evaluated per claim (see the margins above), and the frame rates "
          "are of this machine.\n\n";
    r["settings"] = {{"quality", demos::qualityName(options.quality)}, {"image_size", N}, {"truth_spp", S.truthSpp},
                     {"timing_size", S.timingSize}, {"timing_frames", S.timingFrames}, {"geometry", {S.geoS, S.geoS, S.geoU, S.geoU}},
                     {"radiance", {S.radS, S.radS, S.radU, S.radU}}, {"vq_codebook", S.vqK}, {"vq_codebook_st_uv", S.vqKOther}, {"vq_training_blocks", S.vqTraining},
                     {"vq_iterations", S.vqIterations}, {"env_size", S.envSize}, {"scene", sc.description}};
    r["memory"] = {{"octane_texture_memory", octane.textureMemoryBytes},
                   {"geometry_light_field_bytes", geo.bytes()},
                   {"radiance_light_field_bytes", vqj["radiance_light_field"]["bytes"]},
                   {"vq_all_halved_bytes", vqj["vq_texture_bytes_all_halved"]}};
    r["seconds_total"] = seconds(tStart);
    progress.advance();
    r = rep.write(out, r);
    std::printf("lightfield: pixel texture %.1f FPS (Octane), software %.1f FPS (O2) at %d² (paper: 15–20, about 10)\n",
                fps["pixel_texture_sgi_octane_mxe"]["fps"].get<double>(), fps["software_sgi_o2"]["fps"].get<double>(), S.timingSize);
    return r;
}

// ---- the registry entry ---------------------------------------------------------------------

std::string LightfieldReproduction::paper() const {
    return "Heidrich, Lensch, Cohen & Seidel, \"Light Field Techniques for Reflections and Refractions\", EGWR 1999";
}

nlohmann::json LightfieldReproduction::settings(demos::Quality quality) const {
    const LightfieldSettings s = lightfieldSettingsFor(quality);
    return {{"image_size", s.imageSize}, {"timing_size", s.timingSize}, {"geometry_light_field", {s.geoS, s.geoS, s.geoU, s.geoU}},
            {"radiance_light_field", {s.radS, s.radS, s.radU, s.radU}}, {"vq_codebook", s.vqK}};
}

nlohmann::json LightfieldReproduction::reproduce(const demos::ReproduceOptions& options) const {
    LightfieldSettings s = lightfieldSettingsFor(options.quality);
    s.threads = options.threads;
    return runLightfield(s, options);
}

namespace {

// What the benchmarks share: the built-in scene's geometry light field at the quick setting,
// environment B, a 400² camera.
struct BenchFixture {
    LfScene scene;
    std::unique_ptr<ray::Accel> accel;
    LightField geo;
    ParaboloidMap env;
    HostTexture host;
    std::unique_ptr<SoftwareLookup> lookup;
    std::vector<Rgba8> coords;  // a read-back of the Gortler frame
};

std::shared_ptr<BenchFixture> benchFixture(int threads,
                                           demos::Quality quality = demos::Quality::Quick) {
    auto f = std::make_shared<BenchFixture>();
    f->scene = makeScene("");
    f->accel = std::make_unique<ray::Accel>(f->scene.scene);
    const LightfieldSettings s = lightfieldSettingsFor(quality);
    f->geo = captureParaboloidField(*f->accel, f->scene.object, geometrySlab(s.geoS, s.geoU), f->scene.mode, f->scene.ior, threads);
    f->env = makeParaboloidMap(f->scene.envB, s.envSize, autoExposure(f->scene.envB), 2);
    f->host = hostParaboloidMap(f->env);
    f->lookup = std::make_unique<SoftwareLookup>(f->host, true);
    const Profile& o2 = profile(ProfileId::SgiO2);
    auto mem = std::make_shared<tex::TextureMemory>(o2);
    SliceTextures slices(mem, f->geo);
    raster::Device dev(o2, s.timingSize, s.timingSize, raster::DepthFormat::None, {Path::Fast, threads});
    dev.beginFrame();
    renderGortler(dev, slices, f->geo, evalCamera(1));
    f->coords = dev.readPixels(0, 0, s.timingSize, s.timingSize);
    return f;
}

// The plain loop: the same trilinear lookup written the obvious way, per pixel in float
// (no tables, no integer weights), on one thread per row band as TBB gives it.
Rgba8 plainLookup(const HostTexture& t, Rgba8 px) {
    const float c[3] = {px.r / 255.0f, px.g / 255.0f, px.b / 255.0f};
    int i0[3], i1[3];
    float w1[3];
    for (int d = 0; d < 3; ++d) {
        const float u = c[d] * float(t.size[size_t(d)]) - 0.5f;
        const float f = std::floor(u);
        i0[d] = std::clamp(int(f), 0, t.size[size_t(d)] - 1);
        i1[d] = std::clamp(int(f) + 1, 0, t.size[size_t(d)] - 1);
        w1[d] = u - f;
    }
    glm::vec3 acc(0.0f);
    for (int k = 0; k < 8; ++k) {
        const int x = k & 1 ? i1[0] : i0[0], y = k & 2 ? i1[1] : i0[1], z = k & 4 ? i1[2] : i0[2];
        const float w = (k & 1 ? w1[0] : 1 - w1[0]) * (k & 2 ? w1[1] : 1 - w1[1]) * (k & 4 ? w1[2] : 1 - w1[2]);
        const Rgba8 v = t.texels[(size_t(z) * t.size[1] + size_t(y)) * t.size[0] + size_t(x)];
        acc += w * glm::vec3(v.r, v.g, v.b);
    }
    return {uint8_t(acc.x + 0.5f), uint8_t(acc.y + 0.5f), uint8_t(acc.z + 0.5f), px.a};
}

// §4's whole frame at 400² on either machine: the Gortler reconstruction, the read-back,
// then the Octane's pixel texture lookup, or the O2's software lookup on the CPU and the
// write-back (the routes `reproduce lightfield` times).
enum class Route { OctanePixelTexture, O2Software };

demos::BenchCase frameCase(const std::string& name, demos::Quality quality, Route route) {
    demos::BenchCase c;
    c.name = name;
    // "between 15 and 20 fps" on an Octane MXE, "about 10" on the O2; the goal is 60.
    c.paper = {{"paper_fps", route == Route::OctanePixelTexture ? 17.5 : 10.0}, {"goal_fps", 60.0}};
    c.setup = [quality, route](int threads) {
        struct Frame {
            std::shared_ptr<BenchFixture> f;
            std::shared_ptr<tex::TextureMemory> mem;
            std::unique_ptr<SliceTextures> slices;
            std::shared_ptr<tex::Texture> env;  // the Octane's paraboloid map
            std::unique_ptr<raster::Device> dev;
        };
        auto fr = std::make_shared<Frame>();
        fr->f = benchFixture(threads, quality);
        const Profile& p = rg::profile(route == Route::OctanePixelTexture ? ProfileId::SgiOctaneMxe : ProfileId::SgiO2);
        fr->mem = std::make_shared<tex::TextureMemory>(p);
        if (route == Route::OctanePixelTexture) fr->env = uploadParaboloidMap(*fr->mem, fr->f->env);
        fr->slices = std::make_unique<SliceTextures>(fr->mem, fr->f->geo);
        fr->dev = std::make_unique<raster::Device>(p, 400, 400, raster::DepthFormat::None, raster::DeviceOptions{Path::Fast, threads});
        return std::function<std::map<std::string, double>()>([fr, route, threads] {
            raster::Device& d = *fr->dev;
            d.beginFrame();
            fr->mem->resetFrameCounters();
            renderGortler(d, *fr->slices, fr->f->geo, evalCamera(1));
            std::vector<Rgba8> px = d.readPixels(0, 0, 400, 400);
            if (route == Route::OctanePixelTexture) {
                pixelTextureLookup(d, fr->env, tex::PixelTexGenMode::Rgb, px);
            } else {
                fr->f->lookup->apply(px, threads);
                d.drawPixels(0, 0, 400, 400, px);
            }
            d.endFrame();
            return std::map<std::string, double>{
                {"fragments", double(d.counters().fragmentsGenerated)},
                {"upload_bytes", double(fr->mem->uploadBytes())}};
        });
    };
    return c;
}

}  // namespace

std::unique_ptr<viewer::Demo> LightfieldReproduction::makeDemo(const viewer::DemoOptions& options) const {
    return std::make_unique<LightfieldDemo>(options);
}

std::vector<demos::BenchCase> LightfieldReproduction::benchCases() const {
    std::vector<demos::BenchCase> cases;
    // §4's Octane frame at 400²: Gortler reconstruction, read-back, pixel texture; at
    // quick quality's light field, which fits the 4 MiB of texture memory, and at paper
    // quality's 32·32·128·128, which does not: every slice is swapped in as its eye point
    // is drawn (48 MiB a frame), as `reproduce lightfield --quality paper` times it.
    cases.push_back(frameCase("lightfield_pixel_texture_400", demos::Quality::Quick, Route::OctanePixelTexture));
    cases.push_back(frameCase("lightfield_pixel_texture_400_paper", demos::Quality::Paper, Route::OctanePixelTexture));
    cases.push_back(frameCase("lightfield_software_o2_400_paper", demos::Quality::Paper, Route::O2Software));
    {
        // The O2's software lookup of one 400² read-back, against a plain float loop doing
        // the same trilinear lookup (llvmpipe has no pixel texture: ours only otherwise).
        demos::BenchCase c;
        c.name = "lightfield_software_lookup_400";
        c.paper = {{"paper_fps", 10.0}};  // the whole O2 frame, "about 10 frames per second"
        c.setup = [](int threads) {
            auto f = benchFixture(threads);
            return std::function<std::map<std::string, double>()>([f, threads] {
                std::vector<Rgba8> px = f->coords;
                f->lookup->apply(px, threads);
                return std::map<std::string, double>{{"checksum", double(px[px.size() / 2].r)}};
            });
        };
        c.peer = "plain_loop";
        c.setupPeer = [](int threads) {
            auto f = benchFixture(threads);
            return std::function<std::map<std::string, double>()>([f, threads] {
                std::vector<Rgba8> px = f->coords;
                parallelRowsOf(threads, 400, [&](int y) {
                    for (int x = 0; x < 400; ++x) px[size_t(y) * 400 + x] = plainLookup(f->host, px[size_t(y) * 400 + x]);
                });
                return std::map<std::string, double>{{"checksum", double(px[px.size() / 2].r)}};
            });
        };
        cases.push_back(c);
    }
    return cases;
}

const LightfieldReproduction& lightfieldReproduction() {
    static const LightfieldReproduction instance;
    return instance;
}

}  // namespace rg::lightfield
