#include "impostor_renderer.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include "core/error.h"
#include "core/profile.h"
#include "impostor_height_maps.h"
#include "impostor_height_programs.h"
#include "raycore/texture.h"
#include "texunit/cube_mapping.h"

namespace rg::impostors {

namespace {

using Clock = std::chrono::steady_clock;
using raster::ColorTarget;
using raster::DepthTarget;
using raster::ProgramPrimitive;

const Profile& g80() { return profile(ProfileId::GeForce8800); }

// One triangle over the whole target at depth z: the sky, behind everything drawn before it
// (far is fitted beyond the scene, so geometry's window z stays below this).
constexpr float kBehind = 1.0f - 1.0f / 1048576.0f;
const ImpostorVertex kCoverBehind[3] = {{{-1, -1, kBehind}, {}, {}}, {{3, -1, kBehind}, {}, {}}, {{-1, 3, kBehind}, {}, {}}};

tex::SamplerState pointClamp() {
    tex::SamplerState s;
    s.magFilter = s.minFilter = tex::FilterMode::Nearest;
    s.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge,
                 tex::AddressMode::ClampToEdge};
    return s;
}
tex::SamplerState linearClamp(bool mip) {
    tex::SamplerState s;
    if (mip) s.mipFilter = tex::MipMode::Linear;
    s.address = {tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge, tex::AddressMode::ClampToEdge,
                 tex::AddressMode::ClampToEdge};
    return s;
}

// The world-space triangles of a mesh under a transform.
void appendMesh(const ray::Mesh& m, const glm::mat4& xf, std::vector<ImpostorVertex>& v, std::vector<uint32_t>& idx) {
    const glm::mat3 nx = glm::transpose(glm::inverse(glm::mat3(xf)));
    const uint32_t base = uint32_t(v.size());
    for (size_t i = 0; i < m.positions.size(); ++i) {
        ImpostorVertex t;
        t.position = glm::vec3(xf * glm::vec4(m.positions[i], 1.0f));
        const glm::vec3 n = nx * (i < m.normals.size() ? m.normals[i] : glm::vec3(0, 0, 1));
        const float len = glm::length(n);
        t.normal = len > 0.0f ? n / len : glm::vec3(0, 0, 1);
        t.uv = i < m.uvs.size() ? m.uvs[i] : glm::vec2(0.0f);
        v.push_back(t);
    }
    for (uint32_t i : m.indices) idx.push_back(base + i);
}

void bounds(std::vector<ImpostorVertex>& v, glm::vec3& lo, glm::vec3& hi) {
    lo = glm::vec3(1e30f), hi = glm::vec3(-1e30f);
    for (const ImpostorVertex& x : v) lo = glm::min(lo, x.position), hi = glm::max(hi, x.position);
}

// Whether the linear part of a transform is a rotation (so that the mesh's refractor map
// serves the object turned into its frame).
bool isRotation(const glm::mat4& xf) {
    const glm::mat3 m(xf);
    const glm::mat3 mtm = glm::transpose(m) * m;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            if (std::fabs(mtm[i][j] - (i == j ? 1.0f : 0.0f)) > 1e-4f) return false;
    return glm::determinant(m) > 0.0f;
}

// The view's rotation inverted (rows), as the sky program turns eye directions.
void toWorldRows(const glm::mat4& view, float (&rows)[9]) {
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) rows[3 * i + j] = view[i][j];
}

// The planes of a clip-space frustum (D3D: −w ≤ x, y ≤ w, 0 ≤ z ≤ w) in world space, from
// the view-projection matrix's rows (Gribb & Hartmann), normals inward.
void frustumPlanes(const glm::mat4& vp, glm::vec4 (&planes)[6]) {
    const glm::mat4 t = glm::transpose(vp);  // rows of vp as columns
    const glm::vec4 r0 = t[0], r1 = t[1], r2 = t[2], r3 = t[3];
    planes[0] = r3 + r0;
    planes[1] = r3 - r0;
    planes[2] = r3 + r1;
    planes[3] = r3 - r1;
    planes[4] = r2;
    planes[5] = r3 - r2;
}

}  // namespace

const char* modeName(Mode m) {
    switch (m) {
        case Mode::Static: return "static";
        case Mode::Classical: return "classical";
        case Mode::Separated: return "separated";
        case Mode::RefractorMapsOnly: return "refractor-maps-only";
    }
    return "?";
}

Mode modeByName(const std::string& name) {
    for (Mode m : {Mode::Static, Mode::Classical, Mode::Separated, Mode::RefractorMapsOnly})
        if (name == modeName(m)) return m;
    throw Error("impostors: unknown mode '" + name + "' (static, classical, separated, refractor-maps-only)");
}

const char* exitName(Exit e) { return e == Exit::HeightMap ? "height-map" : "distance-map"; }

Exit exitByName(const std::string& name) {
    for (Exit e : {Exit::DistanceMap, Exit::HeightMap})
        if (name == exitName(e)) return e;
    throw Error("impostors: unknown exit '" + name + "' (distance-map, height-map)");
}

void validate(const ImpostorSettings& s) {
    auto bad = [](const std::string& what) { throw Error("impostors: " + what); };
    if (s.depth < 1 || s.depth > kMaxDepth)
        bad("DEPTH " + std::to_string(s.depth) + " outside 1–" + std::to_string(kMaxDepth) +
            " (002 §5.1: each iteration adds one bounce; " + std::to_string(kMaxDepth) + " is far past what the images show)");
    if (s.iterations < 0 || s.iterations > kMaxIterations)
        bad("secant iterations " + std::to_string(s.iterations) + " outside 0–" + std::to_string(kMaxIterations));
    // Mode A has no height-map search: the exit is refused rather than drawn with distance maps.
    if (s.mode == Mode::RefractorMapsOnly && s.exit == Exit::HeightMap)
        bad("the refractor-maps-only mode (§4.2, mode A) searches refractor distance maps only; the height-map exit "
            "(§6) is for the modes with environment impostors (static, classical, separated)");
    const Profile& p = g80();
    if (s.width < 1 || s.height < 1 || s.width > p.maxViewport || s.height > p.maxViewport)
        bad("frame " + std::to_string(s.width) + "×" + std::to_string(s.height) + " outside what geforce8800 renders (1–" +
            std::to_string(p.maxViewport) + ", its largest viewport)");
    auto cubeSize = [&](int v, const char* what) {
        if (v < 1 || v > p.maxCubeMapSize)
            bad(std::string(what) + " " + std::to_string(v) + "² outside 1–" + std::to_string(p.maxCubeMapSize) +
                "² (geforce8800's largest cube-map face)");
    };
    cubeSize(s.envSize, "environment impostor");
    cubeSize(s.refractorSize, "refractor distance map");
    for (int v : {s.lightMapSize, s.shadowMapSize})
        if (v < 1 || v > p.maxTextureSize)
            bad("light or shadow map " + std::to_string(v) + "² outside 1–" + std::to_string(p.maxTextureSize) +
                "² (geforce8800's largest 2D texture)");
    if (s.caustics) {
        // A photon map is a render target the photon pass's viewport covers whole.
        const int most = std::min(p.maxTextureSize, p.maxViewport);
        if (s.photonMapSize < 1 || s.photonMapSize > most)
            bad("photon map " + std::to_string(s.photonMapSize) + "² outside 1–" + std::to_string(most) +
                "² (geforce8800's largest 2D render target and viewport)");
        if (!(s.causticSigma >= 0.25f && s.causticSigma <= 16.0f))
            bad("caustic splat σ " + std::to_string(s.causticSigma) +
                " light-map texels outside 0.25–16 (below, a splat misses texel centres; above, one photon covers "
                "a 97-texel square)");
    }
    if (s.heightMapSize < 8 || s.heightMapSize > p.maxTextureSize)
        bad("refractor height map " + std::to_string(s.heightMapSize) + "² outside 8–" + std::to_string(p.maxTextureSize) +
            "² (geforce8800's largest 2D texture)");
    if (s.heightSteps < 1 || s.heightSteps > kMaxIterations)
        bad("height-map binary-search steps " + std::to_string(s.heightSteps) + " outside 1–" +
            std::to_string(kMaxIterations));
    if (!(s.moverU >= 0.0f && s.moverU <= 1.0f)) bad("mover position " + std::to_string(s.moverU) + " outside [0, 1]");
    if (!(s.epsilon >= 0.0f) || !std::isfinite(s.epsilon)) bad("validity ε " + std::to_string(s.epsilon) + " is negative");
}

