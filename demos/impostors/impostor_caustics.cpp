// 002 §7's caustics: the splats' vertex order, and the draws of the photon-map, splat and
// caustic-board programs (their kernels instantiated here, apart from the glass programs'
// impostor_programs.cpp).
#include "impostor_caustics.h"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "impostor_renderer.h"
#include "rasterizer/program_registry.h"

namespace rg::impostors {

std::vector<SplatVertex> splatVertices(int n) {
    // Two triangles per photon, corners (−1, −1) (1, −1) (−1, 1) and (1, −1) (1, 1) (−1, 1):
    // both clockwise in window space, as the device draws any winding with culling off.
    static constexpr float kCorners[6][2] = {{-1, -1}, {1, -1}, {-1, 1}, {1, -1}, {1, 1}, {-1, 1}};
    std::vector<SplatVertex> v;
    v.reserve(size_t(n) * size_t(n) * 6);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            for (const auto& c : kCorners) v.push_back({{x, y}, {c[0], c[1]}});
    return v;
}

void drawPhotons(raster::ProgrammableDevice& device, const WorldVP& vp, const PhotonFP& fp,
                 std::span<const ImpostorVertex> vertices, std::span<const uint32_t> indices) {
    device.draw(vp, fp, raster::ProgramPrimitive::TriangleList, vertices, indices);
}

void drawSplats(raster::ProgrammableDevice& device, const SplatVP& vp, const SplatFP& fp,
                std::span<const SplatVertex> vertices) {
    device.draw(vp, fp, raster::ProgramPrimitive::TriangleList, vertices);
}

void drawCausticBoard(raster::ProgrammableDevice& device, const WorldVP& vp, const CausticDiffuseFP& fp,
                      std::span<const ImpostorVertex> vertices, std::span<const uint32_t> indices) {
    device.draw(vp, fp, raster::ProgramPrimitive::TriangleList, vertices, indices);
}

void registerCausticPrograms() {
    using raster::registerProgram;
    registerProgram<WorldVP, PhotonFP, ImpostorVertex>("impostors/caustics/photon_map");
    registerProgram<SplatVP, SplatFP, SplatVertex>("impostors/caustics/splat");
    registerProgram<WorldVP, CausticDiffuseFP, ImpostorVertex>("impostors/caustics/board");
}

// ---- the renderer's caustics pass (002 §7) ---------------------------------------------------

namespace {
tex::SamplerState pointClampSampler() {
    tex::SamplerState s;
    s.magFilter = s.minFilter = tex::FilterMode::Nearest;
    s.address.fill(tex::AddressMode::ClampToEdge);
    return s;
}
tex::SamplerState linearClampSampler() {
    tex::SamplerState s;
    s.address.fill(tex::AddressMode::ClampToEdge);
    return s;
}
}  // namespace

struct ImpostorRenderer::Caustics {
    int photonSize = 0, lightSize = 0;
    std::shared_ptr<tex::Texture> hit, power, depth;  // the photon map (one piece, one light at a time)
    std::shared_ptr<tex::Texture> statics, mover;     // the caustic light maps (RGBA32F)
    std::shared_ptr<tex::Texture> black;              // 1×1 zero: the mover's map where it does not apply
    std::vector<SplatVertex> splats;
};

const tex::Texture* ImpostorRenderer::causticTexture(bool mover) const {
    if (!caustics_) return nullptr;
    return (mover ? caustics_->mover : caustics_->statics).get();
}
const tex::Texture* ImpostorRenderer::photonHitTexture() const { return caustics_ ? caustics_->hit.get() : nullptr; }
const tex::Texture* ImpostorRenderer::photonPowerTexture() const {
    return caustics_ ? caustics_->power.get() : nullptr;
}

ray::Image ImpostorRenderer::causticImage() const {
    const int n = caustics_ ? caustics_->lightSize : 1;
    ray::Image img(n, n, 3);
    if (!caustics_ || !caustics_->statics) return img;
    const glm::vec4* a = caustics_->statics->dataF(0, 0);
    const glm::vec4* b = caustics_->mover->dataF(0, 0);
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const size_t i = size_t(y) * size_t(n) + size_t(x);
            img.setRgb(x, y, glm::vec3(a[i]) + glm::vec3(b[i]));
        }
    return img;
}

