// A precompute split by viewpoint ranges and merged back: the folder of finished views that
// every paper's precompute keeps, written so that a kill never leaves a half view behind,
// and `retroglass merge`, which joins the folders of several `--views A:B` runs (one per
// Slurm array task, docs/cluster.md) only when they provably belong together.
//
//   <out>/<paper>/assets/          (assets-paper/ at paper quality)
//       shard.json           identity: paper, quality, profile, code version, SHA-256 of
//                            the settings and of the scene, view count; the ranges run here
//       view_007/            one finished view: the paper's files + files.json (bytes and
//                            SHA-256 of each, so a truncated or corrupt file is caught)
//       view_008.partial/    a view being written; renamed to view_008/ once complete, so
//                            a run killed mid-write leaves it unfinished, never half-there
//
// A store holding another identity is refused, never cleared: finished views are the
// expensive part of a paper run and are kept whatever the mistake. The one exception is a
// store that only whole runs wrote, made by older code (every commit makes one of the
// default out/): its views are computed again, as before shards.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "reproduction.h"

namespace rg::demos {

// The version of the code that made a shard: the commit, "+dirty-<hash of the diff>" for
// uncommitted changes (generated at build time, cmake/code_version.cmake).
const std::string& codeVersion();

std::string sha256OfBytes(const std::string& bytes);
// rg::Error naming the file when it cannot be read.
std::string sha256OfFile(const std::filesystem::path& file);

// What must agree for views to be merged or reused.
struct ShardIdentity {
    std::string paper, quality, profile;
    std::string codeVersion;
    std::string settingsSha256;  // of the paper's settings, as JSON
    std::string sceneSha256;     // of the scene (its file, or the built-in scene's recipe)
    int views = 0;               // viewpoints of the whole precompute

    nlohmann::json toJson() const;
    // rg::Error naming `file` for a missing field.
    static ShardIdentity fromJson(const nlohmann::json& j, const std::filesystem::path& file);
    // The fields that differ, for an error message; empty when the identities agree.
    std::string differenceFrom(const ShardIdentity& other) const;
    bool operator==(const ShardIdentity&) const = default;
};

std::string viewFolderName(int view);  // view_007

// A paper's assets folder in its output folder: `assets` for quick quality, `assets-paper`
// for paper quality, so that both qualities' views live side by side in one --out.
std::filesystem::path assetsFolder(const std::filesystem::path& paperOut, const std::string& quality);

// One paper's folder of finished views.
class ViewStore {
  public:
    // Opens `dir` (creating it when absent) for views of `identity`. rg::Error naming
    // shard.json when the folder holds views of another identity, except views of older
    // code from whole runs (no --views), which are computed again; leftover .partial views
    // of a killed run are removed (they were never finished).
    ViewStore(std::filesystem::path dir, ShardIdentity identity);

    const std::filesystem::path& dir() const { return dir_; }
    const ShardIdentity& identity() const { return identity_; }
    // Records a range run into this store (merge checks that each one finished).
    void addRange(const ViewRange& range);

    bool finished(int view) const;
    std::filesystem::path viewDir(int view) const;  // the finished view's folder
    // Writing a view: fill the folder beginView returns, then commitView checksums its files
    // and renames it into place. rg::Error naming the folder when a write fails (full disk).
    std::filesystem::path beginView(int view) const;
    void commitView(int view) const;
    // rg::Error naming the file when a finished view's file is missing, truncated or corrupt.
    void verifyView(int view) const;

  private:
    void writeIdentity(const nlohmann::json& ranges) const;
    std::filesystem::path dir_;
    ShardIdentity identity_;
};

// `retroglass merge`: joins the stores of `shards` (each an assets folder, or a `--out`
// folder holding one paper's) into <outDir>/<paper>/assets[-paper], which must not exist; then
// `retroglass reproduce <paper> --out <outDir>` evaluates the merged views.
// Everything is checked before anything is written: one identity, made by this code;
// every range each shard ran finished; no view in two shards; every view of the whole
// precompute present; every file matching its checksum. rg::Error naming the offending
// file otherwise, with nothing written.
struct MergeResult {
    std::string paper;
    std::filesystem::path assets;
    int views = 0;
};
MergeResult mergeShards(const std::vector<std::filesystem::path>& shards,
                        const std::filesystem::path& outDir);

}  // namespace rg::demos
