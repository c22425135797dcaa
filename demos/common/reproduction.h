// One shape for every paper: the Reproduction interface and the one registry that
// `retroglass reproduce`, `view`, `bench` and `compare` read.
//
//   registry ──▶ Reproduction ──reproduce()──▶ out/<name>/ (report.md, index.html, results.json)
//                    │ ──prepare(scene, views)──▶ Technique ──render(variant, camera)──▶ RenderedView
//                    │ ──makeDemo()──▶ viewer::Demo (the window, record/replay, headless)
//                    └ ──benchCases()──▶ `retroglass bench` workloads
//
// Adding a paper: implement Reproduction in demos/<paper>/, add one line to
// demos/registry.cpp (and its folder to demos/CMakeLists.txt). docs/architecture.md has the
// details.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "demo.h"
#include "raycore/camera.h"
#include "raycore/image.h"

namespace rg::ray {
struct Scene;
}

namespace rg::demos {

enum class Quality { Quick, Paper };
const char* qualityName(Quality q);
Quality qualityByName(const std::string& name);  // "quick" | "paper", rg::Error otherwise

struct ReproduceOptions {
    Quality quality = Quality::Quick;
    std::filesystem::path outDir;  // the paper's own folder, e.g. out/pem
    int threads = 0;
    bool referencePath = false;    // --path reference: the scalar reference rasterizer
    bool stats = false;            // --stats: print the emulated device's counters
    std::string scene;             // --scene FILE, empty for the built-in scene
    std::string views;             // --views A:B, empty for all
    std::string capture;           // --capture FILE: record the timed viewer frame as a trace
    std::string mover;             // --mover NAME: the object that moves (impostors, with --scene)
};

// A precompute's viewpoint range [begin, end) from `--views A:B` (empty: all `count`).
// rg::Error for a malformed, empty, overlapping-the-end or negative range.
struct ViewRange {
    int begin = 0, end = 0;
    bool all = true;  // no --views given
    static ViewRange parse(const std::string& spec, int count);
};

// One view rendered by a technique on its emulated profile.
struct RenderedView {
    ray::Image image;     // the framebuffer's RGB bytes / 255
    ray::Image drawn;     // 1 where the technique drew the object (alpha > 0), else 0
    double frameMs = 0;   // wall time of the frame on the emulated device
    int passes = 0;       // device passes the frame took
    nlohmann::json counters;  // the device's counters after the frame
};

// The ray-traced reference of one view: the image and the object's coverage (fraction of
// each pixel's samples that hit the object: the mask the measurements use).
struct GroundTruth {
    ray::Image image, coverage;
    std::string tracer;   // which tracer made it, for the table
};

// A paper's technique prepared for one scene and a set of views: its precompute is done
// and it renders any of those views, in each of its variants (its own method and the
// baselines the paper compares against).
class Technique {
  public:
    virtual ~Technique() = default;
    virtual std::vector<std::string> variants() const = 0;
    // The paper's own method among variants(): the one compare ranks first.
    virtual std::string mainVariant() const = 0;
    virtual RenderedView render(const std::string& variant, const ray::Camera& camera) = 0;
    virtual GroundTruth groundTruth(const ray::Camera& camera) = 0;
    virtual double precomputeSeconds() const = 0;
    virtual uint64_t textureBytes(const std::string& variant) const = 0;
    virtual std::string object() const = 0;  // the scene object the technique renders
};

struct PrepareOptions {
    Quality quality = Quality::Quick;
    std::filesystem::path workDir;  // where the precompute keeps its assets
    int threads = 0;
    int width = 320, height = 240;  // the views' image size
};

// A workload `retroglass bench` times for a paper: a frame at the paper's setting, with the
// paper's own figure beside it (no software peer exists for a whole paper's frame).
struct BenchCase {
    std::string name;                     // <workload>, e.g. pem_viewer_on_manifold
    std::string unit = "frames";          // what one item is
    std::map<std::string, double> paper;  // counters to report beside ours, e.g. paper_fps
    // Called with a thread count: builds the fixture and returns the frame to time.
    using Setup = std::function<std::function<std::map<std::string, double>()>(int threads)>;
    Setup setup;
    // Optional: the same frame by a peer in the same run (e.g. "raycore": the ray tracer on
    // the same rays), registered as <name>/<peer>/threads:N so the harness prints the ratio.
    std::string peer;
    Setup setupPeer;
    // Optional: the frame's emulated-device commands, captured once as trace bytes
    // (docs/trace-format.md). `retroglass bench` then also times their replay on ours and on
    // Mesa llvmpipe as <name>_passes/{retroglass,llvmpipe}/threads:N, so the passes alone
    // have a pipeline peer in the same run beside the whole frame's peer.
    std::function<std::vector<uint8_t>()> capture;
};

class Reproduction {
  public:
    virtual ~Reproduction() = default;
    virtual std::string name() const = 0;     // short name: hybrid, pem, impostors, lightfield, tir
    virtual std::string paper() const = 0;    // authors, title, venue
    virtual std::string profile() const = 0;  // the profile of the paper's machine
    // False while only planned: reproduce says so, and the gallery lists it as not built.
    virtual bool built() const { return true; }
    // The settings each quality runs at (for --help, the gallery and results.json).
    virtual nlohmann::json settings(Quality quality) const = 0;

