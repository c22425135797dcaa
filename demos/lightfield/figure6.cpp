// Figure 6: the basis textures of 4D VQ in the 2D (u, s) case, their basis functions and
// ray fans, and Σ basis under both readings of the paper's "exactly two pixels".
#include "figure6.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "figures.h"
#include "texunit/sampler.h"
#include "texunit/texture.h"

namespace rg::lightfield {

namespace {

constexpr int kSamples = 8;  // samples per axis of the 2D light field drawn (4 blocks)
constexpr int kPanel = 128;

// The 2D basis textures: texel (x, y) = (u parity, s parity); one-hot or "two pixels".
std::shared_ptr<tex::Texture> basisTexture2D(tex::TextureMemory& mem, bool twoPixels) {
    auto t = mem.create({tex::TextureTarget::Texture2D, tex::TexelFormat::A8, 2, 2, 1, 1, 1});
    const std::vector<uint8_t> texels{255, 0, 0, uint8_t(twoPixels ? 255 : 0)};
    mem.upload(*t, 0, 0, texels);
    return t;
}

// One basis pass's alpha at the light-field coordinate (xu, xs) ∈ [0, 1]² for parity class
// (pu, ps): the coordinates renderVq gives the basis pass (N/2 repetitions, one texel's
// shift on an odd axis), sampled LINEAR / WRAP by the emulated unit.
int basisAlpha(const tex::Texture& t, int pu, int ps, float xu, float xs) {
    tex::SamplerState s;  // LINEAR, WRAP
    tex::TapList taps;
    const glm::vec4 c(xu * kSamples * 0.5f - 0.5f * float(pu), xs * kSamples * 0.5f - 0.5f * float(ps), 0.0f, 0.0f);
    tex::gatherTaps(t, s, c, 0, taps);
    return tex::resolveTaps(t, s, taps).a;
}

glm::vec3 classColour(int pu, int ps) {
    static const glm::vec3 c[4] = {{0.85f, 0.15f, 0.1f}, {0.1f, 0.6f, 0.15f}, {0.15f, 0.3f, 0.9f}, {0.9f, 0.55f, 0.0f}};
    return c[ps * 2 + pu];
}

// The 2×2 texture magnified (u right, s up as in the basis panel), a grey grid between texels.
ray::Image texturePanel(bool twoPixels, int pu, int ps) {
    const int M = 48;
    ray::Image img(M, kPanel, 3, 1.0f);
    for (int y = 0; y < M; ++y)
        for (int x = 0; x < M; ++x) {
            const int tu = x * 2 / M, ts = 1 - y * 2 / M;
            // Texel (tu, ts) of the shifted texture holds texel (tu − pu, ts − ps) mod 2.
            const int su = (tu + pu) & 1, ss = (ts + ps) & 1;
            const bool one = (su == 0 && ss == 0) || (twoPixels && su == 1 && ss == 1);
            const bool grid = x == M / 2 || y == M / 2 || x == 0 || y == 0 || x == M - 1 || y == M - 1;
            img.setRgb(x, y + (kPanel - M) / 2, grid ? glm::vec3(0.5f) : glm::vec3(one ? 1.0f : 0.0f));
        }
    return img;
}

// Basis values over the (u, s) domain: u to the right, s upwards.
ray::Image basisPanel(const std::vector<std::vector<int>>& alpha, float scale) {
    ray::Image img(kPanel, kPanel, 3);
    for (int y = 0; y < kPanel; ++y)
        for (int x = 0; x < kPanel; ++x)
            img.setRgb(x, kPanel - 1 - y, glm::vec3(std::min(1.0f, float(alpha[size_t(y)][size_t(x)]) / scale)));
    return img;
}

void line(ray::Image& img, glm::vec2 a, glm::vec2 b, glm::vec3 c) {
    const int n = int(std::ceil(std::max(std::abs(b.x - a.x), std::abs(b.y - a.y)))) + 1;
    for (int i = 0; i <= n; ++i) {
        const glm::vec2 p = a + (b - a) * (float(i) / float(n));
        const int x = int(p.x), y = int(p.y);
        if (x >= 0 && y >= 0 && x < img.width && y < img.height) img.setRgb(x, y, c);
    }
}

// The rays a basis corresponds to: from the eye points s_i (top line) of its s parity to
// the window samples u_k (bottom line) of its u parity — every class whose texel is set.
ray::Image rayFanPanel(const std::vector<std::array<int, 2>>& classes) {
    ray::Image img(kPanel, kPanel, 3, 1.0f);
    const float top = 14.0f, bottom = float(kPanel) - 15.0f;
    auto xAt = [](int i) { return (float(i) + 0.5f) / float(kSamples) * float(kPanel); };
    for (const auto& [pu, ps] : classes)
        for (int i = ps; i < kSamples; i += 2)
            for (int k = pu; k < kSamples; k += 2) line(img, {xAt(i), top}, {xAt(k), bottom}, classColour(pu, ps));
    line(img, {0.0f, top}, {float(kPanel - 1), top}, glm::vec3(0.0f));
    line(img, {0.0f, bottom}, {float(kPanel - 1), bottom}, glm::vec3(0.0f));
    for (int i = 0; i < kSamples; ++i)
        for (int dy = -2; dy <= 2; ++dy)
            for (int dx = -2; dx <= 2; ++dx) {
                img.setRgb(int(xAt(i)) + dx, int(top) + dy, glm::vec3(0.0f));
                img.setRgb(int(xAt(i)) + dx, int(bottom) + dy, glm::vec3(0.0f));
            }
    return img;
}

nlohmann::json sumStats(const std::vector<int>& sums, int textures, int expected) {
    const auto [lo, hi] = std::minmax_element(sums.begin(), sums.end());
    int worst = 0;
    for (int s : sums) worst = std::max(worst, std::abs(s - expected));
    return {{"textures", textures}, {"sum_min", *lo}, {"sum_max", *hi}, {"expected", expected},
            {"max_error_lsb", worst}, {"partition_of_unity", expected == 255}};
}

}  // namespace

Figure6 makeFigure6(const Profile& profile, int points4D) {
    tex::TextureMemory mem(profile);
    Figure6 f;
    std::vector<demos::Cell> cells;
    // ---- 2D: four parity classes (pu, ps), each reading's texture shifted onto each ----------
    std::vector<int> sumOneHot(size_t(kPanel) * kPanel, 0), sumTwoAll(sumOneHot), sumTwoDistinct(sumOneHot);
    for (bool twoPixels : {false, true}) {
        const auto t = basisTexture2D(mem, twoPixels);
        for (int ps = 0; ps < 2; ++ps)
            for (int pu = 0; pu < 2; ++pu) {
                std::vector<std::vector<int>> alpha(kPanel, std::vector<int>(kPanel));
                for (int y = 0; y < kPanel; ++y)
                    for (int x = 0; x < kPanel; ++x) {
                        const int a = basisAlpha(*t, pu, ps, (float(x) + 0.5f) / kPanel, (float(y) + 0.5f) / kPanel);
                        alpha[size_t(y)][size_t(x)] = a;
                        const size_t i = size_t(y) * kPanel + size_t(x);
                        if (!twoPixels) sumOneHot[i] += a;
                        else {
                            sumTwoAll[i] += a;
                            // The shifts by (1, 1) reproduce (0, 0)'s and (1, 0)'s textures:
                            // the distinct ones are the classes with ps = 0.
                            if (ps == 0) sumTwoDistinct[i] += a;
                        }
                    }
                std::vector<std::array<int, 2>> classes{{pu, ps}};
                if (twoPixels) classes.push_back({pu ^ 1, ps ^ 1});
                const std::string name = std::string(twoPixels ? "two pixels" : "one-hot") + ", class (u " +
                                         std::to_string(pu) + ", s " + std::to_string(ps) + ")" +
                                         (twoPixels ? " + (u " + std::to_string(pu ^ 1) + ", s " + std::to_string(ps ^ 1) + ")" : "");
                cells.push_back({demos::hstack({texturePanel(twoPixels, pu, ps), basisPanel(alpha, 255.0f), rayFanPanel(classes)}), name});
            }
    }
    // Σ panels share one scale, two = white, so one reads as mid grey (one = 255 on white
    // paper would vanish); a black frame marks the domain. Padded to the width of the cells
    // above so the labels fit.
    auto sumPanel = [](const std::vector<int>& s, float) {
        std::vector<std::vector<int>> a(kPanel, std::vector<int>(kPanel));
        for (int y = 0; y < kPanel; ++y)
            for (int x = 0; x < kPanel; ++x) a[size_t(y)][size_t(x)] = s[size_t(y) * kPanel + size_t(x)];
        ray::Image img = basisPanel(a, 510.0f);
        for (int k = 0; k < kPanel; ++k) {
            img.setRgb(k, 0, glm::vec3(0.0f));
            img.setRgb(k, kPanel - 1, glm::vec3(0.0f));
            img.setRgb(0, k, glm::vec3(0.0f));
            img.setRgb(kPanel - 1, k, glm::vec3(0.0f));
        }
        return demos::hstack({img, ray::Image(48 + 4 + kPanel, kPanel, 3, 1.0f)});
    };
    f.sums["2d"] = {{"one_hot", sumStats(sumOneHot, 4, 255)},
                    {"two_pixels_one_per_class", sumStats(sumTwoAll, 4, 510)},
                    {"two_pixels_distinct", sumStats(sumTwoDistinct, 2, 255)},
                    {"samples_per_axis", kSamples}, {"points", kPanel * kPanel}};
    auto range = [](const nlohmann::json& j) {
        // ASCII: the label font (DejaVu Sans through OpenImageIO) shows no Σ or en dash here.
        return "sum " + std::to_string(j["sum_min"].get<int>()) + "-" + std::to_string(j["sum_max"].get<int>());
    };
    cells.push_back({sumPanel(sumOneHot, 255.0f), "one-hot, 4 textures: " + range(f.sums["2d"]["one_hot"]) + " (255 = one; grey)"});
    cells.push_back({sumPanel(sumTwoAll, 510.0f), "two pixels, 4 shifts: " + range(f.sums["2d"]["two_pixels_one_per_class"]) + " (white)"});
    cells.push_back({sumPanel(sumTwoDistinct, 255.0f), "two pixels, 2 distinct: " + range(f.sums["2d"]["two_pixels_distinct"]) + " (2 classes each)"});
    f.image = demos::labelledGrid(cells, 4);

    // ---- 4D: the 2^4 textures, 16 parity classes, at random coordinates ------------------------
    // The coordinates renderVq4D gives its basis passes (N/2 repetitions per axis, shifted one
    // texel on odd axes), N = (16, 16, 8, 8), quadrilinear under LINEAR.
    const glm::vec4 n(16.0f, 16.0f, 8.0f, 8.0f);
    std::mt19937 rng(6);
    std::uniform_real_distribution<float> uni(0.0f, 1.0f);
    std::vector<glm::vec4> pts(static_cast<size_t>(points4D));
    for (auto& p : pts) p = {uni(rng), uni(rng), uni(rng), uni(rng)};
    for (bool twoPixels : {false, true}) {
        auto t = mem.create({tex::TextureTarget::Texture4D, tex::TexelFormat::A8, 2, 2, 2, 2, 1});
        std::vector<uint8_t> texels(16, 0);
        texels[0] = 255;
        if (twoPixels) texels[15] = 255;
        mem.upload(*t, 0, 0, texels);
        std::vector<int> all(pts.size(), 0), distinct(pts.size(), 0);
        for (int parity = 0; parity < 16; ++parity) {
            const glm::ivec4 pb(parity & 1, (parity >> 1) & 1, (parity >> 2) & 1, (parity >> 3) & 1);
            for (size_t i = 0; i < pts.size(); ++i) {
                glm::vec4 c;
                for (int a = 0; a < 4; ++a) c[a] = pts[i][a] * n[a] * 0.5f - 0.5f * float(pb[a]);
                tex::SamplerState s;
                tex::TapList taps;
                tex::gatherTaps(*t, s, c, 0, taps);
                const int v = tex::resolveTaps(*t, s, taps).a;
                all[i] += v;
                // Shifting by (1, 1, 1, 1) maps the two-pixel texture onto itself: the classes
                // with t parity 0 give the 8 distinct textures.
                if (pb[3] == 0) distinct[i] += v;
            }
        }
        if (!twoPixels) f.sums["4d"]["one_hot"] = sumStats(all, 16, 255);
        else {
            f.sums["4d"]["two_pixels_one_per_class"] = sumStats(all, 16, 510);
            f.sums["4d"]["two_pixels_distinct"] = sumStats(distinct, 8, 255);
        }
    }
    f.sums["4d"]["points"] = points4D;
    return f;
}

}  // namespace rg::lightfield
