// The papers retroglass reproduces and the entry point of each reproduction.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace rg::demos {

enum class Quality { Quick, Paper };

struct ReproduceOptions {
    Quality quality = Quality::Quick;
    std::filesystem::path outDir;  // the paper's own folder, e.g. out/pem
    int threads = 0;
    bool referencePath = false;    // --path reference: the scalar reference rasterizer
    bool stats = false;            // --stats: print the emulated device's counters
    std::string scene;             // --scene FILE, empty for the built-in scene
    std::string views;             // --views A:B, empty for all
    std::string capture;           // --capture FILE: record the timed viewer frame as a trace
};

struct Reproduction {
    std::string name;      // short name: hybrid, pem, impostors, lightfield, tir
    std::string paper;     // authors, title, venue
    std::string profile;   // the profile of the paper's machine
    // Empty while the reproduction is not built yet. Returns the process exit code and
    // writes report.md and results.json into options.outDir.
    std::function<int(const ReproduceOptions&)> run;
};

const std::vector<Reproduction>& reproductions();

}  // namespace rg::demos
