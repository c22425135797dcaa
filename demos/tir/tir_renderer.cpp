#include "tir_renderer.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>

#include "core/error.h"
#include "core/profile.h"
#include "raycore/accel.h"
#include "raycore/texture.h"
#include "texunit/cube_mapping.h"

namespace rg::tir {

namespace {

using Clock = std::chrono::steady_clock;
using raster::ColorTarget;
using raster::DepthTarget;
using raster::ProgramPrimitive;

// One triangle over the whole target (clip x, y from −1 to 3), at depth z.
constexpr float kBehind = 1.0f - 1.0f / 1048576.0f;
const TirVertex kCover[3] = {{{-1, -1, 0.5f}, {}, {}, 0}, {{3, -1, 0.5f}, {}, {}, 0}, {{-1, 3, 0.5f}, {}, {}, 0}};
const TirVertex kCoverBehind[3] = {{{-1, -1, kBehind}, {}, {}, 0}, {{3, -1, kBehind}, {}, {}, 0}, {{-1, 3, kBehind}, {}, {}, 0}};

const Profile& g80() { return profile(ProfileId::GeForce8800); }

tex::SamplerState pointSampler() {
    tex::SamplerState s;
    s.magFilter = s.minFilter = tex::FilterMode::Nearest;
    s.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge,
                 tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge};
    return s;
}

tex::SamplerState trilinearSampler() {
    tex::SamplerState s;
    s.mipFilter = tex::MipMode::Linear;
    s.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge,
                 tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge};
    return s;
}

// The world-space triangles of one object as the passes draw them.
void appendObject(const ray::Scene& scene, const ray::Object& o, std::vector<TirVertex>& v,
                  std::vector<uint32_t>& idx) {
    const ray::Mesh& m = scene.meshes.at(o.mesh);
    const glm::mat3 nx = glm::transpose(glm::inverse(glm::mat3(o.transform)));
    const uint32_t base = uint32_t(v.size());
    for (size_t i = 0; i < m.positions.size(); ++i) {
        TirVertex t;
        t.position = glm::vec3(o.transform * glm::vec4(m.positions[i], 1.0f));
        const glm::vec3 n = nx * (i < m.normals.size() ? m.normals[i] : glm::vec3(0, 0, 1));
        const float len = glm::length(n);
        t.normal = len > 0.0f ? n / len : glm::vec3(0, 0, 1);
        t.uv = i < m.uvs.size() ? m.uvs[i] : glm::vec2(0.0f);
        v.push_back(t);
    }
    for (uint32_t i : m.indices) idx.push_back(base + i);
}

}  // namespace

const char* methodName(Method m) { return m == Method::Ours ? "ours" : "wyman05"; }

void validate(const TirSettings& s) {
    auto bad = [](const std::string& what) { throw Error("tir: " + what); };
    if (s.bounces < 0 || s.bounces > kMaxBounces)
        bad("bounces " + std::to_string(s.bounces) + " outside 0–" + std::to_string(kMaxBounces));
    if (s.width < 1 || s.height < 1 || s.width > g80().maxViewport || s.height > g80().maxViewport)
        bad("frame " + std::to_string(s.width) + "×" + std::to_string(s.height) +
            " outside what geforce8800 renders (1–" + std::to_string(g80().maxViewport) + ")");
    if (!(s.mapScale > 0.0f) || s.mapScale > 1.0f)
        bad("map scale " + std::to_string(s.mapScale) + " outside (0, 1]");
    const int side = std::max(s.width, s.height);
    const int most = int(std::ceil(std::log2(double(side) * s.mapScale))) + 4;
    for (int it : {s.itersFirst, s.itersLater, s.itersNearby})
        if (it < 1 || it > std::max(most, 16))
            bad("search iterations " + std::to_string(it) + " outside 1–" +
                std::to_string(std::max(most, 16)) + " (004 §3: log₂ of the map size suffices)");
    if (!(s.epsilon >= 0.0f) || !(s.missDegrees > 0.0f && s.missDegrees < 90.0f))
        bad("epsilon or miss angle out of range");
}

