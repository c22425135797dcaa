#include "view_command.h"

#include <cinttypes>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include "core/error.h"
#include "reproduction.h"
#include <OpenImageIO/imageio.h>

namespace fs = std::filesystem;

namespace rg::viewer {

const std::vector<std::pair<std::string, std::string>>& keyBindings() {
    static const std::vector<std::pair<std::string, std::string>> b = {
        {"Left/Right, left drag", "orbit around the target (azimuth)"},
        {"Up/Down, left drag", "orbit (elevation)"},
        {"W/S, wheel, right drag", "dolly in/out"},
        {"A/D, Q/E, middle or shift+left drag", "pan left/right, down/up"},
        {"R/F", "raise/lower the eye (still looking at the target)"},
        {"Home or 0", "reset the camera"},
        {"N", "jump to the nearest viewpoint sample"},
        {"PageUp/PageDown or ]/[", "next/previous viewpoint sample"},
        {"Tab", "show/hide the panel"},
        {"F12 or P", "screenshot (framebuffer PNG + window PNG)"},
        {"I", "pass inspector on/off; , and . step through the passes"},
        {"- / =", "step the demo's first continuous parameter (impostors: the moving piece)"},
        {"Esc", "quit"},
        {"gamepad left stick", "orbit"},
        {"gamepad right stick", "dolly (up/down), raise the eye (left/right)"},
        {"gamepad L1/R1", "previous/next viewpoint sample"},
        {"gamepad d-pad left/right", "step the demo's first continuous parameter, as - / ="},
        {"gamepad South (cross, A)", "screenshot; North: reset; East: nearest sample"},
    };
    return b;
}

std::string bindingsHelp() {
    std::string s = "Bindings:\n";
    for (const auto& [k, v] : keyBindings()) {
        char b[200];
        std::snprintf(b, sizeof b, "  %-38s %s\n", k.c_str(), v.c_str());
        s += b;
    }
    return s;
}

void writePixelsPng(const std::string& path, int width, int height, const std::vector<Rgba8>& px) {
    // The bytes as they are: alpha is written unassociated, so OpenImageIO neither divides
    // the colour by it here nor multiplies by it when a reader asks for the same flag
    // (oiiotool --iconfig oiio:UnassociatedAlpha 1).
    if (fs::path(path).has_parent_path()) fs::create_directories(fs::path(path).parent_path());
    auto out = OIIO::ImageOutput::create(path);
    if (!out) throw Error(path + ": no image writer (" + OIIO::geterror() + ")");
    OIIO::ImageSpec spec(width, height, 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (!out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, px.data()))
        throw Error(path + ": cannot write image (" + out->geterror() + ")");
    out->close();
}

void writeFramebufferPng(const std::string& path, const raster::Framebuffer& fb) {
    std::vector<Rgba8> px(fb.color().begin(), fb.color().end());
    writePixelsPng(path, fb.width(), fb.height(), px);
}

namespace {

// The paper's demo through the one registry (demos/registry.cpp).
std::unique_ptr<Demo> makeDemo(const std::string& name, const ViewOptions& o) {
    std::string known;
    for (const demos::Reproduction* r : demos::reproductions()) {
        DemoOptions d;
        d.outDir = fs::path(o.outRoot) / r->name();
        d.scene = o.scene;
        d.threads = o.threads;
        if (r->name() == name) {
            if (std::unique_ptr<Demo> demo = r->makeDemo(d)) return demo;
            throw Error("'" + name + "' has no viewer demo yet (" +
                        (r->built() ? "its reproduction runs: ./retroglass reproduce " + name
                                    : std::string("not built yet")) + ")");
        }
        known += " " + r->name();
    }
    throw Error("unknown demo '" + name + "' (the papers:" + known + ")");
}

// Replays a recording without a window: the same actions at the same frames, every frame
// written as <out>/frame_NNNNN.png, screenshots again as <out>/screenshot_NNNNN.png, and
// each frame's hash checked against the one the window recorded.
int runHeadlessReplay(const ViewOptions& o) {
    Recording r = readRecordingFile(o.replay);
    if (!o.demo.empty() && o.demo != r.demo)
        throw Error("the recording is of demo '" + r.demo + "', not '" + o.demo + "'");
    ViewOptions demoOptions = o;
    demoOptions.scene = r.scene;
    ViewerSession session(makeDemo(r.demo, demoOptions), r.profile, o.threads);
    const fs::path out = o.out.empty() ? fs::path("out/view/replay") : fs::path(o.out);
    fs::create_directories(out);
    std::map<int64_t, uint64_t> expected(r.hashes.begin(), r.hashes.end());
    std::ofstream hashes(out / "hashes.txt");
    size_t next = 0;
    int64_t checked = 0, mismatched = 0;
    for (int64_t f = 0; f < r.frames; ++f) {
        bool shot = false;
        for (; next < r.actions.size() && r.actions[next].frame <= f; ++next) {
            const Action& a = r.actions[next].action;
            if (a.kind == Action::Kind::Screenshot) shot = true;
            try {
                session.apply(a);
            } catch (const Error& e) {
                std::fprintf(stderr, "view: frame %" PRId64 ": %s (the window refused it too)\n", f, e.what());
            }
        }
        session.render(false);
        uint64_t h = session.frameHash();
        writeHash(hashes, f, h);
        char name[64];
        std::snprintf(name, sizeof name, "frame_%05" PRId64 ".png", f);
        writeFramebufferPng((out / name).string(), session.device().framebuffer());
        if (shot) {
            std::snprintf(name, sizeof name, "screenshot_%05" PRId64 ".png", f);
            writeFramebufferPng((out / name).string(), session.device().framebuffer());
        }
        if (auto it = expected.find(f); it != expected.end()) {
            ++checked;
            if (it->second != h) {
                ++mismatched;
                std::fprintf(stderr, "view: frame %" PRId64 " differs from the recording "
                             "(window %016" PRIx64 ", replay %016" PRIx64 ")\n", f, it->second, h);
            }
        }
    }
    std::printf("view: replayed %" PRId64 " frames of %s into %s; %" PRId64 " frame hashes "
                "checked, %" PRId64 " differ\n", r.frames, o.replay.c_str(), out.string().c_str(),
                checked, mismatched);
    return mismatched ? 1 : 0;
}

}  // namespace

int runView(const ViewOptions& o) {
    if (o.headless && o.replay.empty())
        throw Error("--headless needs --replay FILE (a recording made with --record)");
    if (!o.replay.empty() && !o.record.empty())
        throw Error("--replay and --record together: record a new session without --replay");
    if (o.headless) return runHeadlessReplay(o);
    requireDisplay();  // before the demo loads (or precomputes) for nothing
    std::string demoName = o.demo;
    Recording replay;
    if (!o.replay.empty()) {
        replay = readRecordingFile(o.replay);
        if (demoName.empty()) demoName = replay.demo;
    }
    if (demoName.empty()) throw Error("name a demo: retroglass view pem");
    ViewerSession session(makeDemo(demoName, o), o.replay.empty() ? o.profile : replay.profile,
                          o.threads);
    return runWindow(session, o);
}

}  // namespace rg::viewer
