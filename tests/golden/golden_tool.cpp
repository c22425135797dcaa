// retroglass_golden: writes the golden traces and checks them.
//
//   retroglass_golden write DIR              regenerate DIR/<name>.trace from golden_cases.cpp
//   retroglass_golden manifest DIR           print "<name> <sha256>  # covers" per trace
//   retroglass_golden check NAME FILE HASH   the CTest test golden.<NAME>: the generator
//       still makes FILE byte for byte, and replaying FILE gives HASH on the reference
//       path (1 thread) and the fast path (1, 2 and 3 threads), with every read-back and
//       render target as at capture. A mismatch prints the `retroglass replay` command
//       that reproduces it.
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "golden_cases.h"
#include "rasterizer/trace.h"

namespace fs = std::filesystem;
using namespace rg::raster;
using rg::Path;

namespace {

std::vector<uint8_t> readFile(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

int check(const std::string& name, const fs::path& file, const std::string& expected) {
    int failures = 0;
    const std::vector<uint8_t> bytes = readFile(file);
    if (bytes != rg::golden::buildGoldenTrace(name)) {
        std::printf("FAIL %s: tests/golden/golden_cases.cpp no longer generates %s byte for byte.\n"
                    "  If the change is intended, regenerate and re-hash (docs/testing.md):\n"
                    "    build/bin/retroglass_golden write tests/golden && "
                    "build/bin/retroglass_golden manifest tests/golden > tests/golden/manifest.txt\n",
                    name.c_str(), file.string().c_str());
        ++failures;
    }
    const Trace trace = readTrace(bytes);
    struct Config { Path path; int threads; };
    for (Config c : {Config{Path::Reference, 1}, Config{Path::Fast, 1}, Config{Path::Fast, 2}, Config{Path::Fast, 3}}) {
        const ReplayResult r = replayTrace(trace, {c.path, c.threads, -1});
        const std::string got = r.hash;
        const bool readOk = r.readBackMismatches == 0 && r.targetMismatches == 0;
        if (got != expected || !readOk) {
            std::printf("FAIL %s on path %s, %d thread%s: sha256 %s, expected %s%s\n"
                        "  reproduce: ./retroglass --path %s --threads %d replay %s --out %s.png\n",
                        name.c_str(), std::string(rg::pathName(c.path)).c_str(), c.threads,
                        c.threads == 1 ? "" : "s", got.c_str(), expected.c_str(),
                        readOk ? "" : " (and read-backs or render targets differ from the capture)",
                        std::string(rg::pathName(c.path)).c_str(), c.threads, file.string().c_str(),
                        name.c_str());
            ++failures;
        } else {
            std::printf("ok   %s on path %s, %d thread%s: %s\n", name.c_str(),
                        std::string(rg::pathName(c.path)).c_str(), c.threads, c.threads == 1 ? "" : "s",
                        got.c_str());
        }
    }
    return failures ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        rg::golden::registerGoldenPrograms();
        const std::string cmd = argc > 1 ? argv[1] : "";
        if (cmd == "write" && argc == 3) {
            for (const auto& c : rg::golden::goldenCases()) {
                const std::vector<uint8_t> bytes = rg::golden::buildGoldenTrace(c.name);
                std::ofstream f(fs::path(argv[2]) / (c.name + ".trace"), std::ios::binary);
                f.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
                std::printf("%-32s %6zu bytes\n", c.name.c_str(), bytes.size());
            }
            return 0;
        }
        if (cmd == "manifest" && argc == 3) {
            std::printf("# Golden traces: <name> <sha256 of the replayed framebuffer's RGBA8 bytes (programmable: of the image target's values)>  # what it covers\n"
                        "# Regenerate: docs/testing.md, \"Golden traces\". A changed hash needs a commit saying why.\n");
            for (const auto& c : rg::golden::goldenCases()) {
                const Trace t = readTraceFile(fs::path(argv[2]) / (c.name + ".trace"));
                const ReplayResult r = replayTrace(t, {Path::Reference, 1, -1});
                std::printf("%s %s  # %s\n", c.name.c_str(), r.hash.c_str(), c.covers.c_str());
            }
            return 0;
        }
        if (cmd == "check" && argc == 5) return check(argv[2], argv[3], argv[4]);
        if (cmd == "list" && argc == 2) {  // the cases this build has (a sanitizer build: no demo frames)
            for (const auto& c : rg::golden::goldenCases()) std::printf("%s\n", c.name.c_str());
            return 0;
        }
        std::fprintf(stderr, "usage: retroglass_golden write DIR | manifest DIR | check NAME FILE HASH | list\n");
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "retroglass_golden: %s\n", e.what());
        return 1;
    }
}