TirRenderer::TirRenderer(const TirScene& scene, int threads, Path path, int textureSize)
    : scene_(scene), memory_(g80()), device_(g80(), raster::DeviceOptions{path, threads}) {
    const ray::Scene& s = scene.scene;
    refractorIor(scene);
    appendObject(s, s.objects.at(scene.refractor), refractor_.vertices, refractor_.indices);
    // The refractor's bounding radius scales the start offset.
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (const TirVertex& v : refractor_.vertices) lo = glm::min(lo, v.position), hi = glm::max(hi, v.position);
    radius_ = 0.5f * glm::length(hi - lo);
    centre_ = 0.5f * (lo + hi);

    // Wyman 2005's d_N: from each vertex, inwards along −N, to the far side. Embree finds the
    // triangle; the distance is ours, to that triangle's plane in float in a fixed order:
    // Embree's own t comes from whichever kernel the CPU selects (AVX2 here, AVX-512
    // elsewhere) and differs by an ulp between them, and d_N is vertex data a golden trace
    // holds (tests/golden/programmable-tir-frame.trace).
    auto distanceToPlane = [this](const ray::Ray& r, uint32_t triangle) {
        const glm::vec3 a = refractor_.vertices[refractor_.indices[3 * size_t(triangle)]].position;
        const glm::vec3 b = refractor_.vertices[refractor_.indices[3 * size_t(triangle) + 1]].position;
        const glm::vec3 c = refractor_.vertices[refractor_.indices[3 * size_t(triangle) + 2]].position;
        const glm::vec3 n = glm::cross(b - a, c - a);
        const float along = glm::dot(r.dir, n);
        return along != 0.0f ? glm::dot(a - r.origin, n) / along : 0.0f;
    };
    {
        ray::Accel accel(s);
        for (TirVertex& v : refractor_.vertices) {
            ray::Ray r;
            r.dir = -v.normal;
            r.origin = v.position + r.dir * (1e-4f * radius_);
            const ray::Hit h = accel.intersect(r);
            v.dN = h.valid() && h.object == scene.refractor ? distanceToPlane(r, h.triangle) : 0.0f;
        }
    }

    // Plain colours sample a white texel; textured materials their texture, baked.
    tex::TextureDesc wd;
    white_ = memory_.create(wd);
    const Rgba8 whiteTexel{255, 255, 255, 255};
    memory_.upload(*white_, 0, 0, std::span<const Rgba8>(&whiteTexel, 1));
    for (size_t i = 0; i < s.objects.size(); ++i) {
        if (i == scene.refractor) continue;
        const ray::Object& o = s.objects[i];
        const ray::Material& m = s.materials.at(o.material);
        Batch b;
        appendObject(s, o, b.vertices, b.indices);
        b.albedo = m.diffuse;
        b.texture = white_;
        if (m.diffuseTexture >= 0 && !b.vertices.empty()) {
            // The texture baked over this object's own uv rectangle (raycore's room is
            // textured in metres, so uvs run past 1 and patterns need not repeat at 1),
            // the vertices' uvs mapped onto it.
            glm::vec2 lo(1e30f), hi(-1e30f);
            for (const TirVertex& v : b.vertices) lo = glm::min(lo, v.uv), hi = glm::max(hi, v.uv);
            const glm::vec2 size = glm::max(hi - lo, glm::vec2(1e-6f));
            for (TirVertex& v : b.vertices) v.uv = (v.uv - lo) / size;
            const ray::Texture& tx = s.textures.at(size_t(m.diffuseTexture));
            const int n = textureSize;
            tex::TextureDesc d;
            d.width = d.height = n;
            d.levels = tex::fullChainLevels(d);
            b.texture = memory_.create(d);
            std::vector<Rgba8> texels(size_t(n) * size_t(n));
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    const glm::vec3 c = tx.eval(lo + size * glm::vec2((float(x) + 0.5f) / float(n),
                                                                      (float(y) + 0.5f) / float(n)));
                    texels[size_t(y) * size_t(n) + size_t(x)] = {ray::quantize8(c.x), ray::quantize8(c.y),
                                                                 ray::quantize8(c.z), 255};
                }
            memory_.upload(*b.texture, 0, 0, std::span<const Rgba8>(texels));
            memory_.buildBoxMipmaps(*b.texture);
        }
        nearby_.push_back(std::move(b));
    }
}

