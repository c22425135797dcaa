// Image metrics shared by every reproduction.
#include "raycore/metrics.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

#include "core/error.h"

namespace rg::ray {

namespace {

void requireSameShape(const Image& a, const Image& b) {
    if (a.width != b.width || a.height != b.height || a.channels != b.channels || a.empty())
        throw Error("image comparison needs two non-empty images of one shape (" +
                    std::to_string(a.width) + "×" + std::to_string(a.height) + "×" +
                    std::to_string(a.channels) + " vs " + std::to_string(b.width) + "×" +
                    std::to_string(b.height) + "×" + std::to_string(b.channels) + ")");
}

std::vector<double> luminance(const Image& img) {
    std::vector<double> y(size_t(img.width) * img.height);
    for (int j = 0; j < img.height; ++j)
        for (int i = 0; i < img.width; ++i) {
            glm::vec3 c = img.rgb(i, j);
            y[size_t(j) * img.width + i] =
                img.channels >= 3 ? 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z : double(c.x);
        }
    return y;
}

std::vector<double> pixelErrors(const Image& a, const Image& b) {
    std::vector<double> e(size_t(a.width) * a.height);
    for (size_t p = 0; p < e.size(); ++p) {
        double s = 0.0;
        for (int c = 0; c < a.channels; ++c)
            s += std::abs(double(a.pixels[p * a.channels + c]) - double(b.pixels[p * a.channels + c]));
        e[p] = s / a.channels;
    }
    return e;
}

}  // namespace

double meanSquaredError(const Image& a, const Image& b) {
    requireSameShape(a, b);
    double s = 0.0;
    for (size_t i = 0; i < a.pixels.size(); ++i) {
        double d = double(a.pixels[i]) - double(b.pixels[i]);
        s += d * d;
    }
    return s / double(a.pixels.size());
}

double psnr(const Image& a, const Image& b, double peak) {
    double mse = meanSquaredError(a, b);
    if (mse == 0.0) return std::numeric_limits<double>::infinity();
    return 10.0 * std::log10(peak * peak / mse);
}

namespace {

// SSIM of every 11×11 window that fits, handed to `visit(centreX, centreY, value)` in
// row-major order of the centres. Returns false (and visits nothing) when the image is
// smaller than a window.
template <class Visit>
bool ssimWindows(const std::vector<double>& x, const std::vector<double>& y, int w, int h,
                 double peak, Visit&& visit) {
    const int r = 5;  // 11×11 window
    if (w < 2 * r + 1 || h < 2 * r + 1) return false;
    double g[11];
    double gs = 0.0;
    for (int i = -r; i <= r; ++i) gs += g[i + r] = std::exp(-double(i * i) / (2.0 * 1.5 * 1.5));
    for (double& v : g) v /= gs;
    const double C1 = (0.01 * peak) * (0.01 * peak), C2 = (0.03 * peak) * (0.03 * peak);
    for (int cy = r; cy < h - r; ++cy)
        for (int cx = r; cx < w - r; ++cx) {
            double mx = 0, my = 0, xx = 0, yy = 0, xy = 0;
            for (int j = -r; j <= r; ++j)
                for (int i = -r; i <= r; ++i) {
                    double wt = g[i + r] * g[j + r];
                    double vx = x[size_t(cy + j) * w + cx + i], vy = y[size_t(cy + j) * w + cx + i];
                    mx += wt * vx;
                    my += wt * vy;
                    xx += wt * vx * vx;
                    yy += wt * vy * vy;
                    xy += wt * vx * vy;
                }
            double sx = xx - mx * mx, sy = yy - my * my, sxy = xy - mx * my;
            visit(cx, cy, ((2 * mx * my + C1) * (2 * sxy + C2)) /
                              ((mx * mx + my * my + C1) * (sx + sy + C2)));
        }
    return true;
}

// One unweighted window over the pixels `use` selects (images smaller than a window).
template <class Use>
double ssimWhole(const std::vector<double>& x, const std::vector<double>& y, double peak,
                 Use&& use) {
    const double C1 = (0.01 * peak) * (0.01 * peak), C2 = (0.03 * peak) * (0.03 * peak);
    double mx = 0, my = 0, n = 0;
    for (size_t i = 0; i < x.size(); ++i)
        if (use(i)) mx += x[i], my += y[i], n += 1;
    mx /= n;
    my /= n;
    double vx = 0, vy = 0, cxy = 0;
    for (size_t i = 0; i < x.size(); ++i) {
        if (!use(i)) continue;
        vx += (x[i] - mx) * (x[i] - mx);
        vy += (y[i] - my) * (y[i] - my);
        cxy += (x[i] - mx) * (y[i] - my);
    }
    vx /= n;
    vy /= n;
    cxy /= n;
    return ((2 * mx * my + C1) * (2 * cxy + C2)) / ((mx * mx + my * my + C1) * (vx + vy + C2));
}

}  // namespace

double ssim(const Image& a, const Image& b, double peak) {
    requireSameShape(a, b);
    const std::vector<double> x = luminance(a), y = luminance(b);
    double total = 0.0;
    long count = 0;
    if (!ssimWindows(x, y, a.width, a.height, peak, [&](int, int, double v) {
            total += v;
            ++count;
        }))
        return ssimWhole(x, y, peak, [](size_t) { return true; });
    return total / double(count);
}

MaskedScore compareMasked(const Image& truth, const Image& ours, const Image& mask,
                          const std::string& what, double peak) {
    requireSameShape(truth, ours);
    if (mask.width != truth.width || mask.height != truth.height || mask.channels < 1)
        throw Error(what + ": the mask is " + std::to_string(mask.width) + "×" +
                    std::to_string(mask.height) + ", the images " + std::to_string(truth.width) +
                    "×" + std::to_string(truth.height));
    auto counted = [&](int x, int y) { return mask.at(x, y, 0) >= 0.5f; };
    MaskedScore s;
    double sum = 0;
    Image clamped = truth;
    for (float& v : clamped.pixels) v = std::clamp(v, 0.0f, float(peak));
    for (int y = 0; y < truth.height; ++y)
        for (int x = 0; x < truth.width; ++x) {
            if (!counted(x, y)) continue;
            for (int c = 0; c < truth.channels; ++c) {
                double d = double(clamped.at(x, y, c)) - double(ours.at(x, y, c));
                sum += d * d;
            }
            ++s.pixels;
        }
    if (s.pixels == 0)
        throw Error(what + ": the mask covers no pixel, so there is nothing to measure (does "
                           "the object appear in this view at all?)");
    s.mse = sum / (double(truth.channels) * double(s.pixels));
    s.psnr = s.mse > 0 ? 10.0 * std::log10(peak * peak / s.mse)
                       : std::numeric_limits<double>::infinity();
    const std::vector<double> lx = luminance(clamped), ly = luminance(ours);
    double total = 0;
    long count = 0;
    const bool windows = ssimWindows(lx, ly, truth.width, truth.height, peak,
                                     [&](int cx, int cy, double v) {
                                         if (!counted(cx, cy)) return;
                                         total += v;
                                         ++count;
                                     });
    if (windows && count > 0) {
        s.ssim = total / double(count);
    } else {
        // Too small for a window, or no window centre in the mask (a sliver at the edge):
        // one window over the counted pixels.
        s.ssim = ssimWhole(lx, ly, peak, [&](size_t i) {
            return counted(int(i % size_t(truth.width)), int(i / size_t(truth.width)));
        });
    }
    return s;
}

ErrorStats compareImages(const Image& a, const Image& b, double peak) {
    requireSameShape(a, b);
    ErrorStats s;
    s.width = a.width;
    s.height = a.height;
    std::vector<double> e = pixelErrors(a, b);
    double sum = 0.0;
    for (double v : e) sum += v;
    s.mean = sum / double(e.size());
    std::vector<double> sorted = e;
    // p95: the smallest error at least 95% of pixels do not exceed (nearest rank).
    size_t rank = size_t(std::ceil(0.95 * double(sorted.size())));
    rank = std::clamp<size_t>(rank, 1, sorted.size()) - 1;
    std::nth_element(sorted.begin(), sorted.begin() + long(rank), sorted.end());
    s.p95 = sorted[rank];
    s.max = *std::max_element(e.begin(), e.end());
    double mse = meanSquaredError(a, b);
    s.rmse = std::sqrt(mse);
    s.psnr = psnr(a, b, peak);
    s.ssim = ssim(a, b, peak);
    return s;
}

std::string errorStatsJson(const ErrorStats& s) {
    nlohmann::json j;
    j["mean"] = s.mean;
    j["p95"] = s.p95;
    j["max"] = s.max;
    // JSON has no infinity: identical images report psnr as null.
    j["psnr"] = std::isfinite(s.psnr) ? nlohmann::json(s.psnr) : nlohmann::json(nullptr);
    j["ssim"] = s.ssim;
    j["rmse"] = s.rmse;
    j["width"] = s.width;
    j["height"] = s.height;
    return j.dump(2);
}

void writeErrorStatsJson(const std::filesystem::path& path, const ErrorStats& s) {
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    std::ofstream out(path);
    if (!out) throw Error(path.string() + ": cannot write metrics");
    out << errorStatsJson(s) << "\n";
}

Image errorHeatMap(const Image& a, const Image& b, float scale) {
    requireSameShape(a, b);
    std::vector<double> e = pixelErrors(a, b);
    if (scale <= 0.0f) scale = float(*std::max_element(e.begin(), e.end()));
    Image out(a.width, a.height, 3);
    // Piecewise-linear ramp through black, blue, green, yellow, red, white.
    const glm::vec3 ramp[6] = {{0, 0, 0}, {0, 0, 1}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}, {1, 1, 1}};
    for (size_t p = 0; p < e.size(); ++p) {
        float t = scale > 0.0f ? std::clamp(float(e[p]) / scale, 0.0f, 1.0f) * 5.0f : 0.0f;
        int i = std::min(int(t), 4);
        glm::vec3 c = glm::mix(ramp[i], ramp[i + 1], t - float(i));
        out.setRgb(int(p % size_t(a.width)), int(p / size_t(a.width)), c);
    }
    return out;
}

}  // namespace rg::ray
