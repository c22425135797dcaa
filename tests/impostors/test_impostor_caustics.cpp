// 002 §7's caustics against a ball lens (demos/impostors/impostor_caustics.h): a glass
// sphere of radius R and index n lit from straight above focuses the light to its paraxial
// focus f = nR / (2(n − 1)) from its centre. With the board at that distance, the caustic
// light map's peak lies under the centre, its energy equals the power the sphere lets
// through (I·∫(1 − F) dA over its disc: the splat kernel is normalised), and its mean
// radius is the one an exact double-precision trace of the same rays through the sphere
// gives. The same bytes on both paths and any thread count.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "core/error.h"
#include "impostor_renderer.h"
#include "reproduce_caustics.h"
#include "raycore/builtin_scenes.h"
#include "raycore/shapes.h"
#include "raycore/tracer_caustics.h"

namespace rg::impostors {
namespace {

constexpr float kRadius = 0.5f, kIor = 1.5f;
constexpr float kBoardWidth = 4.0f;  // makeChessboard(0.5): 8 squares of 0.5, uv [0, 1]² on top
// The paraxial focus of a ball lens from its centre: f = nR / (2(n − 1)) = 0.75 here.
constexpr float kFocus = kIor * kRadius / (2.0f * (kIor - 1.0f));
// Encircled-energy shares, ours against the exact lens splatted alike: within this.
constexpr double kEncircledTolerance = 0.05;

ImpostorScene ballLens(float centreHeight) {
    ImpostorScene s;
    ray::Scene& sc = s.scene;
    sc.name = "ball_lens";
    ray::Material board;
    board.name = "board";
    board.diffuse = glm::vec3(0.8f);
    ray::Material glass;
    glass.name = "glass";
    glass.type = ray::MaterialType::Glass;
    glass.ior = kIor;
    glass.transmittance = glm::vec3(1.0f);  // no absorption: the power is the Fresnel transmittance alone
    const uint32_t mb = sc.addMaterial(board), mg = sc.addMaterial(glass);
    sc.addObject("board", sc.addMesh(ray::makeChessboard(0.5f)), mb);
    sc.addObject("sphere", sc.addMesh(ray::makeSphere(kRadius, 96, 48)), mg,
                 glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, centreHeight, 0.0f)));
    // Far above: the rays through the sphere are parallel to the board's normal to within
    // R / 1000 rad.
    ray::PointLight l;
    l.name = "sun";
    l.position = {0.0f, 1000.0f, 0.0f};
    l.intensity = glm::vec3(1.0f);
    sc.lights.push_back(l);
    s.camera.eye = {0.0f, 3.0f, 3.0f};
    s.camera.target = {0.0f, 0.0f, 0.0f};
    sc.cameras.push_back(s.camera);
    indexGlass(s);
    return s;
}

ImpostorSettings causticSettings() {
    ImpostorSettings st;
    st.width = st.height = 32;
    st.envSize = 32;
    st.refractorSize = 256;
    st.depth = 1;
    st.lightMapSize = 256;
    st.shadowMapSize = 64;
    st.mode = Mode::Static;
    st.caustics = true;
    return st;
}