TirRenderer::~TirRenderer() = default;

void TirRenderer::ensureTargets(const TirSettings& s) {
    const int mw = std::max(1, int(std::lround(double(s.width) * s.mapScale)));
    const int mh = std::max(1, int(std::lround(double(s.height) * s.mapScale)));
    if (mw != mapW_ || mh != mapH_) {
        tex::TextureDesc d;
        d.format = tex::TexelFormat::RGBA16F;
        d.width = mw;
        d.height = mh;
        backMap_ = memory_.createRenderTarget(d);
        frontMap_ = memory_.createRenderTarget(d);
        nearbyMap_ = memory_.createRenderTarget(d);
        d.format = tex::TexelFormat::Depth24;
        mapDepth_ = memory_.createRenderTarget(d);
        mapW_ = mw;
        mapH_ = mh;
    }
    if (s.width != frameW_ || s.height != frameH_) {
        tex::TextureDesc d;
        d.width = s.width;
        d.height = s.height;
        frame_ = memory_.createRenderTarget(d);
        d.format = tex::TexelFormat::Depth24;
        frameDepth_ = memory_.createRenderTarget(d);
        frameW_ = s.width;
        frameH_ = s.height;
    }
    if (s.envSize != envSize_) {
        bakeSurroundings(s.envSize);
        envSize_ = s.envSize;
    }
}

TirRenderer::View TirRenderer::makeView(const glm::mat4& view, float px, float py, float near, float far) const {
    View v;
    v.vp.view = view;
    v.vp.px = px;
    v.vp.py = py;
    v.vp.pz = far / (near - far);           // glm::perspectiveRH_ZO's [2][2] and [3][2]
    v.vp.pw = -(far * near) / (far - near);
    SearchConstants& k = v.k;
    k.px = v.vp.px, k.py = v.vp.py, k.pz = v.vp.pz, k.pw = v.vp.pw;
    k.invPx = 1.0f / px;
    k.invPy = 1.0f / py;
    k.far = far;
    k.invFar = 1.0f / far;
    k.eta = refractorIor(scene_);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) k.eyeToWorld[3 * i + j] = view[i][j];
    const ray::Scene& scene = scene_.scene;
    v.lighting.ambient = scene.ambient;
    v.lighting.invFar = k.invFar;
    v.lighting.lights = int32_t(std::min<size_t>(scene.lights.size(), NearbyFP::kMaxLights));
    for (int i = 0; i < v.lighting.lights; ++i) {
        v.lighting.lightEye[i] = glm::vec3(view * glm::vec4(scene.lights[size_t(i)].position, 1.0f));
        v.lighting.lightIntensity[i] = scene.lights[size_t(i)].intensity;
    }
    return v;
}

float TirRenderer::farthestFrom(glm::vec3 eye) const {
    float farthest = 0.0f;
    auto reach = [&](const std::vector<TirVertex>& vs) {
        for (const TirVertex& v : vs) farthest = std::max(farthest, glm::length(v.position - eye));
    };
    reach(refractor_.vertices);
    for (const Batch& b : nearby_) reach(b.vertices);
    return std::max(1e-3f, farthest * 1.02f);
}