glm::mat4 cubeFaceView(int face, const glm::vec3& centre) {
    // Eye axes from the face's own mapping: x along increasing s, y against increasing t
    // (window rows run down), looking along the face's major axis. The result is a mirror
    // image of a right-handed view (cube maps are left-handed), so winding flips.
    const tex::CubeFace f = tex::CubeFace(face);
    const glm::vec3 ahead = tex::cubeFaceDirection(f, 0.5f, 0.5f);
    const glm::vec3 right = tex::cubeFaceDirection(f, 1.0f, 0.5f) - ahead;
    const glm::vec3 up = ahead - tex::cubeFaceDirection(f, 0.5f, 1.0f);
    glm::mat4 view(1.0f);
    for (int c = 0; c < 3; ++c) {
        view[c][0] = right[c];
        view[c][1] = up[c];
        view[c][2] = -ahead[c];
    }
    return view * glm::translate(glm::mat4(1.0f), -centre);
}

glm::mat4 cubeFaceProjection(float near, float far) {
    // glm::perspectiveRH_ZO at 90° with 1/tan(45°) written as exactly 1.
    glm::mat4 p(0.0f);
    p[0][0] = 1.0f;
    p[1][1] = 1.0f;
    p[2][2] = far / (near - far);
    p[2][3] = -1.0f;
    p[3][2] = -(far * near) / (far - near);
    return p;
}

ImpostorRenderer::ImpostorRenderer(const ImpostorScene& scene, int threads, Path path)
    : scene_(scene), memory_(g80()), device_(g80(), raster::DeviceOptions{path, threads}) {
    const ray::Scene& s = scene.scene;
    if (scene.glass.empty()) throw Error("impostors: scene '" + s.name + "' has no glass or mirror object");
    // Plain colours sample a white texel; textured materials their texture, baked over the
    // object's own uv rectangle (RGBA8, box mipmaps, trilinear).
    tex::TextureDesc wd;
    white_ = memory_.create(wd);
    const Rgba8 whiteTexel{255, 255, 255, 255};
    memory_.upload(*white_, 0, 0, std::span<const Rgba8>(&whiteTexel, 1));
    for (size_t i = 0; i < s.objects.size(); ++i) {
        const ray::Object& o = s.objects[i];
        const ray::Material& m = s.materials.at(o.material);
        if (std::find(scene.glass.begin(), scene.glass.end(), uint32_t(i)) != scene.glass.end()) continue;
        Batch b;
        appendMesh(s.meshes.at(o.mesh), o.transform, b.vertices, b.indices);
        bounds(b.vertices, b.lo, b.hi);
        std::shared_ptr<tex::Texture> texture = white_;
        if (m.diffuseTexture >= 0 && !b.vertices.empty()) {
            glm::vec2 lo(1e30f), hi(-1e30f);
            for (const ImpostorVertex& v : b.vertices) lo = glm::min(lo, v.uv), hi = glm::max(hi, v.uv);
            const glm::vec2 size = glm::max(hi - lo, glm::vec2(1e-6f));
            for (ImpostorVertex& v : b.vertices) v.uv = (v.uv - lo) / size;
            const ray::Texture& tx = s.textures.at(size_t(m.diffuseTexture));
            const int n = 512;
            tex::TextureDesc d;
            d.width = d.height = n;
            d.levels = tex::fullChainLevels(d);
            texture = memory_.create(d);
            std::vector<Rgba8> texels(size_t(n) * size_t(n));
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    const glm::vec3 c = tx.eval(lo + size * glm::vec2((float(x) + 0.5f) / float(n), (float(y) + 0.5f) / float(n)));
                    texels[size_t(y) * size_t(n) + size_t(x)] = {ray::quantize8(c.x), ray::quantize8(c.y),
                                                                 ray::quantize8(c.z), 255};
                }
            memory_.upload(*texture, 0, 0, std::span<const Rgba8>(texels));
            memory_.buildBoxMipmaps(*texture);
        }
        diffuse_.push_back(std::move(b));
        diffuseMaterials_.push_back(m);
        diffuseTextures_.push_back(texture);
    }
    // The glass objects and their refractor maps: one per mesh for objects placed by a
    // rotation (the chess pieces of a kind share one, §4.2), one of its own otherwise.
    for (uint32_t oi : scene.glass) {
        const ray::Object& o = s.objects[oi];
        Glass g;
        g.object = oi;
        const bool shared = isRotation(o.transform);
        int found = -1;
        for (size_t r = 0; r < refractors_.size(); ++r)
            if (shared && refractors_[r].object < 0 && refractors_[r].mesh == o.mesh) found = int(r);
        if (found < 0) {
            Refractor r;
            r.mesh = o.mesh;
            r.object = shared ? -1 : int(oi);
            appendMesh(s.meshes.at(o.mesh), shared ? glm::mat4(1.0f) : o.transform, r.model.vertices, r.model.indices);
            bounds(r.model.vertices, r.lo, r.hi);
            r.centre = 0.5f * (r.lo + r.hi);
            r.model.lo = r.lo;
            r.model.hi = r.hi;
            refractors_.push_back(std::move(r));
            found = int(refractors_.size()) - 1;
        }
        g.refractor = found;
        if (int(oi) == scene.mover) moverGlass_ = int(glass_.size());
        glass_.push_back(std::move(g));
    }
    frames_.resize(glass_.size());
    placeMover(0.0f);
    boardSetup();
    // The sky as a float cube, each texel the environment along its centre's direction
    // (raycore's lookup: the reference sees the same sky), read bilinearly.
    const int n = 64;
    tex::TextureDesc d;
    d.target = tex::TextureTarget::CubeMap;
    d.format = tex::TexelFormat::RGBA32F;
    d.width = d.height = n;
    world_ = memory_.create(d);
    std::vector<float> texels(size_t(n) * size_t(n) * 4);
    for (int f = 0; f < 6; ++f) {
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) {
                const glm::vec3 dir =
                    tex::cubeFaceDirection(tex::CubeFace(f), (float(x) + 0.5f) / float(n), (float(y) + 0.5f) / float(n));
                const glm::vec3 c = s.environment.lookup(glm::normalize(dir));
                float* t = &texels[(size_t(y) * size_t(n) + size_t(x)) * 4];
                t[0] = c.x, t[1] = c.y, t[2] = c.z, t[3] = 1.0f;
            }
        memory_.upload(*world_, 0, f,
                       std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(texels.data()), texels.size() * sizeof(float)));
    }
}

ImpostorRenderer::~ImpostorRenderer() = default;  // caustics_: a shared_ptr, complete where it is made

void ImpostorRenderer::invalidate() {
    content_ = Content::None;
    impostorKey_.clear();
    lightKey_.clear();
    causticKey_.clear();
    moverU_ = -1.0f;
}

