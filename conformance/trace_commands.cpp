// `retroglass replay FILE` plays a trace and prints the SHA-256 of the raw framebuffer
// bytes; `retroglass conform` compares our replay of every golden trace with Mesa's.
#include "conformance/trace_commands.h"

#include <CLI/CLI.hpp>
#include <OpenImageIO/imageio.h>

#include <cstdio>

#include "conformance/mesa_player.h"
#include "core/error.h"
#include "rasterizer/trace.h"

namespace rg::conformance {

namespace {

// The framebuffer's bytes as they are. Alpha is declared unassociated: OpenImageIO takes
// RGBA as premultiplied unless told, and a PNG (whose colour is never premultiplied) would
// then be written with colour divided by alpha wherever 0 < alpha < 255.
void writePng(const std::string& file, const raster::Framebuffer& fb) {
    auto out = OIIO::ImageOutput::create(file);
    if (!out) throw Error("cannot write image '" + file + "': " + OIIO::geterror());
    OIIO::ImageSpec spec(fb.width(), fb.height(), 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    if (!out->open(file, spec) || !out->write_image(OIIO::TypeDesc::UINT8, fb.color().data()))
        throw Error("cannot write image '" + file + "': " + out->geterror());
    out->close();
}

// The bare RGBA8 bytes, rows top to bottom: what the printed SHA-256 is of.
void writeRaw(const std::string& file, const raster::Framebuffer& fb) {
    std::FILE* f = std::fopen(file.c_str(), "wb");
    if (!f) throw Error("cannot write '" + file + "'");
    const size_t n = fb.color().size_bytes();
    const bool ok = std::fwrite(fb.color().data(), 1, n, f) == n;
    if (std::fclose(f) != 0 || !ok) throw Error("cannot write '" + file + "' (disk full?)");
}

}  // namespace

TraceCommands::TraceCommands(CLI::App& app) {
    replay_ = app.add_subcommand("replay", "replay a captured trace (docs/trace-format.md) and print "
                                           "the SHA-256 of the raw framebuffer bytes");
    replay_->add_option("file", file_, "the .trace file")->required();
    replay_->add_option("--out", out_, "write the framebuffer as a PNG (its bytes as they are, alpha unassociated)");
    replay_->add_option("--raw", raw_, "write the framebuffer's bare RGBA8 bytes, rows top to bottom");
    replay_->add_option("--pass", pass_, "stop when pass K (from 0) ends: the state after it");
    replay_->add_option("--backend", backend_, "ours (the emulation) or mesa (OSMesa llvmpipe, GL 1.3)")
        ->check(CLI::IsMember({"ours", "mesa"}));
    conform_ = app.add_subcommand("conform", "replay every golden trace on ours and on Mesa and "
                                             "compare against the tolerances of docs/hardware.md");
    conform_->add_option("--golden", goldenDir_, "folder of golden traces (default tests/golden)");
    // `retroglass replay FILE --threads N --path reference` as docs/trace-format.md writes
    // it: the program's global options are accepted after the subcommand too.
    replay_->fallthrough();
    conform_->fallthrough();
}

bool TraceCommands::parsed() const { return replay_->parsed() || conform_->parsed(); }

int TraceCommands::run(int threads, const std::string& path) const {
    if (conform_->parsed()) return runConform(goldenDir_.empty() ? std::string(RETROGLASS_SOURCE_DIR "/tests/golden") : goldenDir_);
    const raster::Trace trace = raster::readTraceFile(file_);
    raster::Framebuffer fb;
    std::string hash;  // ours: ReplayResult::hash; Mesa: of its RGBA8 image
    if (backend_ == "mesa") {
        if (pass_ >= 0) throw Error("--pass is not supported with --backend mesa");
        MesaReplay m = replayOnMesa(trace);
        if (!m.unsupported.empty()) {
            std::fprintf(stderr, "retroglass: ours only: %s\n", oursOnlyReason(trace).c_str());
            return 4;
        }
        fb = std::move(m.framebuffer);
        hash = raster::framebufferHash(fb);
    } else {
        if (pass_ >= 0 && trace.passCount() == 0)
            throw Error("--pass " + std::to_string(pass_) + ": '" + file_ +
                        "' has no BeginPass records; replay it without --pass");
        raster::ReplayOptions o;
        o.path = path == "reference" ? Path::Reference : Path::Fast;
        o.threads = threads;
        o.stopAfterPass = pass_;
        raster::ReplayResult r = raster::replayTrace(trace, o);
        if (r.readBacks)
            std::printf("read-backs: %d, %d differing from the capture\n", r.readBacks, r.readBackMismatches);
        if (r.targetChecks)
            std::printf("render targets: %d, %d differing from the capture\n", r.targetChecks, r.targetMismatches);
        fb = std::move(r.framebuffer);
        hash = r.hash;
    }
    if (!out_.empty() || !raw_.empty()) {
        if (fb.width() == 0) throw Error("--out/--raw: '" + file_ + "' binds no colour target, so it has no image");
        if (!out_.empty()) writePng(out_, fb);
        if (!raw_.empty()) writeRaw(raw_, fb);
    }
    std::printf("%s  %s (%s, %dx%d%s)\n", hash.c_str(), file_.c_str(),
                trace.profile.c_str(), fb.width(), fb.height(),
                pass_ >= 0 ? (", after pass " + std::to_string(pass_)).c_str() : "");
    return 0;
}

}  // namespace rg::conformance
