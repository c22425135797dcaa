// 002 §7's caustics against photon tracing (reproduce_caustics.h).
#include "reproduce_caustics.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include <glm/vec2.hpp>

#include "raycore/accel.h"
#include "raycore/metrics.h"
#include "raycore/tracer_caustics.h"

namespace rg::impostors {

namespace {
using Clock = std::chrono::steady_clock;

double luminance(const ray::Image& im, int x, int y) {
    const glm::vec3 c = im.rgb(x, y);
    return (double(c.x) + double(c.y) + double(c.z)) / 3.0;
}

// The caustics' peaks: texels at least `floor` that no texel within 2 (a 5 × 5 window)
// exceeds (ties go to the first in row order).
std::vector<glm::ivec2> peaks(const ray::Image& im, double floor) {
    std::vector<glm::ivec2> out;
    const int n = im.width;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const double v = luminance(im, x, y);
            if (v < floor) continue;
            bool top = true;
            for (int dy = -2; dy <= 2 && top; ++dy)
                for (int dx = -2; dx <= 2 && top; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if ((dx == 0 && dy == 0) || xx < 0 || yy < 0 || xx >= n || yy >= n) continue;
                    const double w = luminance(im, xx, yy);
                    const bool before = yy < y || (yy == y && xx < x);
                    top = before ? w < v : w <= v;
                }
            if (top) out.push_back({x, y});
        }
    return out;
}

// For each peak of `from`, the distance to the nearest peak of `to` (texels; 1e9 where `to`
// has none), sorted.
std::vector<double> peakOffsets(const std::vector<glm::ivec2>& from, const std::vector<glm::ivec2>& to) {
    std::vector<double> d;
    for (const glm::ivec2& p : from) {
        double best = 1e9;
        for (const glm::ivec2& q : to) best = std::min(best, std::hypot(double(p.x - q.x), double(p.y - q.y)));
        d.push_back(best);
    }
    std::sort(d.begin(), d.end());
    return d;
}

double quantile(const std::vector<double>& sorted, double q) {
    if (sorted.empty()) return 0.0;
    return sorted[std::min(sorted.size() - 1, size_t(q * double(sorted.size() - 1) + 0.5))];
}
}  // namespace

ray::CausticTraceOptions causticTraceOptions(const ImpostorRenderer& r, const ImpostorScene& scene,
                                             const ImpostorSettings& s, int photonsPerAxis) {
    ray::CausticTraceOptions o;
    o.lightMapSize = s.lightMapSize;
    o.photonsPerAxis = photonsPerAxis;
    o.sigmaTexels = s.causticSigma;
    const GridConstants& g = r.board();
    o.board.y = g.boardY;
    for (int k = 0; k < 6; ++k) o.board.uv[k] = g.uv[k];
    o.board.lo = {g.boardLo[0], g.boardLo[1]};
    o.board.hi = {g.boardHi[0], g.boardHi[1]};
    o.objects.assign(scene.glass.begin(), scene.glass.end());
    return o;
}