void ImpostorRenderer::placeMover(float u) {
    if (u == moverU_) return;
    moverU_ = u;
    const ray::Scene& s = scene_.scene;
    for (size_t i = 0; i < glass_.size(); ++i) {
        Glass& g = glass_[i];
        if (!g.world.vertices.empty() && int(i) != moverGlass_) continue;
        const ray::Object& o = s.objects[g.object];
        const glm::mat4 xf = int(i) == moverGlass_ ? scene_.moverTransform(u) : o.transform;
        g.world = Batch{};
        appendMesh(s.meshes.at(o.mesh), xf, g.world.vertices, g.world.indices);
        bounds(g.world.vertices, g.world.lo, g.world.hi);
    }
}

ObjectFrame ImpostorRenderer::frameOf(const Glass& g, const ImpostorSettings& s) const {
    const ray::Scene& sc = scene_.scene;
    const ray::Object& o = sc.objects[g.object];
    const ray::Material& m = sc.materials.at(o.material);
    const Refractor& r = refractors_[size_t(g.refractor)];
    const glm::mat4 xf = int(&g - glass_.data()) == moverGlass_ ? scene_.moverTransform(moverU_) : o.transform;
    ObjectFrame f;
    glm::vec3 c = r.centre;
    glm::mat3 rot(1.0f);
    if (r.object < 0) {
        c = glm::vec3(xf * glm::vec4(r.centre, 1.0f));
        rot = glm::mat3(xf);
    }
    for (int i = 0; i < 3; ++i) {
        f.centre[i] = c[i];
        f.boxLo[i] = r.lo[i] - r.centre[i];
        f.boxHi[i] = r.hi[i] - r.centre[i];
        for (int j = 0; j < 3; ++j) f.toLocal[3 * i + j] = rot[i][j];  // row i: column i of rot (rot⁻¹ = rotᵀ)
    }
    f.mirror = m.type == ray::MaterialType::Mirror ? 1 : 0;
    f.mirrorSchlick = m.fresnel == ray::MirrorFresnel::Schlick ? 1 : 0;
    f.eta = m.ior;
    f.f0 = ((m.ior - 1.0f) / (m.ior + 1.0f)) * ((m.ior - 1.0f) / (m.ior + 1.0f));
    for (int i = 0; i < 3; ++i) {
        f.absorption[i] = m.transmittance[i] > 0.0f ? -std::log(m.transmittance[i]) : 16.0f;
        f.reflectance[i] = m.reflectance[i];
    }
    f.epsilon = s.epsilon * 0.5f * glm::length(r.hi - r.lo);
    return f;
}

std::shared_ptr<tex::Texture> ImpostorRenderer::cubeTarget(int size) {
    tex::TextureDesc d;
    d.target = tex::TextureTarget::CubeMap;
    d.format = tex::TexelFormat::RGBA16F;
    d.width = d.height = size;
    return memory_.createRenderTarget(d);
}