void TirRenderer::bakeSurroundings(int size) {
    // The world as a float cube map, each texel the scene's environment along the direction
    // through its centre (raycore's lookup: the reference sees the same world).
    tex::TextureDesc d;
    d.target = tex::TextureTarget::CubeMap;
    d.format = tex::TexelFormat::RGBA32F;
    d.width = d.height = size;
    world_ = memory_.create(d);
    std::vector<float> texels(size_t(size) * size_t(size) * 4);
    for (int f = 0; f < 6; ++f) {
        for (int y = 0; y < size; ++y)
            for (int x = 0; x < size; ++x) {
                const glm::vec3 dir = tex::cubeFaceDirection(tex::CubeFace(f), (float(x) + 0.5f) / float(size),
                                                             (float(y) + 0.5f) / float(size));
                const glm::vec3 c = scene_.scene.environment.lookup(glm::normalize(dir));
                float* t = &texels[(size_t(y) * size_t(size) + size_t(x)) * 4];
                t[0] = c.x, t[1] = c.y, t[2] = c.z, t[3] = 1.0f;
            }
        memory_.upload(*world_, 0, f,
                       std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(texels.data()),
                                                texels.size() * sizeof(float)));
    }
    // The environment the exit rays read: the world and the nearby geometry seen from the
    // refractor's centre, rendered once into a cube map (six 90° passes of pass 3's
    // program), so that a ray leaving the view frustum still finds the room around it —
    // 004 §3's "intersect this ray with the nearby geometry and or an environment map".
    d.format = tex::TexelFormat::RGBA16F;
    env_ = memory_.createRenderTarget(d);
    tex::TextureDesc dd;
    dd.format = tex::TexelFormat::Depth24;
    dd.width = dd.height = size;
    auto depth = memory_.createRenderTarget(dd);
    const float far = farthestFrom(centre_);
    for (int f = 0; f < 6; ++f) {
        // Eye axes from the face's own mapping: x along increasing s, y against increasing t
        // (window rows run down), looking along the face's major axis.
        const tex::CubeFace face = tex::CubeFace(f);
        const glm::vec3 ahead = tex::cubeFaceDirection(face, 0.5f, 0.5f);
        const glm::vec3 right = tex::cubeFaceDirection(face, 1.0f, 0.5f) - ahead;
        const glm::vec3 up = ahead - tex::cubeFaceDirection(face, 0.5f, 1.0f);
        glm::mat4 view(1.0f);
        for (int c = 0; c < 3; ++c) {
            view[c][0] = right[c];
            view[c][1] = up[c];
            view[c][2] = -ahead[c];
        }
        view = view * glm::translate(glm::mat4(1.0f), -centre_);
        const View v = makeView(view, 1.0f, 1.0f, far / 500.0f, far);
        ColorTarget ct{env_, 0, f};
        device_.setRenderTargets({&ct, 1}, DepthTarget{depth});
        device_.clearColor(0, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));
        device_.clearDepth(1.0f);
        drawNearby(v, false);
        drawEnvironment(v, size, size);
    }
}

void TirRenderer::passNormalDepth(const EyeVP& vp, float invFar, const std::shared_ptr<tex::Texture>& map,
                                  const std::shared_ptr<tex::Texture>& depth, raster::CullMode cull) {
    ColorTarget ct{map};
    device_.setRenderTargets({&ct, 1}, DepthTarget{depth});
    device_.clearColor(0, glm::vec4(0.0f, 0.0f, 0.0f, 1.0f));  // w = 1: nothing here
    device_.clearDepth(1.0f);
    raster::ProgramState st;
    st.cull = cull;
    st.depthTest = st.depthWrite = 1;
    device_.setState(st);
    NormalDepthFP fp;
    fp.invFar = invFar;
    device_.draw(vp, fp, ProgramPrimitive::TriangleList, std::span<const TirVertex>(refractor_.vertices),
                 std::span<const uint32_t>(refractor_.indices));
}

void TirRenderer::drawEnvironment(const View& v, int width, int height) {
    // After the geometry, behind it: the depth test (no write) leaves it only the pixels
    // nothing covers.
    raster::ProgramState st;
    st.depthTest = 1;
    device_.setState(st);
    EnvFP fp;
    fp.k = v.k;
    fp.invWidth = 1.0f / float(width);
    fp.invHeight = 1.0f / float(height);
    device_.setTexture(0, world_, tex::SamplerState{});
    device_.draw(ScreenVP{}, fp, ProgramPrimitive::TriangleList, std::span<const TirVertex>(kCoverBehind, 3));
}