// The exact ball lens in double precision: a ray straight down at distance ρ from the axis
// enters the sphere (Snell, 1 → n), leaves it (n → 1), meets the board plane y = 0 at
// radius |r(ρ)|; its power is 1 − F at entry (Schlick, F0 = ((n − 1)/(n + 1))²), as the photon
// program weighs it. Returns {∫(1 − F) dA, ∫|r|(1 − F) dA} over the disc, midpoint rule.
struct LensMoments {
    double power = 0, radiusPower = 0;
};
LensMoments exactLens(double centreHeight) {
    const double R = kRadius, n = kIor, f0 = ((n - 1) / (n + 1)) * ((n - 1) / (n + 1));
    LensMoments m;
    const int steps = 20000;
    for (int k = 0; k < steps; ++k) {
        const double rho = (k + 0.5) * R / steps;
        // Entry at (rho, h) relative to the centre, normal (rho, h)/R, direction (0, −1).
        const double h = std::sqrt(R * R - rho * rho);
        const double nx = rho / R, ny = h / R;
        const double cosI = ny;  // −d·n with d = (0, −1)
        const double mm = 1.0 - cosI;
        const double F = f0 + (1 - f0) * mm * mm * mm * mm * mm;
        auto refract = [](double dx, double dy, double nx, double ny, double eta, double& ox, double& oy) {
            const double c = -(dx * nx + dy * ny);
            const double k2 = 1 - eta * eta * (1 - c * c);
            const double t = eta * c - std::sqrt(k2);
            ox = eta * dx + t * nx;
            oy = eta * dy + t * ny;
        };
        double tx, ty;
        refract(0.0, -1.0, nx, ny, 1.0 / n, tx, ty);
        // The chord: from p on the sphere along t, the far intersection at s = −2 p·t.
        const double px = rho, py = h;
        const double s = -2.0 * (px * tx + py * ty);
        const double qx = px + s * tx, qy = py + s * ty;
        double ox, oy;
        refract(tx, ty, -qx / R, -qy / R, n, ox, oy);  // the normal turned against t
        const double y0 = centreHeight + qy;              // exit height above the board
        const double r = qx + ox * (-y0 / oy);
        const double dA = 2.0 * std::numbers::pi * rho * (R / steps);
        m.power += (1 - F) * dA;
        m.radiusPower += std::fabs(r) * (1 - F) * dA;
    }
    return m;
}

// The splat kernel's normalisation on a size² map over the board: 1/(2πσ²·(1 − e^(−R²/2σ²))·A)
// with R = 3σ and A a texel's world area, so that a splat carries its photon's power.
double splatNorm(int size, double sigma) {
    const double texel = double(kBoardWidth) / size, radius = 3.0 * sigma;
    const double kept = 1.0 - std::exp(-radius * radius / (2.0 * sigma * sigma));
    return 1.0 / (2.0 * std::numbers::pi * sigma * sigma * kept * texel * texel);
}

// A photon of `power` landing at texel position (px, py) of a size² map, splatted as the
// emulated splats are: e^(−r²/2σ²) out to 3σ, times `norm` (the kernel's normalisation over
// its disc and a texel's area).
void splat(std::vector<double>& map, int size, double px, double py, double power, double sigma, double norm) {
    const double radius = 3.0 * sigma;
    for (int y = int(std::floor(py - radius)); y <= int(std::ceil(py + radius)); ++y)
        for (int x = int(std::floor(px - radius)); x <= int(std::ceil(px + radius)); ++x) {
            if (x < 0 || y < 0 || x >= size || y >= size) continue;
            const double dx = (x + 0.5) - px, dy = (y + 0.5) - py, r2 = dx * dx + dy * dy;
            if (r2 > radius * radius) continue;
            map[size_t(y) * size_t(size) + size_t(x)] += power * norm * std::exp(-r2 / (2.0 * sigma * sigma));
        }
}

// The exact lens's light map: photons on a fine grid over the disc (K × K cells of the
// sphere's bounding square, each ray straight down through its centre), traced as above,
// landing at (r·x/ρ, r·z/ρ), splatted with the emulated splats' kernel (σ texels to 3σ,
// normalised over the disc) into a size² map of the board's texels about its centre.
// Returns irradiance per texel (world units).
std::vector<double> exactLightMap(double centreHeight, int size, double sigma) {
    const double R = kRadius, n = kIor, f0 = ((n - 1) / (n + 1)) * ((n - 1) / (n + 1));
    const double texel = double(kBoardWidth) / size, norm = splatNorm(size, sigma);
    std::vector<double> map(size_t(size) * size_t(size), 0.0);
    const int K = 400;
    const double cell = 2.0 * R / K;
    for (int j = 0; j < K; ++j)
        for (int i = 0; i < K; ++i) {
            const double x = -R + (i + 0.5) * cell, z = -R + (j + 0.5) * cell, rho = std::hypot(x, z);
            if (rho >= R) continue;
            const double h = std::sqrt(R * R - rho * rho);
            const double mm = 1.0 - h / R;
            const double F = f0 + (1 - f0) * mm * mm * mm * mm * mm;
            auto refract = [](double dx, double dy, double nx, double ny, double eta, double& ox, double& oy) {
                const double c = -(dx * nx + dy * ny);
                const double t = eta * c - std::sqrt(1 - eta * eta * (1 - c * c));
                ox = eta * dx + t * nx;
                oy = eta * dy + t * ny;
            };
            double tx, ty, ox, oy;
            refract(0.0, -1.0, rho / R, h / R, 1.0 / n, tx, ty);
            const double sc = -2.0 * (rho * tx + h * ty);
            const double qx = rho + sc * tx, qy = h + sc * ty;
            refract(tx, ty, -qx / R, -qy / R, n, ox, oy);
            const double r = qx + ox * (-(centreHeight + qy) / oy);
            const double lx = rho > 0 ? r * x / rho : 0.0, lz = rho > 0 ? r * z / rho : 0.0;
            splat(map, size, 0.5 * size + lx / texel, 0.5 * size + lz / texel, (1 - F) * cell * cell, sigma, norm);
        }
    return map;
}