bool ImpostorRenderer::drawCausticBoard(const WorldVP& vp, const DiffuseFP& fp, size_t diffuse, bool moverShadow) {
    if (!causticsOn_ || !caustics_ || !caustics_->statics) return false;
    const tex::SamplerState linear = linearClampSampler();
    device_.setTexture(kUnitCausticStatic, caustics_->statics, linear);
    device_.setTexture(kUnitCausticMover, moverShadow ? caustics_->mover : caustics_->black, linear);
    CausticDiffuseFP c;
    c.base = fp;
    impostors::drawCausticBoard(device_, vp, c, std::span<const ImpostorVertex>(diffuse_[diffuse].vertices),
                                std::span<const uint32_t>(diffuse_[diffuse].indices));
    return true;
}

void ImpostorRenderer::buildCaustics(const ImpostorSettings& s, bool staticMap, bool moverMap, bool moverInStatic) {
    registerCausticPrograms();
    if (!caustics_) caustics_ = std::make_shared<Caustics>();
    Caustics& c = *caustics_;
    const int n = s.photonMapSize, size = s.lightMapSize;
    if (c.photonSize != n) {
        tex::TextureDesc d;
        d.format = tex::TexelFormat::RGBA32F;
        d.width = d.height = n;
        c.hit = memory_.createRenderTarget(d);
        c.power = memory_.createRenderTarget(d);
        d.format = tex::TexelFormat::Depth32F;
        c.depth = memory_.createRenderTarget(d);
        c.splats = splatVertices(n);
        c.photonSize = n;
    }
    if (c.lightSize != size) {
        tex::TextureDesc d;
        d.format = tex::TexelFormat::RGBA32F;
        d.width = d.height = size;
        c.statics = memory_.createRenderTarget(d);
        c.mover = memory_.createRenderTarget(d);
        d.width = d.height = 1;
        if (!c.black) c.black = memory_.createRenderTarget(d);
        c.lightSize = size;
        staticMap = moverMap = true;
    }
    const ray::Scene& sc = scene_.scene;
    const int nLights = int(std::min<size_t>(sc.lights.size(), DiffuseFP::kMaxLights));
    const bool board = boardSetup();

    PhotonBoard pb;
    pb.boardY = grid_.boardY;
    for (int k = 0; k < 6; ++k) pb.uv[k] = grid_.uv[k];
    for (int k = 0; k < 2; ++k) pb.lo[k] = grid_.boardLo[k], pb.hi[k] = grid_.boardHi[k];
    // A light-map texel's world area: the board's uv is affine in (x, z) with Jacobian
    // determinant det, so one texel (1/size)² of uv covers (1/size)²/|det|.
    const double det = double(grid_.uv[0]) * double(grid_.uv[4]) - double(grid_.uv[1]) * double(grid_.uv[3]);
    const double texelWorld = 1.0 / (double(size) * double(size) * std::fabs(det));
    // The splat kernel: σ in light-map texels, radius R = 3σ, normalised over the disc of
    // radius R so that a splat's texels sum (times their area) to the photon's power.
    const double sigma = double(s.causticSigma), radius = double(kSplatRadiusSigmas) * sigma;
    const double kept = 1.0 - std::exp(-radius * radius / (2.0 * sigma * sigma));
    SplatVP splatVp;
    splatVp.size = float(size);
    splatVp.radius = float(radius);
    splatVp.norm = float(1.0 / (2.0 * std::numbers::pi * sigma * sigma * kept * texelWorld));
    SplatFP splatFp;
    splatFp.inv2Sigma2 = float(1.0 / (2.0 * sigma * sigma));
    splatFp.radius2 = float(radius * radius);

    // One piece under one light: its photon map, then its splats added into `target`.
    auto piece = [&](size_t g, int light, const std::shared_ptr<tex::Texture>& target) {
        const Glass& gl = glass_[g];
        const ObjectFrame& f = frames_[g];
        const glm::vec3 L = sc.lights[size_t(light)].position;
        const glm::vec3 lo = gl.world.lo, hi = gl.world.hi, centre = 0.5f * (lo + hi);
        if (glm::all(glm::greaterThanEqual(L, lo)) && glm::all(glm::lessThanEqual(L, hi))) return;  // light inside
        // The photon camera: at the light, aimed at the box's centre, its square frustum
        // fitted to the box's corners.
        const glm::vec3 axis = glm::normalize(centre - L);
        const glm::vec3 up = std::fabs(axis.y) > 0.9f ? glm::vec3(0, 0, -1) : glm::vec3(0, 1, 0);
        const glm::mat4 view = glm::lookAt(L, centre, up);
        float tanMax = 0.0f, near = 1e30f, far = 0.0f;
        for (int k = 0; k < 8; ++k) {
            const glm::vec3 p((k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z);
            const glm::vec3 e = glm::vec3(view * glm::vec4(p, 1.0f));
            const float z = std::max(-e.z, 1e-4f);
            tanMax = std::max(tanMax, std::max(std::fabs(e.x), std::fabs(e.y)) / z);
            near = std::min(near, z);
            far = std::max(far, z);
        }
        near = std::max(near * 0.9f, 1e-3f);
        far *= 1.1f;
        tanMax *= 1.02f;
        glm::mat4 proj(0.0f);
        proj[0][0] = proj[1][1] = 1.0f / tanMax;
        proj[2][2] = far / (near - far);
        proj[2][3] = -1.0f;
        proj[3][2] = -(far * near) / (far - near);

        // Pass 1: the photon map.
        {
            raster::ColorTarget cts[2] = {{c.hit}, {c.power}};
            device_.setRenderTargets(cts, raster::DepthTarget{c.depth});
            device_.clearColor(0, glm::vec4(0.0f));
            device_.clearColor(1, glm::vec4(0.0f));
            device_.clearDepth(1.0f);
            raster::ProgramState st;
            st.depthTest = st.depthWrite = 1;
            device_.setState(st);
            device_.setTexture(kUnitPhotonRefractor, refractors_[size_t(gl.refractor)].cube, pointClampSampler());
            PhotonFP fp;
            fp.self = f;
            fp.iterations = s.iterations;
            for (int k = 0; k < 3; ++k) {
                fp.light[k] = L[k];
                fp.intensity[k] = sc.lights[size_t(light)].intensity[k];
                fp.axis[k] = axis[k];
            }
            const float edge = 2.0f * tanMax / float(n);
            fp.texelArea = edge * edge;
            fp.board = pb;
            WorldVP vp;
            vp.viewProj = proj * view;
            drawPhotons(device_, vp, fp, std::span<const ImpostorVertex>(gl.world.vertices),
                        std::span<const uint32_t>(gl.world.indices));
        }
        // Pass 2: the splats, read from the photon map by the vertex program.
        {
            raster::ColorTarget ct{target};
            device_.setRenderTargets({&ct, 1});
            raster::ProgramState st;
            st.blend[0] = raster::TargetBlend{1, raster::BlendFactor::One, raster::BlendFactor::One,
                                              raster::BlendOp::Add, raster::kWriteRGBA};
            device_.setState(st);
            device_.setTexture(kUnitPhotonHit, c.hit, pointClampSampler());
            device_.setTexture(kUnitPhotonPower, c.power, pointClampSampler());
            drawSplats(device_, splatVp, splatFp, std::span<const SplatVertex>(c.splats));
        }
    };
    auto accumulate = [&](const std::shared_ptr<tex::Texture>& target, bool statics, bool mover) {
        raster::ColorTarget ct{target};
        device_.setRenderTargets({&ct, 1});
        device_.clearColor(0, glm::vec4(0.0f));
        if (!board) return;
        for (size_t g = 0; g < glass_.size(); ++g) {
            const bool isMover = int(g) == moverGlass_;
            if (isMover ? !mover : !statics) continue;
            for (int i = 0; i < nLights; ++i) piece(g, i, target);
        }
    };
    if (c.black) {
        raster::ColorTarget ct{c.black};
        device_.setRenderTargets({&ct, 1});
        device_.clearColor(0, glm::vec4(0.0f));
    }
    if (staticMap) accumulate(c.statics, true, moverInStatic);
    if (moverMap) accumulate(c.mover, false, !moverInStatic);
}

}  // namespace rg::impostors