ImpostorRenderer::View ImpostorRenderer::cameraView(const ray::Camera& c, int width, int height) const {
    View v;
    v.eye = c.eye;
    float far = 1e-3f;
    auto reach = [&](const Batch& b) {
        for (int k = 0; k < 8; ++k) {
            const glm::vec3 p((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z);
            far = std::max(far, glm::length(p - c.eye));
        }
    };
    for (const Batch& b : diffuse_) reach(b);
    for (const Glass& g : glass_) reach(g.world);
    far *= 1.02f;
    const float near = far / 2000.0f;
    const glm::mat4 view = glm::lookAt(c.eye, c.target, c.up);
    const float py = 1.0f / std::tan(glm::radians(c.fovYDegrees) * 0.5f);
    const float px = py * float(height) / float(width);
    glm::mat4 proj(0.0f);
    proj[0][0] = px;
    proj[1][1] = py;
    proj[2][2] = far / (near - far);
    proj[2][3] = -1.0f;
    proj[3][2] = -(far * near) / (far - near);
    v.viewProj = proj * view;
    toWorldRows(view, v.sky.toWorld);
    v.sky.invPx = 1.0f / px;
    v.sky.invPy = 1.0f / py;
    v.sky.invWidth = 1.0f / float(width);
    v.sky.invHeight = 1.0f / float(height);
    v.backFaces = raster::CullMode::CW;  // counter-clockwise meshes stay so on the y-down window
    frustumPlanes(v.viewProj, v.planes);
    return v;
}

ImpostorRenderer::View ImpostorRenderer::faceView(int face, const glm::vec3& centre, int size) const {
    View v;
    v.eye = centre;
    v.cube = true;
    float far = 1e-3f;
    auto reach = [&](const Batch& b) {
        for (int k = 0; k < 8; ++k) {
            const glm::vec3 p((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z);
            far = std::max(far, glm::length(p - centre));
        }
    };
    for (const Batch& b : diffuse_) reach(b);
    for (const Glass& g : glass_) reach(g.world);
    far *= 1.02f;
    const glm::mat4 view = cubeFaceView(face, centre);
    v.viewProj = cubeFaceProjection(far / 4000.0f, far) * view;
    toWorldRows(view, v.sky.toWorld);
    v.sky.invWidth = v.sky.invHeight = 1.0f / float(size);
    v.sky.writeDistance = 1;
    // The face's view is a mirror image: back faces wind the other way.
    v.backFaces = raster::CullMode::CCW;
    frustumPlanes(v.viewProj, v.planes);
    return v;
}

bool ImpostorRenderer::visible(const View& v, const Batch& b) const {
    for (const glm::vec4& p : v.planes) {
        // The box corner farthest along the plane's normal.
        const glm::vec3 q(p.x >= 0 ? b.hi.x : b.lo.x, p.y >= 0 ? b.hi.y : b.lo.y, p.z >= 0 ? b.hi.z : b.lo.z);
        if (p.x * q.x + p.y * q.y + p.z * q.z + p.w < 0.0f) return false;
    }
    return true;
}

void ImpostorRenderer::buildRefractors(int size) {
    tex::TextureDesc dd;
    dd.format = tex::TexelFormat::Depth24;
    dd.width = dd.height = size;
    auto depth = memory_.createRenderTarget(dd);
    for (Refractor& r : refractors_) {
        if (r.size == size && r.cube) continue;
        r.cube = cubeTarget(size);
        r.size = size;
        const float far = 2.0f * glm::length(r.hi - r.lo) + 1e-3f;
        for (int f = 0; f < 6; ++f) {
            ColorTarget ct{r.cube, 0, f};
            device_.setRenderTargets({&ct, 1}, DepthTarget{depth});
            // Directions that see no surface (a centre outside the mesh) keep distance 0.
            device_.clearColor(0, glm::vec4(0.0f, 0.0f, 0.0f, 0.0f));
            device_.clearDepth(1.0f);
            raster::ProgramState st;
            st.cull = raster::CullMode::None;  // the surface seen from inside: its back faces
            st.depthTest = st.depthWrite = 1;
            device_.setState(st);
            WorldVP vp;
            vp.viewProj = cubeFaceProjection(far / 4000.0f, far) * cubeFaceView(f, r.centre);
            NormalDistanceFP fp;
            for (int i = 0; i < 3; ++i) fp.centre[i] = r.centre[i];
            drawTriangles(device_, vp, fp, std::span<const ImpostorVertex>(r.model.vertices),
                          std::span<const uint32_t>(r.model.indices));
        }
    }
}

void ImpostorRenderer::buildHeightMaps(int size, int steps) {
    // 002 §6: per mesh (the six piece kinds and the sphere, like the refractor distance maps)
    // the orthographic picture over its plane of symmetry, taken by raycore's Embree tracer and
    // uploaded as a texture the glass programs read (RGBA32F: normal, height; point sampled).
    for (Refractor& r : refractors_) {
        if (r.heightSize == size && r.height && r.heightFrame.steps == steps) continue;
        ray::Mesh m;
        m.name = "refractor";
        for (const ImpostorVertex& v : r.model.vertices) {
            m.positions.push_back(v.position);
            m.normals.push_back(v.normal);
            m.uvs.push_back(v.uv);
        }
        m.indices = r.model.indices;
        const HeightMap hm = buildHeightMap(m, r.centre, size, steps);
        tex::TextureDesc d;
        d.format = tex::TexelFormat::RGBA32F;
        d.width = d.height = size;
        r.height = memory_.create(d);
        memory_.upload(*r.height, 0, 0,
                       std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(hm.texels.data()),
                                                hm.texels.size() * sizeof(glm::vec4)));
        r.heightFrame = hm.frame;
        r.heightSize = size;
    }
}

void ImpostorRenderer::buildLightMaps(const ImpostorSettings& s, bool staticMap, bool moverMap, bool moverInStatic) {
    const ray::Scene& sc = scene_.scene;
    const int nLights = int(std::min<size_t>(sc.lights.size(), DiffuseFP::kMaxLights));
    if (shadowSize_ != s.shadowMapSize || lightSize_ != s.lightMapSize) {
        tex::TextureDesc d;
        d.format = tex::TexelFormat::Depth32F;
        d.width = d.height = s.shadowMapSize;
        for (int i = 0; i < 2; ++i) {
            shadowStatic_[i] = memory_.createRenderTarget(d);
            shadowMover_[i] = memory_.createRenderTarget(d);
        }
        tex::TextureDesc l;
        l.width = l.height = s.lightMapSize;
        lightStatic_ = memory_.createRenderTarget(l);
        lightMover_ = memory_.createRenderTarget(l);
        shadowSize_ = s.shadowMapSize;
        lightSize_ = s.lightMapSize;
        staticMap = moverMap = true;
        // Each light's projection: from the light towards the board's centre, wide enough
        // for every object's box.
        for (int i = 0; i < nLights; ++i) {
            const glm::vec3 lp = sc.lights[size_t(i)].position;
            glm::vec3 lo(1e30f), hi(-1e30f);
            for (const Batch& b : diffuse_) lo = glm::min(lo, b.lo), hi = glm::max(hi, b.hi);
            const glm::vec3 target = 0.5f * (lo + hi);
            const glm::vec3 axis = glm::normalize(target - lp);
            const glm::vec3 up = std::fabs(axis.y) > 0.9f ? glm::vec3(0, 0, -1) : glm::vec3(0, 1, 0);
            const glm::mat4 view = glm::lookAt(lp, target, up);
            float tanMax = 0.0f, near = 1e30f, far = 0.0f;
            auto take = [&](const Batch& b) {
                for (int k = 0; k < 8; ++k) {
                    const glm::vec3 p((k & 1) ? b.hi.x : b.lo.x, (k & 2) ? b.hi.y : b.lo.y, (k & 4) ? b.hi.z : b.lo.z);
                    const glm::vec3 e = glm::vec3(view * glm::vec4(p, 1.0f));
                    const float z = -e.z;
                    if (z <= 1e-4f) continue;
                    tanMax = std::max(tanMax, std::max(std::fabs(e.x), std::fabs(e.y)) / z);
                    near = std::min(near, z);
                    far = std::max(far, z);
                }
            };
            for (const Batch& b : diffuse_) take(b);
            for (const Glass& g : glass_) take(g.world);
            near = std::max(near * 0.9f, 1e-3f);
            far *= 1.1f;
            const float p = 1.0f / (tanMax * 1.02f);
            glm::mat4 proj(0.0f);
            proj[0][0] = p;
            proj[1][1] = p;
            proj[2][2] = far / (near - far);
            proj[2][3] = -1.0f;
            proj[3][2] = -(far * near) / (far - near);
            lightViewProj_[size_t(i)] = proj * view;
        }
    }
    // Shadow maps: the casters' depth from each light (glass casts opaque shadows, as the
    // ray-traced reference's shadow rays see it).
    auto shadow = [&](const std::shared_ptr<tex::Texture>& map, int light, bool statics, bool mover) {
        device_.setRenderTargets({}, DepthTarget{map});
        device_.clearDepth(1.0f);
        raster::ProgramState st;
        st.depthTest = st.depthWrite = 1;
        device_.setState(st);
        WorldVP vp;
        vp.viewProj = lightViewProj_[size_t(light)];
        for (size_t g = 0; g < glass_.size(); ++g) {
            const bool isMover = int(g) == moverGlass_;
            if (isMover ? !mover : !statics) continue;
            drawTriangles(device_, vp, DepthOnlyFP{}, std::span<const ImpostorVertex>(glass_[g].world.vertices),
                          std::span<const uint32_t>(glass_[g].world.indices));
        }
    };
    // The light map: the board's up-facing triangles drawn in its texture space, each texel
    // the 2×2 percentage-closer visibility of each light.
    auto resolve = [&](const std::shared_ptr<tex::Texture>& target, const std::shared_ptr<tex::Texture>* maps,
                       const raster::Rect* scissor = nullptr) {
        ColorTarget ct{target};
        device_.setRenderTargets({&ct, 1}, DepthTarget{});
        device_.clearColor(0, glm::vec4(1.0f));
        device_.setScissor(scissor);
        device_.setState(raster::ProgramState{});
        tex::SamplerState pcf = linearClamp(false);
        for (int i = 0; i < 2; ++i) device_.setTexture(i, maps[std::min(i, std::max(nLights - 1, 0))], pcf);
        LightMapFP fp;
        fp.lights = nLights;
        for (int i = 0; i < nLights; ++i) fp.lightViewProj[i] = lightViewProj_[size_t(i)];
        if (board_ < 0) return;
        {
            const Batch& b = diffuse_[size_t(board_)];
            std::vector<uint32_t> up;
            for (size_t t = 0; t + 2 < b.indices.size(); t += 3) {
                const glm::vec3 n = b.vertices[b.indices[t]].normal + b.vertices[b.indices[t + 1]].normal +
                                    b.vertices[b.indices[t + 2]].normal;
                if (n.y > 1.5f) up.insert(up.end(), {b.indices[t], b.indices[t + 1], b.indices[t + 2]});
            }
            if (!up.empty())
                drawTriangles(device_, TextureSpaceVP{}, fp, std::span<const ImpostorVertex>(b.vertices),
                          std::span<const uint32_t>(up));
        }
        device_.setScissor(nullptr);
    };
    if (nLights == 0) return;
    if (staticMap) {
        for (int i = 0; i < nLights; ++i) shadow(shadowStatic_[i], i, true, moverInStatic);
        resolve(lightStatic_, shadowStatic_);
    }
    if (moverMap) {
        for (int i = 0; i < nLights; ++i) shadow(shadowMover_[i], i, false, !moverInStatic);
        // §7: "Only the light map of the moving piece has to be updated" — and only where
        // its shadow falls: cleared to unshadowed, resolved inside the footprint of the
        // mover's box cast from each light onto the board (a scissor in texels).
        raster::Rect rect{0, 0, s.lightMapSize, s.lightMapSize};
        if (!moverInStatic && moverGlass_ >= 0 && boardSetup()) {
            const Batch& m = glass_[size_t(moverGlass_)].world;
            float u0 = 1e30f, v0 = 1e30f, u1 = -1e30f, v1 = -1e30f;
            auto take = [&](glm::vec3 p) {
                const float u = (p.x * grid_.uv[0] + p.z * grid_.uv[1]) + grid_.uv[2];
                const float v = (p.x * grid_.uv[3] + p.z * grid_.uv[4]) + grid_.uv[5];
                u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
            };
            for (int k = 0; k < 8; ++k) {
                const glm::vec3 c((k & 1) ? m.hi.x : m.lo.x, (k & 2) ? m.hi.y : m.lo.y, (k & 4) ? m.hi.z : m.lo.z);
                take(c);
                for (int i = 0; i < nLights; ++i) {
                    const glm::vec3 l = sc.lights[size_t(i)].position;
                    if (l.y <= c.y + 1e-4f) {  // a light below the top: the whole board
                        u0 = v0 = -1e30f, u1 = v1 = 1e30f;
                        continue;
                    }
                    take(l + (c - l) * ((l.y - grid_.boardY) / (l.y - c.y)));
                }
            }
            const float n = float(s.lightMapSize);
            const int x0 = std::clamp(int(std::floor(u0 * n)) - 2, 0, s.lightMapSize);
            const int x1 = std::clamp(int(std::ceil(u1 * n)) + 2, 0, s.lightMapSize);
            const int y0 = std::clamp(int(std::floor(v0 * n)) - 2, 0, s.lightMapSize);
            const int y1 = std::clamp(int(std::ceil(v1 * n)) + 2, 0, s.lightMapSize);
            rect = {x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0)};
        }
        resolve(lightMover_, shadowMover_, &rect);
    }
}