CausticsComparison compareCaustics(const ImpostorScene& scene, const ImpostorSettings& base, float u,
                                   int referencePhotonsPerAxis, int threads, Path path) {
    CausticsComparison out;
    nlohmann::json& j = out.json;
    // ---- ours: all pieces (static mode), then the mover alone (separated, moved) -------------
    ImpostorRenderer r(scene, threads, path);
    ImpostorSettings s = base;
    s.caustics = true;
    s.mode = Mode::Static;
    s.moverU = u;
    const ImpostorFrame f = r.render(scene.camera, s);
    for (const PassTiming& p : f.passes)
        if (p.name.rfind("caustics", 0) == 0)
            j["passes"][p.name] = {{"ms", p.ms},
                                   {"draw_calls", p.counters.drawCalls},
                                   {"vertex_texture_fetches", p.counters.vertexTextureFetches},
                                   {"fragment_invocations", p.counters.fragmentInvocations},
                                   {"fragments_written", p.counters.fragmentsWritten}};
    out.ours = r.causticImage();
    out.shadows = r.lightMapImage();
    if (scene.mover >= 0) {
        ImpostorRenderer rm(scene, threads, path);
        ImpostorSettings sm = s;
        sm.mode = Mode::Separated;
        rm.render(scene.camera, sm);
        sm.moverU = u > 0.5f ? u - 0.25f : u + 0.25f;
        const ImpostorFrame fm = rm.render(scene.camera, sm);
        for (const PassTiming& p : fm.passes)
            if (p.name == "caustics: the mover")
                j["passes"][p.name] = {{"ms", p.ms},
                                       {"draw_calls", p.counters.drawCalls},
                                       {"vertex_texture_fetches", p.counters.vertexTextureFetches},
                                       {"fragment_invocations", p.counters.fragmentInvocations},
                                       {"fragments_written", p.counters.fragmentsWritten}};
    }
    // ---- the photon-traced reference ---------------------------------------------------------
    const ray::Scene placed = scene.at(u);
    const ray::CausticTraceOptions o = causticTraceOptions(r, scene, s, referencePhotonsPerAxis);
    const auto t0 = Clock::now();
    const ray::CausticTraceResult ref = ray::traceCausticLightMap(placed, o);
    const double refMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    out.reference = ref.lightMap;
    // The reference's own spread: the same trace with half the photons per axis (another
    // sampling of the same caustics), for the peaks' margin.
    ray::CausticTraceOptions oHalf = o;
    oHalf.photonsPerAxis = std::max(1, referencePhotonsPerAxis / 2);
    const ray::CausticTraceResult half = ray::traceCausticLightMap(placed, oHalf);

    // ---- scores --------------------------------------------------------------------------------
    const int n = s.lightMapSize;
    double refMax = 0, sumOurs = 0, sumRef = 0, l1 = 0;
    int refPeakX = 0, refPeakY = 0, ourPeakX = 0, ourPeakY = 0;
    double ourMax = 0;
    double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const double a = luminance(out.ours, x, y), b = luminance(out.reference, x, y);
            if (b > refMax) refMax = b, refPeakX = x, refPeakY = y;
            if (a > ourMax) ourMax = a, ourPeakX = x, ourPeakY = y;
            sumOurs += a, sumRef += b, l1 += std::fabs(a - b);
            sx += a, sy += b, sxx += a * a, syy += b * b, sxy += a * b;
        }
    const double N = double(n) * double(n);
    const double cov = sxy / N - (sx / N) * (sy / N);
    const double corr = cov / std::sqrt(std::max(1e-300, (sxx / N - (sx / N) * (sx / N)) * (syy / N - (sy / N) * (sy / N))));
    // Where the reference's bright caustics are (texels above half its largest irradiance),
    // the share of their energy that ours also puts above a quarter of that largest value
    // within 2σ: the caustics' cores found, whatever their exact shape.
    const int reach = int(std::ceil(2.0 * double(s.causticSigma)));
    double coreEnergy = 0, coreFound = 0;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            const double b = luminance(out.reference, x, y);
            if (b < 0.5 * refMax) continue;
            coreEnergy += b;
            bool found = false;
            for (int dy = -reach; dy <= reach && !found; ++dy)
                for (int dx = -reach; dx <= reach && !found; ++dx) {
                    const int xx = x + dx, yy = y + dy;
                    if (xx < 0 || yy < 0 || xx >= n || yy >= n || dx * dx + dy * dy > reach * reach) continue;
                    found = luminance(out.ours, xx, yy) >= 0.25 * refMax;
                }
            if (found) coreFound += b;
        }
    const double peakOffset = std::hypot(double(ourPeakX - refPeakX), double(ourPeakY - refPeakY));
    // The caustics' peaks above a tenth of the reference's largest irradiance (the sphere's
    // focus and the pieces' brighter caustics): how far ours are from the reference's, against
    // how far the half-photon reference's are (the margin: twice its 90th percentile, at least
    // one texel).
    const double floorIrr = 0.1 * refMax;
    const std::vector<glm::ivec2> pRef = peaks(out.reference, floorIrr), pOurs = peaks(out.ours, floorIrr),
                                  pHalf = peaks(half.lightMap, floorIrr);
    const std::vector<double> offOurs = peakOffsets(pRef, pOurs), offHalf = peakOffsets(pRef, pHalf);
    const double margin = std::max(1.0, 2.0 * quantile(offHalf, 0.9));
    double within = 0;
    for (double d : offOurs) within += d <= margin ? 1.0 : 0.0;
    const double mse = ray::meanSquaredError(out.ours, out.reference);
    // Our photons that reached the board: each splat's weights sum (alpha) to about
    // 2πσ²·(1 − e^(−R²/2σ²)) (the discrete sum of the kernel), so Σ alpha over both maps over
    // that is their count (an estimate to the kernel's sampling, under 1 %).
    double alphaSum = 0;
    for (const tex::Texture* t : {r.causticTexture(false), r.causticTexture(true)})
        if (t)
            for (int i = 0; i < n * n; ++i) alphaSum += double(t->dataF(0, 0)[i].w);
    const double sg = double(s.causticSigma), rr = 3.0 * sg;
    const double ourHits = alphaSum / (2.0 * 3.14159265358979323846 * sg * sg * (1.0 - std::exp(-rr * rr / (2.0 * sg * sg))));
    int64_t ourPhotons = 0;  // photon-map texels drawn: per light and glass or mirror object
    for (uint32_t obj : scene.glass)
        if (placed.materials[placed.objects[obj].material].type != ray::MaterialType::Diffuse)
            ourPhotons += int64_t(std::min<size_t>(placed.lights.size(), DiffuseFP::kMaxLights)) * s.photonMapSize *
                          s.photonMapSize;
    j["settings"] = {{"photon_map_size", s.photonMapSize},
                     {"photons_per_piece_and_light", s.photonMapSize * s.photonMapSize},
                     {"splat_sigma_texels", s.causticSigma},
                     {"splat_radius_texels", 3.0 * s.causticSigma},
                     {"light_map_size", s.lightMapSize},
                     {"caustic_map_format", "RGBA32F, ONE/ONE blending"},
                     {"reference_photons_per_piece_and_light", referencePhotonsPerAxis * referencePhotonsPerAxis},
                     {"reference_other_pieces", "neglected, as 002 §7 and ours"},
                     {"mover_u", u}};
    j["reference_ms"] = refMs;
    j["reference_photons"] = ref.photons;
    j["reference_board_hits"] = ref.boardHits;
    j["ours_photons"] = ourPhotons;
    j["ours_board_hits_estimate"] = ourHits;
    j["reference_photons_lost"] = {{"met_their_object", ref.objectHits},
                                   {"no_exit_found", ref.lostInside},
                                   {"inside_after_max_interfaces", ref.lostInterfaces},
                                   {"leaving_upward_or_level", ref.lostUpward},
                                   {"off_the_board", ref.lostOffBoard}};
    j["scores"] = {{"psnr_db_peak_reference_max", mse > 0 ? 10.0 * std::log10(refMax * refMax / mse) : 99.0},
                   {"relative_l1", sumRef > 0 ? l1 / sumRef : 0.0},
                   {"energy_ratio", sumRef > 0 ? sumOurs / sumRef : 0.0},
                   {"correlation", corr},
                   {"reference_max_irradiance", refMax},
                   {"ours_max_irradiance", ourMax},
                   {"brightest_texel_offset_texels", peakOffset},
                   {"core_energy_found", coreEnergy > 0 ? coreFound / coreEnergy : 0.0},
                   {"core_reach_texels", reach},
                   {"reference_peaks", pRef.size()},
                   {"our_peaks", pOurs.size()},
                   {"peak_floor_irradiance", floorIrr},
                   {"peak_offset_median_texels", quantile(offOurs, 0.5)},
                   {"peak_offset_p90_texels", quantile(offOurs, 0.9)},
                   {"half_photon_reference_peak_offset_p90_texels", quantile(offHalf, 0.9)},
                   {"peak_margin_texels", margin},
                   {"peaks_within_margin", pRef.empty() ? 0.0 : within / double(pRef.size())}};
    return out;
}

}  // namespace rg::impostors