void TirRenderer::drawNearby(const View& v, bool depthInAlpha) {
    raster::ProgramState st;
    st.cull = raster::CullMode::None;  // walls are seen from inside
    st.depthTest = st.depthWrite = 1;
    device_.setState(st);
    for (const Batch& b : nearby_) {
        NearbyFP fp = v.lighting;
        fp.albedo = b.albedo;
        fp.depthInAlpha = depthInAlpha ? 1 : 0;
        device_.setTexture(0, b.texture, b.texture == white_ ? pointSampler() : trilinearSampler());
        device_.draw(v.vp, fp, ProgramPrimitive::TriangleList, std::span<const TirVertex>(b.vertices),
                     std::span<const uint32_t>(b.indices));
    }
}

TirFrame TirRenderer::render(const ray::Camera& camera, const TirSettings& s) {
    validate(s);
    ensureTargets(s);
    // ---- the camera: far fitted to the scene (linear depth spends binary16's 11 bits
    // between the eye and it), near at 1/500 of it for the depth buffer's test ------------
    const float far = farthestFrom(camera.eye);
    const glm::mat4 view = glm::lookAt(camera.eye, camera.target, camera.up);
    const float py = 1.0f / std::tan(glm::radians(camera.fovYDegrees) * 0.5f);
    const View v = makeView(view, py * float(s.height) / float(s.width), py, far / 500.0f, far);
    const EyeVP& vp = v.vp;
    eyeVP_ = vp;
    constants_ = v.k;
    SearchConstants& k = constants_;
    k.epsilon = s.epsilon * radius_;
    k.cosMiss = float(std::cos(double(s.missDegrees) * 3.14159265358979323846 / 180.0));
    k.minDistance2 = (2.0f * k.epsilon) * (2.0f * k.epsilon);
    k.bounces = s.bounces;
    k.itersFirst = s.itersFirst;
    k.itersLater = s.itersLater;
    k.itersNearby = s.itersNearby;
    k.frontAndBack = s.frontAndBack ? 1 : 0;
    k.searchNearby = s.searchNearby ? 1 : 0;

    TirFrame frame;
    const auto tFrame = Clock::now();
    auto pass = [&](const char* name, auto&& body) {
        device_.beginFrame();
        const auto t0 = Clock::now();
        body();
        frame.passes.push_back({name, std::chrono::duration<double, std::milli>(Clock::now() - t0).count(),
                                device_.counters()});
    };
    // Passes 1 and 2: the nearest back face (front faces culled), then the nearest front
    // face. The meshes wind counter-clockwise seen from outside and stay counter-clockwise
    // on the screen (the y-down window and the view's mirror cancel): D3DCULL_CCW culls
    // front faces, D3DCULL_CW back faces (docs/hardware.md, "Orientation and culling").
    pass("back faces: normals and depth", [&] { passNormalDepth(vp, k.invFar, backMap_, mapDepth_, raster::CullMode::CCW); });
    pass("front faces: normals and depth", [&] { passNormalDepth(vp, k.invFar, frontMap_, mapDepth_, raster::CullMode::CW); });
    pass("nearby geometry: colour and depth", [&] {
        ColorTarget ct{nearbyMap_};
        device_.setRenderTargets({&ct, 1}, DepthTarget{mapDepth_});
        device_.clearDepth(1.0f);
        drawNearby(v, true);
        drawEnvironment(v, mapW_, mapH_);  // the world behind, w = 1: empty for the searches
    });
    const bool sameSize = mapW_ == frameW_ && mapH_ == frameH_;
    pass(s.method == Method::Ours ? "final: refraction with TIR" : "final: Wyman 2005", [&] {
        ColorTarget ct{frame_};
        if (sameSize) {
            // The background is pass 3's map, with pass 3's depth buffer for the refractor's
            // depth test.
            device_.setRenderTargets({&ct, 1}, DepthTarget{mapDepth_});
            device_.setState(raster::ProgramState{});
            CopyFP copy;
            copy.invWidth = 1.0f / float(frameW_);
            copy.invHeight = 1.0f / float(frameH_);
            device_.setTexture(0, nearbyMap_, pointSampler());
            device_.draw(ScreenVP{}, copy, ProgramPrimitive::TriangleList, std::span<const TirVertex>(kCover, 3));
        } else {
            // Smaller maps (Figure 7): the background drawn again at the frame's size.
            device_.setRenderTargets({&ct, 1}, DepthTarget{frameDepth_});
            device_.clearDepth(1.0f);
            drawNearby(v, false);
            drawEnvironment(v, s.width, s.height);
        }
        raster::ProgramState st;
        st.cull = raster::CullMode::CW;  // the refractor's front faces
        st.depthTest = st.depthWrite = 1;
        device_.setState(st);
        device_.setTexture(kUnitBack, backMap_, pointSampler());
        device_.setTexture(kUnitFront, frontMap_, pointSampler());
        device_.setTexture(kUnitNearby, nearbyMap_, pointSampler());
        tex::SamplerState envSampler;  // bilinear; cube maps clamp to their face edges
        device_.setTexture(kUnitEnv, env_, envSampler);
        const auto verts = std::span<const TirVertex>(refractor_.vertices);
        const auto idx = std::span<const uint32_t>(refractor_.indices);
        // The refractor's own counters: the pass's so far subtracted.
        const raster::ProgramCounters before = device_.counters();
        if (s.method == Method::Ours) {
            TirFP fp;
            fp.k = k;
            device_.draw(vp, fp, ProgramPrimitive::TriangleList, verts, idx);
        } else {
            Wyman05FP fp;
            fp.k = k;
            device_.draw(vp, fp, ProgramPrimitive::TriangleList, verts, idx);
        }
        refractiveFragments_ = int64_t(device_.counters().fragmentInvocations - before.fragmentInvocations);
        refractiveFetches_ = int64_t(device_.counters().textureFetches - before.textureFetches);
    });
    frame.totalMs = std::chrono::duration<double, std::milli>(Clock::now() - tFrame).count();
    frame.refractiveFragments = refractiveFragments_;
    frame.fetchesPerRefractiveFragment =
        refractiveFragments_ ? double(refractiveFetches_) / double(refractiveFragments_) : 0.0;
    return frame;
}