void ImpostorRenderer::drawSurroundings(const View& v, bool writeDistance, bool moverShadow) {
    const ray::Scene& sc = scene_.scene;
    raster::ProgramState st;
    st.cull = v.backFaces;
    st.depthTest = st.depthWrite = 1;
    device_.setState(st);
    WorldVP vp;
    vp.viewProj = v.viewProj;
    for (size_t i = 0; i < diffuse_.size(); ++i) {
        if (!visible(v, diffuse_[i])) continue;
        DiffuseFP fp;
        for (int k = 0; k < 3; ++k) {
            fp.eye[k] = v.eye[k];
            fp.albedo[k] = diffuseMaterials_[i].diffuse[k];
            fp.ambient[k] = sc.ambient[k];
        }
        fp.lights = int32_t(std::min<size_t>(sc.lights.size(), DiffuseFP::kMaxLights));
        for (int l = 0; l < fp.lights; ++l)
            for (int k = 0; k < 3; ++k) {
                fp.lightPos[l][k] = sc.lights[size_t(l)].position[k];
                fp.lightIntensity[l][k] = sc.lights[size_t(l)].intensity[k];
            }
        fp.writeDistance = writeDistance ? 1 : 0;
        fp.lightMapped = lightStatic_ && int(i) == board_ ? 1 : 0;  // the board's top face
        device_.setTexture(kUnitAlbedo, diffuseTextures_[i],
                           diffuseTextures_[i] == white_ ? pointClamp() : linearClamp(true));
        device_.setTexture(kUnitLightMap, lightStatic_ ? lightStatic_ : white_, linearClamp(false));
        device_.setTexture(kUnitLightMapMover, moverShadow && lightMover_ ? lightMover_ : white_, linearClamp(false));
        if (fp.lightMapped && drawCausticBoard(vp, fp, i, moverShadow)) continue;
        drawTriangles(device_, vp, fp, std::span<const ImpostorVertex>(diffuse_[i].vertices),
                      std::span<const uint32_t>(diffuse_[i].indices));
    }
    // The sky behind: the depth test (no write) leaves it the pixels nothing covers.
    raster::ProgramState sky;
    sky.depthTest = 1;
    device_.setState(sky);
    SkyFP fp = v.sky;
    fp.writeDistance = writeDistance ? 1 : 0;
    device_.setTexture(0, world_, linearClamp(false));
    drawTriangles(device_, ScreenVP{}, fp, std::span<const ImpostorVertex>(kCoverBehind, 3));
}

void ImpostorRenderer::drawGlass(const View& v, const ImpostorSettings& s, int i, const std::shared_ptr<tex::Texture>& env,
                                 bool searchMover, bool diagnostics, bool writeDistance) {
    const Glass& g = glass_[size_t(i)];
    raster::ProgramState st;
    st.cull = v.backFaces;
    st.depthTest = st.depthWrite = 1;
    device_.setState(st);
    WorldVP vp;
    vp.viewProj = v.viewProj;
    GlassConstants k;
    for (int c = 0; c < 3; ++c) k.eye[c] = v.eye[c];
    k.iterations = s.iterations;
    k.writeDistance = writeDistance ? 1 : 0;
    k.self = frames_[size_t(i)];
    const tex::SamplerState point = pointClamp();
    device_.setTexture(kUnitEnv, env, point);
    device_.setTexture(kUnitRefractor, refractors_[size_t(g.refractor)].cube, point);
    const auto verts = std::span<const ImpostorVertex>(g.world.vertices);
    const auto idx = std::span<const uint32_t>(g.world.indices);
    if (searchMover) {
        k.mover = frames_[size_t(moverGlass_)];
        device_.setTexture(kUnitMoverEnv, moverImpostor_, point);
        device_.setTexture(kUnitMoverRefractor, refractors_[size_t(glass_[size_t(moverGlass_)].refractor)].cube, point);
    }
    lastConstants_ = k;
    if (s.exit == Exit::HeightMap && !k.self.mirror) {
        // §6: the exit through the object's refractor height map.
        const Refractor& r = refractors_[size_t(g.refractor)];
        device_.setTexture(kUnitHeight, r.height, point);
        const Refractor* rm = searchMover ? &refractors_[size_t(glass_[size_t(moverGlass_)].refractor)] : nullptr;
        if (rm) device_.setTexture(kUnitMoverHeight, rm->height, point);
        auto drawH = [&](auto fp) {
            fp.h.k = k;
            fp.h.self = r.heightFrame;
            if (rm) fp.h.mover = rm->heightFrame;
            drawHeightGlass(device_, vp, fp, verts, idx);
        };
        if (searchMover) {
            if (diagnostics) drawH(GlassHeightFP<true, true>{});
            else drawH(GlassHeightFP<true, false>{});
        } else {
            if (diagnostics) drawH(GlassHeightFP<false, true>{});
            else drawH(GlassHeightFP<false, false>{});
        }
        return;
    }
    auto draw = [&](auto fp) {
        fp.k = k;
        drawTriangles(device_, vp, fp, verts, idx);
    };
    if (searchMover) {
        if (diagnostics) draw(GlassFP<true, true>{});
        else draw(GlassFP<true, false>{});
    } else {
        if (diagnostics) draw(GlassFP<false, true>{});
        else draw(GlassFP<false, false>{});
    }
}

void ImpostorRenderer::renderImpostor(const ImpostorSettings& s, int i, const std::shared_ptr<tex::Texture>& target,
                                      bool withMover, bool moverShadow) {
    const glm::vec3 c(frames_[size_t(i)].centre[0], frames_[size_t(i)].centre[1], frames_[size_t(i)].centre[2]);
    for (int f = 0; f < 6; ++f) {
        const View v = faceView(f, c, s.envSize);
        ColorTarget ct{target, 0, f};
        device_.setRenderTargets({&ct, 1}, DepthTarget{cubeDepth_});
        device_.clearColor(0, glm::vec4(0.0f, 0.0f, 0.0f, kSkyDistance));
        device_.clearDepth(1.0f);
        // A face's draws as one batch (one fork and join); the impostors they read are
        // other pieces' (a piece is never drawn into its own), finished before it.
        raster::ProgramBatch batch(device_);
        drawSurroundings(v, true, moverShadow);
        for (size_t j = 0; j < glass_.size(); ++j) {
            if (int(j) == i) continue;  // a piece is never drawn into its own impostor
            if (int(j) == moverGlass_ && !withMover) continue;
            if (!visible(v, glass_[j].world)) continue;
            // Every object through its own impostor as it stands (the mover's map sees the
            // static objects through their static ones).
            drawGlass(v, s, int(j), impostors_[j], false, false, true);
        }
        batch.end();
    }
}