// The share of a light map's energy within `r` texels of the board's centre.
double encircled(const std::vector<double>& map, int size, double r) {
    double in = 0, all = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const double v = map[size_t(y) * size_t(size) + size_t(x)];
            const double dx = (x + 0.5) - 0.5 * size, dy = (y + 0.5) - 0.5 * size;
            all += v;
            if (dx * dx + dy * dy <= r * r) in += v;
        }
    return all > 0 ? in / all : 0.0;
}

struct Measured {
    double energy = 0, meanRadius = 0;
    int peakX = 0, peakY = 0;
    double peak = 0;
    std::vector<float> bytes;
    std::vector<double> red;  // irradiance per texel
};
Measured measure(const ImpostorRenderer& r, int size) {
    const tex::Texture* t = r.causticTexture(false);
    EXPECT_NE(t, nullptr);
    Measured m;
    if (!t) return m;
    const glm::vec4* d = t->dataF(0, 0);
    const double texelWorld = kBoardWidth / size, area = texelWorld * texelWorld;
    double e = 0, er = 0;
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const glm::vec4 v = d[size_t(y) * size_t(size) + size_t(x)];
            for (int c = 0; c < 4; ++c) m.bytes.push_back(v[c]);
            m.red.push_back(v.x);
            const double dx = (x + 0.5) - 0.5 * size, dy = (y + 0.5) - 0.5 * size;
            e += double(v.x) * area;
            er += double(v.x) * area * std::sqrt(dx * dx + dy * dy) * texelWorld;
            if (v.x > m.peak) m.peak = v.x, m.peakX = x, m.peakY = y;
        }
    m.energy = e;
    m.meanRadius = e > 0 ? er / e : 0;
    return m;
}

TEST(ImpostorCaustics, BallLensFocusesWhereTheExactTraceDoesWithItsPowerConserved) {
    const ImpostorScene scene = ballLens(kFocus);
    const ImpostorSettings st = causticSettings();
    ImpostorRenderer r(scene, 2);
    const ImpostorFrame f = r.render(scene.camera, st);
    bool passFound = false;
    for (const PassTiming& p : f.passes)
        if (p.name == "caustics: all pieces") {
            passFound = true;
            EXPECT_EQ(p.counters.vertexTextureFetches, 2u * 6u * 32u * 32u);  // hit + power per corner
        }
    EXPECT_TRUE(passFound);
    const Measured m = measure(r, st.lightMapSize);
    const LensMoments exact = exactLens(kFocus);
    const double sigmaWorld = st.causticSigma * kBoardWidth / st.lightMapSize;
    // The peak under the centre: texels 127 and 128 straddle it.
    EXPECT_NEAR(m.peakX + 0.5, 0.5 * st.lightMapSize, 1.0) << "peak at texel " << m.peakX << ", " << m.peakY;
    EXPECT_NEAR(m.peakY + 0.5, 0.5 * st.lightMapSize, 1.0) << "peak at texel " << m.peakX << ", " << m.peakY;
    // Energy: I·∫(1 − F) dA over the disc (I = 1). The photon map samples the disc with
    // ~750 photons, its rim quantised to photon-map texels: 3 %.
    EXPECT_NEAR(m.energy / exact.power, 1.0, 0.03) << "caustic energy " << m.energy << " exact " << exact.power;
    // How the power spreads: the share within 2, 4, 8 and 16 texels of the axis, against the
    // exact lens splatted with the same kernel (the mean radius would weigh the grazing rim,
    // which 32 photons across the disc sample with one texel, far more than the caustic).
    const std::vector<double> exactMap = exactLightMap(kFocus, st.lightMapSize, st.causticSigma);
    for (double rad : {2.0, 4.0, 8.0, 16.0})
        EXPECT_NEAR(encircled(m.red, st.lightMapSize, rad), encircled(exactMap, st.lightMapSize, rad), kEncircledTolerance)
            << "within " << rad << " texels (σ " << sigmaWorld << " world units)";
    (void)exact;
    // Focused: the peak irradiance is many times the light's own (I = 1).
    EXPECT_GT(m.peak, 5.0);
}

