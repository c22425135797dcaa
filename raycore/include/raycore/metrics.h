// Image comparison, in one place for every reproduction: PSNR, SSIM, error statistics
// (mean, 95th percentile, max) written as JSON, and an error heat map.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "raycore/image.h"

namespace rg::ray {

// Both images must have the same size and channel count (rg::Error otherwise).
// Mean squared error over all channels, and PSNR = 10·log10(peak²/MSE) in dB (+inf when
// the images are equal).
double meanSquaredError(const Image& a, const Image& b);
double psnr(const Image& a, const Image& b, double peak = 1.0);

// Structural similarity (Wang, Bovik, Sheikh & Simoncelli 2004) on luminance
// (0.2126 R + 0.7152 G + 0.0722 B, or the single channel), 11×11 Gaussian window with
// σ = 1.5, K1 = 0.01, K2 = 0.03, dynamic range `peak`; the mean over windows that fit.
double ssim(const Image& a, const Image& b, double peak = 1.0);

// Per-pixel error = mean over channels of |a − b|.
struct ErrorStats {
    double mean = 0, p95 = 0, max = 0;
    double psnr = 0, ssim = 0, rmse = 0;
    int width = 0, height = 0;
};
ErrorStats compareImages(const Image& a, const Image& b, double peak = 1.0);
// {"mean":…, "p95":…, "max":…, "psnr":…, "ssim":…, "rmse":…, "width":…, "height":…}
std::string errorStatsJson(const ErrorStats& s);
void writeErrorStatsJson(const std::filesystem::path& path, const ErrorStats& s);

// Measurements over a mask (a 1-channel image, pixel counted where mask ≥ 0.5): the
// object a technique renders, not the whole frame. MSE over the counted pixels' channels;
// PSNR = 10·log10(peak²/MSE) (+inf when they agree); SSIM as ssim() but averaged over the
// windows whose centre is counted (images smaller than a window: over the counted pixels).
// `truth` is clamped to [0, peak] first (an 8-bit framebuffer cannot hold more). An empty
// mask raises rg::Error naming `what` (e.g. "object 'teapot' in view 'between'"): a
// measurement of nothing is an error, never a perfect score.
struct MaskedScore {
    double psnr = 0, ssim = 0, mse = 0;
    int64_t pixels = 0;
};
MaskedScore compareMasked(const Image& truth, const Image& ours, const Image& mask,
                          const std::string& what, double peak = 1.0);

// Per-pixel error mapped black → blue → green → yellow → red → white over [0, scale]
// (scale ≤ 0: the image's max error).
Image errorHeatMap(const Image& a, const Image& b, float scale = 0.0f);

}  // namespace rg::ray