void ImpostorRenderer::buildImpostors(const ImpostorSettings& s, Content content, ImpostorFrame& f) {
    const bool withMover = content == Content::Full;
    // Pass 0: board and sky into every impostor; then DEPTH passes of the surrounding
    // objects, each through the impostors as they stand (in place, scene order).
    for (size_t i = 0; i < glass_.size(); ++i) {
        if (!withMover && int(i) == moverGlass_) continue;
        const glm::vec3 c(frames_[i].centre[0], frames_[i].centre[1], frames_[i].centre[2]);
        for (int face = 0; face < 6; ++face) {
            const View v = faceView(face, c, s.envSize);
            ColorTarget ct{impostors_[i], 0, face};
            device_.setRenderTargets({&ct, 1}, DepthTarget{cubeDepth_});
            device_.clearColor(0, glm::vec4(0.0f, 0.0f, 0.0f, kSkyDistance));
            device_.clearDepth(1.0f);
            raster::ProgramBatch batch(device_);
            drawSurroundings(v, true, withMover);
            batch.end();
        }
        f.impostorTexels += 6 * int64_t(s.envSize) * s.envSize;
    }
    for (int it = 0; it < s.depth; ++it)
        for (size_t i = 0; i < glass_.size(); ++i) {
            if (!withMover && int(i) == moverGlass_) continue;
            renderImpostor(s, int(i), impostors_[i], withMover, /*moverShadow=*/withMover);
            f.impostorTexels += 6 * int64_t(s.envSize) * s.envSize;
        }
    for (size_t i = 0; i < glass_.size(); ++i)
        if (withMover || int(i) != moverGlass_) ++f.impostorsRebuilt;
}

void ImpostorRenderer::buildMoverImpostor(const ImpostorSettings& s, ImpostorFrame& f) {
    // §5.2: the mover's impostor holds everything: the board (with both light maps), the
    // sky and the static objects through their static impostors, which already carry
    // DEPTH bounces — one pass.
    renderImpostor(s, moverGlass_, moverImpostor_, false, /*moverShadow=*/true);
    f.impostorTexels += 6 * int64_t(s.envSize) * s.envSize;
    ++f.impostorsRebuilt;
}

void ImpostorRenderer::ensureStatic(const ImpostorSettings& s) {
    const int64_t need = int64_t(glass_.size() + 1) * 6 * int64_t(s.envSize) * s.envSize * 8;
    if (s.mode != Mode::RefractorMapsOnly && uint64_t(need) > g80().textureMemoryBytes)
        throw Error("impostors: " + std::to_string(glass_.size() + 1) + " environment impostors of 6 × " +
                    std::to_string(s.envSize) + "² RGBA16F texels need " + std::to_string(need >> 20) +
                    " MiB, more than geforce8800's " + std::to_string(g80().textureMemoryBytes >> 20) +
                    " MiB of texture memory");
    if (envSize_ != s.envSize && s.mode != Mode::RefractorMapsOnly) {
        impostors_.clear();
        moverImpostor_.reset();
        cubeDepth_.reset();
        for (size_t i = 0; i < glass_.size(); ++i) impostors_.push_back(cubeTarget(s.envSize));
        moverImpostor_ = cubeTarget(s.envSize);
        tex::TextureDesc dd;
        dd.format = tex::TexelFormat::Depth24;
        dd.width = dd.height = s.envSize;
        cubeDepth_ = memory_.createRenderTarget(dd);
        envSize_ = s.envSize;
        content_ = Content::None;
    }
    if (s.width != frameW_ || s.height != frameH_ || (s.diagnostics && !diag_[0])) {
        tex::TextureDesc d;
        d.width = s.width;
        d.height = s.height;
        frame_ = memory_.createRenderTarget(d);
        if (s.diagnostics) {
            d.format = tex::TexelFormat::RGBA32F;
            for (auto& t : diag_) t = memory_.createRenderTarget(d);
        } else {
            for (auto& t : diag_) t.reset();
        }
        d.format = tex::TexelFormat::Depth24;
        frameDepth_ = memory_.createRenderTarget(d);
        frameW_ = s.width;
        frameH_ = s.height;
    }
}

ImpostorFrame ImpostorRenderer::render(const ray::Camera& camera, const ImpostorSettings& s) {
    validate(s);
    ImpostorFrame frame;
    const auto tFrame = Clock::now();
    auto pass = [&](const std::string& name, auto&& body) {
        device_.beginFrame();
        const auto t0 = Clock::now();
        body();
        frame.passes.push_back({name, std::chrono::duration<double, std::milli>(Clock::now() - t0).count(),
                                device_.counters()});
    };
    ensureStatic(s);
    const bool hasMover = moverGlass_ >= 0;
    const float u = s.moverU;
    const bool moved = u != moverU_;
    placeMover(u);
    for (size_t i = 0; i < glass_.size(); ++i) frames_[i] = frameOf(glass_[i], s);
    if (refractors_.empty() || refractors_[0].size != s.refractorSize)
        pass("refractor distance maps", [&] { buildRefractors(s.refractorSize); });
    if (s.exit == Exit::HeightMap && s.mode != Mode::RefractorMapsOnly &&
        (refractors_[0].heightSize != s.heightMapSize || refractors_[0].heightFrame.steps != s.heightSteps))
        pass("refractor height maps", [&] { buildHeightMaps(s.heightMapSize, s.heightSteps); });

    // ---- the maps this mode needs this frame --------------------------------------------------
    const std::string key = std::to_string(s.envSize) + "/" + std::to_string(s.depth) + "/" +
                            std::to_string(s.iterations) + "/" + std::to_string(s.epsilon) + "/" +
                            std::to_string(s.refractorSize) + "/" + std::to_string(s.lightMapSize) + "/" +
                            std::to_string(s.shadowMapSize) + "/" + exitName(s.exit) + "/" +
                            std::to_string(s.heightMapSize) + "/" + std::to_string(s.heightSteps) +
                            (s.caustics ? "/caustics/" + std::to_string(s.photonMapSize) + "/" +
                                              std::to_string(s.causticSigma)
                                        : std::string());
    const bool separated = s.mode == Mode::Separated && hasMover;
    const Content want = separated ? Content::StaticOnly : Content::Full;
    const std::string lightKey = key + (separated ? "/sep" : "/full");
    const auto tMaps = Clock::now();
    if (lightKey != lightKey_ || (moved && !separated) || lightSize_ != s.lightMapSize) {
        pass("light maps: all pieces", [&] { buildLightMaps(s, true, true, !separated); });
        lightKey_ = lightKey;
    } else if (separated && moved) {
        pass("light map: the mover", [&] { buildLightMaps(s, false, true, false); });
    }
    // §7: caustics go into light maps of their own, built when the shadows' are (the static
    // pieces' once, the mover's per frame).
    causticsOn_ = s.caustics;
    if (s.caustics) {
        if (lightKey != causticKey_ || (moved && !separated)) {
            pass("caustics: all pieces", [&] { buildCaustics(s, true, true, !separated); });
            causticKey_ = lightKey;
        } else if (separated && moved) {
            pass("caustics: the mover", [&] { buildCaustics(s, false, true, false); });
        }
    }
    if (s.mode != Mode::RefractorMapsOnly) {
        const bool rebuild = content_ != want || impostorKey_ != key || s.mode == Mode::Classical ||
                             (s.mode == Mode::Static && moved);
        if (rebuild) {
            pass(want == Content::Full ? "impostors: every object, DEPTH " + std::to_string(s.depth)
                                       : "impostors: static objects, DEPTH " + std::to_string(s.depth),
                 [&] { buildImpostors(s, want, frame); });
            content_ = want;
            impostorKey_ = key;
        }
        if (separated) pass("impostor: the mover", [&] { buildMoverImpostor(s, frame); });
    }
    frame.mapsMs = std::chrono::duration<double, std::milli>(Clock::now() - tMaps).count();

    if (s.mode == Mode::RefractorMapsOnly) buildGridTexture();

    // ---- the frame ---------------------------------------------------------------------------
    const View v = cameraView(camera, s.width, s.height);
    frameDiagnostics_ = s.diagnostics;
    pass("frame: board and sky", [&] {
        std::vector<ColorTarget> cts{{frame_}};
        if (s.diagnostics)
            for (auto& t : diag_) cts.push_back({t});
        device_.setRenderTargets(cts, DepthTarget{frameDepth_});
        for (int t = 0; t < int(cts.size()); ++t) device_.clearColor(t, glm::vec4(0.0f, 0.0f, 0.0f, t == 0 ? 1.0f : 0.0f));
        device_.clearDepth(1.0f);
        raster::ProgramBatch batch(device_);
        drawSurroundings(v, false, true);
        batch.end();
    });
    pass(std::string("frame: glass (") + modeName(s.mode) + ")", [&] {
        // Nearest first, so the early depth test skips what later objects would overwrite.
        std::vector<int> order(glass_.size());
        std::iota(order.begin(), order.end(), 0);
        std::vector<float> dist(glass_.size());
        for (size_t i = 0; i < glass_.size(); ++i)
            dist[i] = glm::length(0.5f * (glass_[i].world.lo + glass_[i].world.hi) - camera.eye);
        std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return dist[size_t(a)] < dist[size_t(b)]; });
        lastGlassOrder_.clear();
        lastViewProj_ = v.viewProj;
        raster::ProgramBatch batch(device_);  // every piece's glass, one fork and join
        for (int i : order) {
            if (!visible(v, glass_[size_t(i)].world)) continue;
            lastGlassOrder_.push_back(i);
            const bool isMover = i == moverGlass_;
            if (s.mode == Mode::RefractorMapsOnly) {
                drawGrid(v, s, i);
                continue;
            }
            drawGlass(v, s, i, separated && isMover ? moverImpostor_ : impostors_[size_t(i)], separated && !isMover,
                      s.diagnostics, false);
        }
        batch.end();
        frame.glassFragments = int64_t(device_.counters().fragmentInvocations);
        frame.fetchesPerGlassFragment = device_.counters().meanFetchesPerFragment();
    });
    frame.totalMs = std::chrono::duration<double, std::milli>(Clock::now() - tFrame).count();
    return frame;
}