TEST(ImpostorCaustics, SpreadFollowsTheExactTraceAtTwoBoardDistances) {
    // A ball lens has strong spherical aberration: its marginal rays cross the axis well before
    // the paraxial focus, so with the board between the sphere and that focus more of the
    // light is near the axis than at the focus (the exact trace: half the power within 0.026
    // of the axis with the board 0.125 below the sphere, within 0.069 at the paraxial focus).
    // Ours follows the splatted exact lens at both distances.
    const ImpostorSettings st = causticSettings();
    const float near = kRadius + 0.5f * (kFocus - kRadius);
    const ImpostorScene a = ballLens(near), b = ballLens(kFocus);
    ImpostorRenderer ra(a, 2), rb(b, 2);
    ra.render(a.camera, st);
    rb.render(b.camera, st);
    const Measured ma = measure(ra, st.lightMapSize), mb = measure(rb, st.lightMapSize);
    const std::vector<double> ea = exactLightMap(near, st.lightMapSize, st.causticSigma),
                              eb = exactLightMap(kFocus, st.lightMapSize, st.causticSigma);
    ASSERT_GT(encircled(ea, st.lightMapSize, 4.0), encircled(eb, st.lightMapSize, 4.0));  // the oracle's own order
    EXPECT_GT(encircled(ma.red, st.lightMapSize, 4.0), encircled(mb.red, st.lightMapSize, 4.0));
    for (double rad : {2.0, 4.0, 8.0, 16.0})
        EXPECT_NEAR(encircled(ma.red, st.lightMapSize, rad), encircled(ea, st.lightMapSize, rad), kEncircledTolerance)
            << "within " << rad << " texels";
    EXPECT_NEAR(ma.energy / exactLens(near).power, 1.0, 0.03);
}

// The photon-traced reference's light map of `scene` (photonsPerAxis² per object and light)
// in the board's texture space as the renderer sets it up: irradiance per texel (red), its
// energy, and the trace's counts where `result` is given.
std::vector<double> referenceMap(const ImpostorScene& scene, const ImpostorSettings& st, int photonsPerAxis,
                                 double& energy, ray::CausticTraceResult* result) {
    ImpostorRenderer r(scene, 2);
    r.render(scene.camera, st);  // the board's texture space, as the reproduction takes it
    const ray::CausticTraceResult ref = ray::traceCausticLightMap(scene.scene, causticTraceOptions(r, scene, st, photonsPerAxis));
    std::vector<double> red;
    energy = 0;
    const double area = (kBoardWidth / st.lightMapSize) * (kBoardWidth / st.lightMapSize);
    for (int y = 0; y < st.lightMapSize; ++y)
        for (int x = 0; x < st.lightMapSize; ++x) {
            red.push_back(ref.lightMap.rgb(x, y).x);
            energy += red.back() * area;
        }
    if (result) *result = ref;
    return red;
}

// The photon-traced reference (raycore/tracer_caustics.h) through the same ball lens: its
// energy and spread are the exact lens's too (its meshes are the tessellated sphere's).
TEST(ImpostorCaustics, PhotonTracedReferenceMatchesTheExactLens) {
    const ImpostorScene scene = ballLens(kFocus);
    const ImpostorSettings st = causticSettings();
    double energy = 0;
    const std::vector<double> red = referenceMap(scene, st, 128, energy, nullptr);
    EXPECT_NEAR(energy / exactLens(kFocus).power, 1.0, 0.03) << "reference energy " << energy;
    const std::vector<double> exactMap = exactLightMap(kFocus, st.lightMapSize, st.causticSigma);
    for (double rad : {2.0, 4.0, 8.0, 16.0})
        EXPECT_NEAR(encircled(red, st.lightMapSize, rad), encircled(exactMap, st.lightMapSize, rad), kEncircledTolerance)
            << "within " << rad << " texels";
}