ray::Image TirRenderer::frame() const {
    ray::Image img(frameW_, frameH_, 3);
    const Rgba8* p = const_cast<tex::Texture&>(*frame_).renderData8(0, 0);
    for (int y = 0; y < frameH_; ++y)
        for (int x = 0; x < frameW_; ++x) {
            const Rgba8 c = p[size_t(y) * size_t(frameW_) + size_t(x)];
            img.setRgb(x, y, glm::vec3(c.r, c.g, c.b) / 255.0f);
        }
    return img;
}

ray::Image TirRenderer::mapImage(const tex::Texture& map, int which) const {
    ray::Image img(mapW_, mapH_, 3);
    const glm::vec4* p = const_cast<tex::Texture&>(map).renderDataF(0, 0);
    for (int y = 0; y < mapH_; ++y)
        for (int x = 0; x < mapW_; ++x) {
            const glm::vec4 t = p[size_t(y) * size_t(mapW_) + size_t(x)];
            const bool empty = t.w >= 1.0f;
            glm::vec3 c(0.0f);
            if (which == 0 && !empty) c = 0.5f + 0.5f * glm::vec3(t);  // normal
            if (which == 1) c = glm::vec3(empty ? 1.0f : std::min(1.0f, t.w * 4.0f));  // depth ×4
            if (which == 2 && !empty) c = glm::vec3(t);  // colour
            img.setRgb(x, y, c);
        }
    return img;
}

ray::Image TirRenderer::backNormals() const { return mapImage(*backMap_, 0); }
ray::Image TirRenderer::backDepth() const { return mapImage(*backMap_, 1); }
ray::Image TirRenderer::frontNormals() const { return mapImage(*frontMap_, 0); }
ray::Image TirRenderer::frontDepth() const { return mapImage(*frontMap_, 1); }
ray::Image TirRenderer::nearbyColor() const { return mapImage(*nearbyMap_, 2); }
ray::Image TirRenderer::nearbyDepth() const { return mapImage(*nearbyMap_, 1); }

uint64_t TirRenderer::textureBytes() const { return memory_.residentBytes(); }

}  // namespace rg::tir