bool ImpostorRenderer::boardSetup() {
    // The board: the diffuse object with the largest footprint; its top face's uv as an
    // affine function of (x, z) (the light maps' and mode A's texture space).
    if (board_ >= 0) return true;
    if (boardMissing_) return false;
    {
        float best = 0.0f;
        for (size_t i = 0; i < diffuse_.size(); ++i) {
            const Batch& b = diffuse_[i];
            const float area = (b.hi.x - b.lo.x) * (b.hi.z - b.lo.z);
            if (area > best) best = area, board_ = int(i);
        }
        if (board_ < 0) {
            boardMissing_ = true;
            return false;
        }
        // The top face's uv as an affine function of (x, z), from one of its triangles.
        const Batch& b = diffuse_[size_t(board_)];
        for (size_t t = 0; t + 2 < b.indices.size(); t += 3) {
            const ImpostorVertex& a = b.vertices[b.indices[t]];
            const ImpostorVertex& c1 = b.vertices[b.indices[t + 1]];
            const ImpostorVertex& c2 = b.vertices[b.indices[t + 2]];
            if (a.normal.y < 0.5f || std::fabs(a.position.y - b.hi.y) > 1e-4f) continue;
            const glm::vec2 e1(c1.position.x - a.position.x, c1.position.z - a.position.z);
            const glm::vec2 e2(c2.position.x - a.position.x, c2.position.z - a.position.z);
            const float det = e1.x * e2.y - e1.y * e2.x;
            if (std::fabs(det) < 1e-8f) continue;
            for (int k = 0; k < 2; ++k) {
                const float d1 = c1.uv[k] - a.uv[k], d2 = c2.uv[k] - a.uv[k];
                const float gx = (d1 * e2.y - d2 * e1.y) / det, gz = (e1.x * d2 - e2.x * d1) / det;
                grid_.uv[3 * k] = gx;
                grid_.uv[3 * k + 1] = gz;
                grid_.uv[3 * k + 2] = a.uv[k] - gx * a.position.x - gz * a.position.z;
            }
            break;
        }
        grid_.boardLo[0] = b.lo.x, grid_.boardLo[1] = b.lo.z;
        grid_.boardHi[0] = b.hi.x, grid_.boardHi[1] = b.hi.z;
        grid_.boardY = b.hi.y;
        grid_.cell = (b.hi.x - b.lo.x) / float(kGridSize);
        for (int k = 0; k < 3; ++k) grid_.boardAlbedo[k] = diffuseMaterials_[size_t(board_)].diffuse[k];
    }
    return true;
}

void ImpostorRenderer::buildGridTexture() {
    // 002 §4.2: "a uniform grid aligned on the squares of the chessboard", at most one
    // object a square.
    if (!boardSetup()) throw Error("impostors: mode A needs a board (a diffuse object under the glass objects)");
    if (!gridCells_) {
        tex::TextureDesc d;
        d.format = tex::TexelFormat::R32F;
        d.width = d.height = kGridSize;
        gridCells_ = memory_.create(d);
    }
    if (glass_.size() > size_t(kGridObjects) || refractors_.size() > size_t(kGridMaps))
        throw Error("impostors: mode A holds at most " + std::to_string(kGridObjects) + " objects and " +
                    std::to_string(kGridMaps) + " refractor maps in a program's constants and units (this scene has " +
                    std::to_string(glass_.size()) + " and " + std::to_string(refractors_.size()) + ")");
    std::vector<float> cells(size_t(kGridSize) * kGridSize, -1.0f);
    grid_.maxHeight = grid_.boardY;
    for (size_t i = 0; i < glass_.size(); ++i) {
        const glm::vec3 c = 0.5f * (glass_[i].world.lo + glass_[i].world.hi);
        grid_.maxHeight = std::max(grid_.maxHeight, glass_[i].world.hi.y);
        const int cx = int(std::floor((c.x - grid_.boardLo[0]) / grid_.cell));
        const int cz = int(std::floor((c.z - grid_.boardLo[1]) / grid_.cell));
        if (cx < 0 || cz < 0 || cx >= kGridSize || cz >= kGridSize) continue;  // off the board: not in the grid
        float& cell = cells[size_t(cz) * kGridSize + size_t(cx)];
        if (cell < 0.0f) cell = float(i);  // "only one piece in one square": the first keeps it
    }
    memory_.upload(*gridCells_, 0, 0,
                   std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(cells.data()), cells.size() * sizeof(float)));
}