TEST(ImpostorCaustics, SameBytesOnBothPathsAndAnyThreadCount) {
    const ImpostorScene scene = ballLens(kFocus);
    ImpostorSettings st = causticSettings();
    st.lightMapSize = 128;
    st.photonMapSize = 16;
    std::vector<float> first;
    for (Path path : {Path::Fast, Path::Reference})
        for (int threads : {1, 3}) {
            if (path == Path::Reference && threads != 1) continue;
            ImpostorRenderer r(scene, threads, path);
            r.render(scene.camera, st);
            const Measured m = measure(r, st.lightMapSize);
            if (first.empty()) first = m.bytes;
            EXPECT_TRUE(m.bytes == first) << "path " << int(path) << " threads " << threads;
        }
}

// The board's program adds the caustic irradiance to what the lights and shadows leave
// (CausticDiffuseFP): light only comes back, so no pixel of the frame gets darker with
// caustics on, and the focus under the ball lens, which the camera sees beside the sphere,
// gets brighter by many times the board's direct light there.
TEST(ImpostorCaustics, CausticsOnlyAddLightToTheFrame) {
    const ImpostorScene scene = ballLens(kFocus);
    ImpostorSettings st = causticSettings();
    st.width = st.height = 64;
    st.lightMapSize = 128;
    ImpostorRenderer r(scene, 2);
    st.caustics = false;
    r.render(scene.camera, st);
    const ray::Image off = r.frame();
    st.caustics = true;
    r.render(scene.camera, st);
    const ray::Image on = r.frame();
    ASSERT_EQ(on.pixels.size(), off.pixels.size());
    size_t darker = 0, focused = 0;
    for (size_t i = 0; i < on.pixels.size(); ++i) {
        if (on.pixels[i] < off.pixels[i]) ++darker;
        if (on.pixels[i] > 2.0f * off.pixels[i] + 0.05f) ++focused;
    }
    EXPECT_EQ(darker, 0u) << "caustics darkened " << darker << " channel values";
    EXPECT_GT(focused, 0u) << "no pixel shows the focus";
}

// ---- a mirror ball ----------------------------------------------------------------------
// A mirror sphere of radius R and constant reflectance ρ_m resting on the board, lit from
// straight above: a ray at distance ρ from the axis meets it at height h = √(R² − ρ²) over
// its centre and leaves along d' = (2ρh/R², 2h²/R² − 1) — upward for ρ < R/√2, else down
// to the board at radius r = ρ + d'_x·(R + h)/(−d'_y), a ring about the ball's foot (no
// light reaches the axis). Its power is ρ_m·dA. The exact map below traces those rays in
// double and splats them with the emulated kernel, as exactLightMap does for the lens.
constexpr float kMirrorReflectance = 0.8f;

ImpostorScene mirrorBall() {
    ImpostorScene s = ballLens(kRadius);
    ray::Material& m = s.scene.materials[s.scene.objects[1].material];
    m.name = "mirror";
    m.type = ray::MaterialType::Mirror;
    m.fresnel = ray::MirrorFresnel::Constant;
    m.reflectance = glm::vec3(kMirrorReflectance);
    indexGlass(s);
    return s;
}

