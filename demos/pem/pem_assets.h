// PEM assets on disk: each inferred map as an EXR image (OpenImageIO) plus JSON.
//
//   <dir>/manifest.json        settings and EM geometry; what a loader checks
//   <dir>/shard.json           identity of the views (demos/common/shards.h)
//   <dir>/view_007/view.json   one viewpoint sample: its camera; timing.json its timings
//   <dir>/view_007/body_local.exr, body_distant.exr, ... ground_truth.exr, coverage.exr
//
// A map's EXR is baseSize wide; level l, face f, row y is image row Σ_{k<l} faces·size_k
// + f·size_l + y; values are the RGBA8 texels / 255 in 32-bit float, so loading rounds
// back to the same bytes and a loaded PEM renders the same frame bit for bit. Views live
// in their own folders so that a precompute split by viewpoint ranges (--views A:B) on
// several machines merges by copying the folders together.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "pem_precompute.h"

namespace rg::pem {

void saveMap(const std::filesystem::path& path, const MapTexels& map);
// Raises rg::Error naming the file when it is missing or does not match `layout`.
MapTexels loadMap(const std::filesystem::path& path, const TexelLayout& layout);

// The settings that decide whether stored views can be reused.
nlohmann::json manifestFor(const PemScene& scene, const PemSettings& settings, int emSize);
void writeManifest(const std::filesystem::path& dir, const nlohmann::json& manifest);
// True when <dir>/manifest.json exists and equals `manifest`.
bool manifestMatches(const std::filesystem::path& dir, const nlohmann::json& manifest);

// Writes one view's files into `viewDir` (a ViewStore's beginView folder, demos/common/shards.h).
void saveView(const std::filesystem::path& viewDir, const PemScene& scene, const ViewSample& v,
              const ray::Camera& camera);
// nullopt when the view was not stored; rg::Error when it is stored but broken.
std::optional<ViewSample> loadView(const std::filesystem::path& dir, const PemScene& scene,
                                   int view, int emSize, int ptmSize);

}  // namespace rg::pem