void ImpostorRenderer::drawGrid(const View& v, const ImpostorSettings& s, int i) {
    const ray::Scene& sc = scene_.scene;
    GridFP fp;
    fp.g = grid_;
    GridConstants& g = fp.g;
    for (int k = 0; k < 3; ++k) {
        g.eye[k] = v.eye[k];
        g.ambient[k] = sc.ambient[k];
    }
    g.iterations = s.iterations;
    g.self = i;
    g.objects = int32_t(glass_.size());
    for (size_t k = 0; k < glass_.size(); ++k) {
        g.frame[k] = frames_[k];
        g.map[k] = glass_[k].refractor;
    }
    g.lights = int32_t(std::min<size_t>(sc.lights.size(), 2));
    for (int l = 0; l < g.lights; ++l)
        for (int k = 0; k < 3; ++k) {
            g.lightPos[l][k] = sc.lights[size_t(l)].position[k];
            g.lightIntensity[l][k] = sc.lights[size_t(l)].intensity[k];
        }
    const tex::SamplerState point = pointClamp();
    for (int m = 0; m < kGridMaps; ++m)
        device_.setTexture(m, refractors_[size_t(std::min<int>(m, int(refractors_.size()) - 1))].cube, point);
    device_.setTexture(kGridUnitAlbedo, diffuseTextures_[size_t(board_)], linearClamp(false));
    device_.setTexture(kGridUnitLight, lightStatic_ ? lightStatic_ : white_, linearClamp(false));
    device_.setTexture(kGridUnitLightMover, lightMover_ ? lightMover_ : white_, linearClamp(false));
    device_.setTexture(kGridUnitSky, world_, linearClamp(false));
    device_.setTexture(kGridUnitCells, gridCells_, point);
    raster::ProgramState st;
    st.cull = v.backFaces;
    st.depthTest = st.depthWrite = 1;
    device_.setState(st);
    WorldVP vp;
    vp.viewProj = v.viewProj;
    drawTriangles(device_, vp, fp, std::span<const ImpostorVertex>(glass_[size_t(i)].world.vertices),
                  std::span<const uint32_t>(glass_[size_t(i)].world.indices));
}

ray::Image ImpostorRenderer::frame() const {
    ray::Image img(frameW_, frameH_, 3);
    const Rgba8* p = const_cast<tex::Texture&>(*frame_).renderData8(0, 0);
    for (int y = 0; y < frameH_; ++y)
        for (int x = 0; x < frameW_; ++x) {
            const Rgba8 c = p[size_t(y) * size_t(frameW_) + size_t(x)];
            img.setRgb(x, y, glm::vec3(c.r, c.g, c.b) / 255.0f);
        }
    return img;
}

ImpostorRenderer::Diagnostics ImpostorRenderer::readDiagnostics() const {
    if (!frameDiagnostics_ || !diag_[0]) throw Error("impostors: the last frame was rendered without diagnostics");
    Diagnostics d;
    const int w = frameW_, h = frameH_;
    d.searches = ray::Image(w, h, 1);
    d.flags = ray::Image(w, h, 1);
    d.reflDir = ray::Image(w, h, 3);
    d.reflD = ray::Image(w, h, 1);
    d.exitOrigin = ray::Image(w, h, 3);
    d.exitD = ray::Image(w, h, 1);
    d.exitDir = ray::Image(w, h, 3);
    const glm::vec4* t1 = const_cast<tex::Texture&>(*diag_[0]).renderDataF(0, 0);
    const glm::vec4* t2 = const_cast<tex::Texture&>(*diag_[1]).renderDataF(0, 0);
    const glm::vec4* t3 = const_cast<tex::Texture&>(*diag_[2]).renderDataF(0, 0);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t i = size_t(y) * size_t(w) + size_t(x);
            const float code = t3[i].w;
            const float flags = std::floor(code / 64.0f);
            d.flags.at(x, y, 0) = flags;
            d.searches.at(x, y, 0) = code - 64.0f * flags;
            d.reflDir.setRgb(x, y, glm::vec3(t1[i]));
            d.reflD.at(x, y, 0) = t1[i].w;
            d.exitOrigin.setRgb(x, y, glm::vec3(t2[i]));
            d.exitD.at(x, y, 0) = t2[i].w;
            d.exitDir.setRgb(x, y, glm::vec3(t3[i]));
        }
    return d;
}

namespace {

// A cube map's six faces as a horizontal cross:     [+Y]
//                                              [−X][+Z][+X][−Z]
//                                                   [−Y]
// (the faces as seen from inside, looking along −z at +Z; ARB_texture_cube_map's (s, t)).
template <class Texel>
ray::Image cross(int n, Texel&& texel) {
    ray::Image img(4 * n, 3 * n, 3, 1.0f);
    const int at[6][2] = {{2, 1}, {0, 1}, {1, 0}, {1, 2}, {1, 1}, {3, 1}};  // +X −X +Y −Y +Z −Z
    // Face placement for a viewer inside looking at +Z ... the standard OpenGL cross uses
    // +Z in the middle with +X on its right when the faces are shown as the map stores them.
    const int cols[6] = {2, 0, 1, 1, 1, 3};
    const int rows[6] = {1, 1, 0, 2, 1, 1};
    (void)at;
    for (int f = 0; f < 6; ++f)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x) img.setRgb(cols[f] * n + x, rows[f] * n + y, texel(f, x, y));
    return img;
}

}  // namespace

ray::Image ImpostorRenderer::impostorImage(int i, bool distance, float maxDistance) const {
    const auto& t = i == moverGlass_ && content_ == Content::StaticOnly ? moverImpostor_ : impostors_.at(size_t(i));
    const int n = envSize_;
    return cross(n, [&](int f, int x, int y) {
        const glm::vec4 v = const_cast<tex::Texture&>(*t).renderDataF(0, f)[size_t(y) * size_t(n) + size_t(x)];
        if (distance) return glm::vec3(std::min(1.0f, v.w / maxDistance));
        return glm::vec3(v);
    });
}

ray::Image ImpostorRenderer::refractorImage(int m) const {
    const Refractor& r = refractors_.at(size_t(m));
    return cross(r.size, [&](int f, int x, int y) {
        const glm::vec4 v = const_cast<tex::Texture&>(*r.cube).renderDataF(0, f)[size_t(y) * size_t(r.size) + size_t(x)];
        return v.w > 0.0f ? 0.5f + 0.5f * glm::vec3(v) : glm::vec3(0.0f);
    });
}

ray::Image ImpostorRenderer::heightMapImage(int m) const {
    const Refractor& r = refractors_.at(size_t(m));
    if (!r.height) throw Error("impostors: no refractor height map built yet (render a frame with the height-map exit)");
    const int n = r.heightSize;
    ray::Image img(2 * n, n, 3);
    const glm::vec4* t = r.height->dataF(0, 0);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const glm::vec4 v = t[size_t(y) * size_t(n) + size_t(x)];
            const bool empty = !(v.w > 0.0f);
            img.setRgb(x, y, empty ? glm::vec3(0.0f) : 0.5f + 0.5f * glm::vec3(v));
            img.setRgb(n + x, y, glm::vec3(empty ? 0.0f : v.w / r.heightFrame.hMax));
        }
    return img;
}

ray::Image ImpostorRenderer::lightMapImage() const {
    ray::Image img(lightSize_, lightSize_, 3);
    const Rgba8* a = const_cast<tex::Texture&>(*lightStatic_).renderData8(0, 0);
    const Rgba8* b = const_cast<tex::Texture&>(*lightMover_).renderData8(0, 0);
    for (int y = 0; y < lightSize_; ++y)
        for (int x = 0; x < lightSize_; ++x) {
            const size_t i = size_t(y) * size_t(lightSize_) + size_t(x);
            img.setRgb(x, y, glm::vec3(float(a[i].r) * float(b[i].r), float(a[i].g) * float(b[i].g), 0.0f) / 65025.0f);
        }
    return img;
}

const tex::Texture& ImpostorRenderer::impostorTexture(int i) const {
    if (i == moverGlass_ && content_ == Content::StaticOnly) return *moverImpostor_;
    return *impostors_.at(size_t(i));
}

uint64_t ImpostorRenderer::textureBytes() const { return memory_.residentBytes(); }

}  // namespace rg::impostors