// The exact mirror ball's light map (size² texels over the board) and the power that lands
// on the board.
std::vector<double> exactMirrorMap(int size, double sigma, double& landed) {
    const double R = kRadius, half = 0.5 * kBoardWidth;
    const double texel = double(kBoardWidth) / size, norm = splatNorm(size, sigma);
    std::vector<double> map(size_t(size) * size_t(size), 0.0);
    landed = 0.0;
    const int K = 800;
    const double cell = 2.0 * R / K;
    for (int j = 0; j < K; ++j)
        for (int i = 0; i < K; ++i) {
            const double x = -R + (i + 0.5) * cell, z = -R + (j + 0.5) * cell, rho = std::hypot(x, z);
            if (rho >= R || rho == 0.0) continue;
            const double h = std::sqrt(R * R - rho * rho);
            const double dx = 2.0 * rho * h / (R * R), dy = 2.0 * h * h / (R * R) - 1.0;
            if (!(dy < 0.0)) continue;  // upward
            const double r = rho + dx * (R + h) / -dy;
            const double lx = r * x / rho, lz = r * z / rho;
            if (std::fabs(lx) > half || std::fabs(lz) > half) continue;
            const double power = kMirrorReflectance * cell * cell;
            landed += power;
            splat(map, size, 0.5 * size + lx / texel, 0.5 * size + lz / texel, power, sigma, norm);
        }
    return map;
}

// 002 §7: "refracting and reflecting materials can focus the light". The mirror ball's
// photons land where the exact reflection puts them, with its power: the energy on the
// board, and its spread over rings about the foot (the light within 1, 1.5, 2 and 3 radii
// of the axis), against the exact map — and none within the ball's own radius but the
// kernel's spill, where a refracting ball would focus.
TEST(ImpostorCaustics, MirrorBallLightsTheRingTheExactReflectionLights) {
    const ImpostorScene scene = mirrorBall();
    ImpostorSettings st = causticSettings();
    st.photonMapSize = 96;  // the ring is the outer 29 % of the disc's radius: finer photons
    ImpostorRenderer r(scene, 2);
    r.render(scene.camera, st);
    const Measured m = measure(r, st.lightMapSize);
    double landed = 0;
    const std::vector<double> exactMap = exactMirrorMap(st.lightMapSize, st.causticSigma, landed);
    ASSERT_GT(landed, 0.05);  // the oracle's own sanity: a good part of the ring is on the board
    EXPECT_NEAR(m.energy / landed, 1.0, 0.03) << "caustic energy " << m.energy << " exact " << landed;
    const double radiusTexels = kRadius / (kBoardWidth / st.lightMapSize);
    for (double k : {1.0, 1.5, 2.0, 3.0})
        EXPECT_NEAR(encircled(m.red, st.lightMapSize, k * radiusTexels), encircled(exactMap, st.lightMapSize, k * radiusTexels),
                    kEncircledTolerance)
            << "within " << k << " radii";
    EXPECT_LT(encircled(m.red, st.lightMapSize, 0.8 * radiusTexels), 0.01) << "light under the ball";
}

// The photon-traced reference (raycore/tracer_caustics.h) reflects off the same mirror ball
// onto the same ring with the same power.
TEST(ImpostorCaustics, PhotonTracedReferenceMatchesTheExactMirrorBall) {
    const ImpostorScene scene = mirrorBall();
    const ImpostorSettings st = causticSettings();
    double energy = 0;
    ray::CausticTraceResult ref;
    const std::vector<double> red = referenceMap(scene, st, 256, energy, &ref);
    double landed = 0;
    const std::vector<double> exactMap = exactMirrorMap(st.lightMapSize, st.causticSigma, landed);
    EXPECT_NEAR(energy / landed, 1.0, 0.03) << "reference energy " << energy << " exact " << landed;
    EXPECT_GT(ref.lostUpward, 0) << "the rays inside R/√2 leave upward";
    const double radiusTexels = kRadius / (kBoardWidth / st.lightMapSize);
    for (double k : {1.0, 1.5, 2.0, 3.0})
        EXPECT_NEAR(encircled(red, st.lightMapSize, k * radiusTexels), encircled(exactMap, st.lightMapSize, k * radiusTexels),
                    kEncircledTolerance)
            << "within " << k << " radii";
}

TEST(ImpostorCaustics, BadPhotonMapSizeAndSigmaAreErrorsNamingThem) {
    ImpostorSettings st = causticSettings();
    st.photonMapSize = 100000;
    try {
        validate(st);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("photon map 100000²"), std::string::npos) << e.what();
    }
    st = causticSettings();
    st.causticSigma = 0.0f;
    EXPECT_THROW(validate(st), Error);
    st.caustics = false;
    EXPECT_NO_THROW(validate(st));  // only checked when caustics are on
}

}  // namespace
}  // namespace rg::impostors