    // The whole reproduction into options.outDir: precompute (resumable, the range
    // options.views), evaluation, figures, report.md, index.html and results.json (with
    // its claims). Returns the results (empty after a partial --views precompute).
    virtual nlohmann::json reproduce(const ReproduceOptions& options) const = 0;

    // `retroglass compare`: the scene object this technique applies to ("" when none: a
    // mirror technique on a scene without mirrors), and the technique prepared for it.
    virtual std::string appliesTo(const ray::Scene& scene) const { return {}; }
    virtual std::unique_ptr<Technique> prepare(const ray::Scene& scene,
                                               const std::vector<ray::Camera>& views,
                                               const PrepareOptions& options) const {
        return nullptr;
    }

    // `retroglass view <name>`; nullptr when the paper has no viewer demo.
    virtual std::unique_ptr<viewer::Demo> makeDemo(const viewer::DemoOptions& options) const {
        return nullptr;
    }
    // `retroglass bench`: the paper's frame workloads.
    virtual std::vector<BenchCase> benchCases() const { return {}; }
    // `retroglass --capture FILE reproduce <name>`: which frame reproduce() records into
    // options.capture (docs/trace-format.md); empty when it records none, and then
    // --capture is an error rather than silently ignored.
    virtual std::string capturedFrame() const { return {}; }
    // The paper's programmable-profile programs, registered by name for traces
    // (rg::raster::registerProgram<VP, FP, V>("<paper>/<pass>"), and registerGlslTwin for a
    // program with a GLSL twin; rasterizer/include/rasterizer/program_registry.h), so that
    // `retroglass replay` plays its captured frames. `retroglass` calls it for every paper
    // at startup; it must be safe to call more than once (registering again is a no-op).
    virtual void registerPrograms() const {}
};

// A paper not built yet: listed, with what it will run on.
class PlannedReproduction final : public Reproduction {
  public:
    PlannedReproduction(std::string name, std::string paper, std::string profile)
        : name_(std::move(name)), paper_(std::move(paper)), profile_(std::move(profile)) {}
    std::string name() const override { return name_; }
    std::string paper() const override { return paper_; }
    std::string profile() const override { return profile_; }
    bool built() const override { return false; }
    nlohmann::json settings(Quality) const override { return nlohmann::json::object(); }
    nlohmann::json reproduce(const ReproduceOptions&) const override;

  private:
    std::string name_, paper_, profile_;
};

// The registry (demos/registry.cpp), in the order the project builds the papers.
const std::vector<const Reproduction*>& reproductions();
// By short name; rg::Error listing the known names otherwise.
const Reproduction& findReproduction(const std::string& name);

}  // namespace rg::demos
