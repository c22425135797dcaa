#include "viewer_session.h"

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "core/profile.h"
#include "texunit/format.h"
#include "texunit/stages.h"
#include "texunit/texture.h"

namespace rg::viewer {

// ---- device state as text ---------------------------------------------------------------

namespace {

const char* compareName(raster::CompareFunc f) {
    static const char* n[] = {"NEVER", "LESS", "EQUAL", "LESSEQUAL",
                              "GREATER", "NOTEQUAL", "GREATEREQUAL", "ALWAYS"};
    return n[size_t(f) % 8];
}
const char* blendName(raster::BlendFactor f) {
    static const char* n[] = {"ZERO", "ONE", "SRCCOLOR", "INVSRCCOLOR", "SRCALPHA",
                              "INVSRCALPHA", "DESTALPHA", "INVDESTALPHA", "DESTCOLOR",
                              "INVDESTCOLOR", "SRCALPHASAT", "BOTHSRCALPHA", "BOTHINVSRCALPHA"};
    return n[size_t(f) % 13];
}
const char* cullName(raster::CullMode c) {
    return c == raster::CullMode::None ? "NONE" : c == raster::CullMode::CW ? "CW" : "CCW";
}
std::string argName(uint8_t a) {
    static const char* n[] = {"DIFFUSE", "CURRENT", "TEXTURE", "TFACTOR", "SPECULAR"};
    uint8_t s = a & tex::arg::SourceMask;
    std::string r = s < 5 ? n[s] : "?";
    if (a & tex::arg::Complement) r += "|COMPLEMENT";
    if (a & tex::arg::AlphaReplicate) r += "|ALPHAREPLICATE";
    return r;
}
std::string textureName(const tex::Texture* t) {
    if (!t) return "none (reads white)";
    static const char* targets[] = {"1D", "2D", "3D", "cube", "4D"};
    const tex::TextureDesc& d = t->desc();
    char b[160];
    std::snprintf(b, sizeof b, "%s %dx%d%s, %d levels, %s, %" PRIu64 " bytes",
                  targets[size_t(d.target) % 5], d.width, d.height, t->faces() == 6 ? "x6" : "",
                  d.levels, std::string(t->format().name).c_str(), t->bytes());
    return b;
}

}  // namespace

std::string describeDeviceState(const raster::Device& device) {
    std::ostringstream o;
    const raster::PipelineState& s = device.state();
    o << "profile " << device.profile().name << "\n";
    o << "depth " << (s.depthTest ? compareName(s.depthFunc) : "off")
      << (s.depthWrite ? ", write" : ", no write") << "   cull " << cullName(s.cull) << "\n";
    if (s.blend)
        o << "blend " << blendName(s.srcBlend) << " / " << blendName(s.dstBlend) << "\n";
    else
        o << "blend off\n";
    if (s.alphaTest) o << "alpha test " << compareName(s.alphaFunc) << " " << int(s.alphaRef) << "\n";
    const tex::TextureUnits& tu = device.textureUnits();
    Rgba8 f = tu.textureFactor();
    o << "TFACTOR (" << int(f.r) << ", " << int(f.g) << ", " << int(f.b) << ", " << int(f.a) << ")\n";
    for (int i = 0; i < device.profile().maxTextureStages; ++i) {
        const tex::StageState& st = tu.stage(i);
        if (st.colorOp == tex::TextureOp::Disable) {
            o << "stage " << i << " DISABLE\n";
            break;
        }
        o << "stage " << i << " color " << tex::textureOpName(st.colorOp) << "("
          << argName(st.colorArg1) << ", " << argName(st.colorArg2) << ")  alpha "
          << tex::textureOpName(st.alphaOp) << "(" << argName(st.alphaArg1) << ", "
          << argName(st.alphaArg2) << ")  coords " << int(st.texCoordIndex) << "\n"
          << "        texture " << textureName(tu.texture(i).get()) << "\n";
    }
    return o.str();
}

// ---- actions ----------------------------------------------------------------------------

const char* actionVerb(Action::Kind k) {
    switch (k) {
        case Action::Kind::Orbit: return "orbit";
        case Action::Kind::Dolly: return "dolly";
        case Action::Kind::Pan: return "pan";
        case Action::Kind::Raise: return "raise";
        case Action::Kind::Reset: return "reset";
        case Action::Kind::Sample: return "sample";
        case Action::Kind::Step: return "step";
        case Action::Kind::Nearest: return "nearest";
        case Action::Kind::Param: return "param";
        case Action::Kind::Profile: return "profile";
        case Action::Kind::Threads: return "threads";
        case Action::Kind::Screenshot: return "screenshot";
    }
    return "?";
}

// ---- session ----------------------------------------------------------------------------

std::optional<Action> nudgeAction(const std::vector<Param>& params, int direction) {
    for (const Param& p : params) {
        if (p.kind != Param::Kind::Float) continue;
        const double v = std::clamp(p.value + double(direction) * (p.max - p.min) / 20.0, p.min, p.max);
        return Action{Action::Kind::Param, 0, 0, v, p.name};
    }
    return std::nullopt;
}

ViewerSession::ViewerSession(std::unique_ptr<Demo> demo, const std::string& profile, int threads)
    : demo_(std::move(demo)), threads_(threads) {
    rig_ = demo_->rig();
    camera_ = OrbitCamera::fromCamera(rig_.start);
    samples_ = demo_->viewpointSamples();
    makeDevice(profile.empty() ? demo_->defaultProfile() : profile);
}

void ViewerSession::makeDevice(const std::string& profile) {
    auto [w, h] = demo_->frameSize();
    device_ = std::make_unique<raster::Device>(profileByName(profile), w, h,
                                               raster::DepthFormat::D24,
                                               raster::DeviceOptions{Path::Fast, threads_});
    profile_ = profile;
}

int ViewerSession::nearestSample() const {
    int best = -1;
    float bestCos = -2.0f;
    ray::Camera c = camera_.camera();
    glm::vec3 d = glm::normalize(c.eye - c.target);
    for (size_t i = 0; i < samples_.size(); ++i) {
        const ray::Camera& s = samples_[i].camera;
        float cs = glm::dot(d, glm::normalize(s.eye - s.target));
        if (cs > bestCos) bestCos = cs, best = int(i);
    }
    return best;
}

void ViewerSession::apply(const Action& a) {
    switch (a.kind) {
        case Action::Kind::Orbit: camera_.orbit(a.x, a.y); break;
        case Action::Kind::Dolly: camera_.dolly(a.x, rig_.minDistance, rig_.maxDistance); break;
        case Action::Kind::Pan: camera_.pan(a.x, a.y); break;
        case Action::Kind::Raise: camera_.raise(a.x); break;
        case Action::Kind::Reset: camera_ = OrbitCamera::fromCamera(rig_.start); break;
        case Action::Kind::Sample:
        case Action::Kind::Step:
        case Action::Kind::Nearest: {
            if (samples_.empty()) break;
            int n = int(samples_.size());
            int i = a.kind == Action::Kind::Sample ? int(a.value)
                    : a.kind == Action::Kind::Nearest ? nearestSample()
                                                      : nearestSample() + int(a.value);
            i = ((i % n) + n) % n;
            camera_ = OrbitCamera::fromCamera(samples_[size_t(i)].camera);
            break;
        }
        case Action::Kind::Param: {
            Param& p = findParam(demo_->params(), a.name);
            double v = a.value;
            if (p.kind == Param::Kind::Bool) v = v != 0 ? 1 : 0;
            if (p.kind == Param::Kind::Enum) v = std::clamp(std::round(v), 0.0, double(p.choices.size()) - 1);
            if (p.kind == Param::Kind::Int) v = std::clamp(std::round(v), p.min, p.max);
            if (p.kind == Param::Kind::Float) v = std::clamp(v, p.min, p.max);
            const double old = p.value;
            p.value = v;
            try {
                demo_->checkParams();
            } catch (...) {
                p.value = old;
                throw;
            }
            break;
        }
        case Action::Kind::Profile: {
            if (a.name == profile_) break;
            std::unique_ptr<raster::Device> old = std::move(device_);
            std::string oldName = profile_;
            try {
                makeDevice(a.name);
                // Draw once so that a profile the demo cannot run on is refused here.
                demo_->render(*device_, camera_.camera());
            } catch (...) {
                device_ = std::move(old);
                profile_ = oldName;
                demo_->render(*device_, camera_.camera());  // rebinds the demo
                throw;
            }
            break;
        }
        case Action::Kind::Threads:
            threads_ = int(a.value);
            device_->setThreads(threads_);
            break;
        case Action::Kind::Screenshot: break;  // the caller writes the file
    }
}

void ViewerSession::render(bool capturePasses) {
    snapshots_.clear();
    raster::Device& dev = *device_;
    if (capturePasses)
        dev.setPassObserver([this, &dev](const raster::PassRecord& r, const raster::Framebuffer& fb) {
            PassSnapshot s;
            s.record = r;
            s.width = fb.width();
            s.height = fb.height();
            s.color.assign(fb.color().begin(), fb.color().end());
            s.state = describeDeviceState(dev);
            snapshots_.push_back(std::move(s));
        });
    else
        dev.setPassObserver({});
    demo_->setCapturePasses(capturePasses);
    auto t0 = std::chrono::steady_clock::now();
    notes_ = demo_->render(dev, camera_.camera());
    frameMs_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    dev.setPassObserver({});
    if (!capturePasses) return;
    // A programmable demo's passes, one snapshot per target, before the hand-over pass.
    std::vector<PassSnapshot> programmable;
    for (const ProgrammablePass& p : demo_->programmablePasses())
        for (const TargetImage& t : p.targets) {
            PassSnapshot s;
            s.record.label = p.label + ": " + t.name;
            s.record.drawCalls = 0;
            s.width = dev.framebuffer().width();
            s.height = dev.framebuffer().height();
            s.color = displayTarget(t, s.width, s.height, &s.range);
            s.state = p.state;
            s.target = t.name;
            s.image = t;
            programmable.push_back(std::move(s));
        }
    snapshots_.insert(snapshots_.begin(), std::make_move_iterator(programmable.begin()),
                      std::make_move_iterator(programmable.end()));
}

uint64_t ViewerSession::frameHash() const {
    uint64_t h = 1469598103934665603ull;
    for (const Rgba8& c : device_->framebuffer().color())
        for (uint8_t b : {c.r, c.g, c.b, c.a}) h = (h ^ b) * 1099511628211ull;
    return h;
}

// ---- record format ----------------------------------------------------------------------

void writeRecordingHeader(std::ostream& out, const Recording& r) {
    out << "retroglass-view-record 1\n"
        << "demo " << r.demo << "\n"
        << "profile " << r.profile << "\n"
        << "scene " << (r.scene.empty() ? "-" : r.scene) << "\n";
}

void writeAction(std::ostream& out, int64_t frame, const Action& a) {
    char b[64];
    out << frame << " " << actionVerb(a.kind);
    auto f = [&](double v) {
        std::snprintf(b, sizeof b, " %.9g", v);
        out << b;
    };
    switch (a.kind) {
        case Action::Kind::Orbit:
        case Action::Kind::Pan: f(a.x), f(a.y); break;
        case Action::Kind::Dolly:
        case Action::Kind::Raise: f(a.x); break;
        case Action::Kind::Sample:
        case Action::Kind::Step:
        case Action::Kind::Threads: f(a.value); break;
        case Action::Kind::Param: out << " " << a.name, f(a.value); break;
        case Action::Kind::Profile: out << " " << a.name; break;
        default: break;
    }
    out << "\n";
}

void writeHash(std::ostream& out, int64_t frame, uint64_t hash) {
    char b[48];
    std::snprintf(b, sizeof b, "%016" PRIx64, hash);
    out << frame << " hash " << b << "\n";
}

void writeEnd(std::ostream& out, int64_t frames) { out << "end " << frames << "\n"; }

Recording readRecording(std::istream& in) {
    Recording r;
    std::string line;
    int lineNo = 0;
    bool sawMagic = false, sawEnd = false;
    auto fail = [&](const std::string& why) {
        throw Error("record line " + std::to_string(lineNo) + " '" + line + "': " + why);
    };
    while (std::getline(in, line)) {
        ++lineNo;
        if (line.empty() || line[0] == '#') continue;
        std::istringstream ls(line);
        std::string first;
        ls >> first;
        if (!sawMagic) {
            int version = 0;
            if (first != "retroglass-view-record" || !(ls >> version) || version != 1)
                fail("expected 'retroglass-view-record 1'");
            sawMagic = true;
            continue;
        }
        if (first == "demo") { ls >> r.demo; continue; }
        if (first == "profile") { ls >> r.profile; continue; }
        if (first == "scene") {
            ls >> r.scene;
            if (r.scene == "-") r.scene.clear();
            continue;
        }
        if (first == "end") {
            if (!(ls >> r.frames)) fail("expected 'end FRAMES'");
            sawEnd = true;
            continue;
        }
        int64_t frame = 0;
        try {
            size_t used = 0;
            frame = std::stoll(first, &used);
            if (used != first.size() || frame < 0) fail("bad frame number");
        } catch (const std::logic_error&) {
            fail("expected a frame number or a header word");
        }
        std::string verb;
        ls >> verb;
        if (verb == "hash") {
            std::string hex;
            ls >> hex;
            if (hex.size() != 16) fail("expected 16 hex digits");
            r.hashes.push_back({frame, std::stoull(hex, nullptr, 16)});
            continue;
        }
        Action a;
        bool ok = true;
        if (verb == "orbit") a.kind = Action::Kind::Orbit, ok = bool(ls >> a.x >> a.y);
        else if (verb == "pan") a.kind = Action::Kind::Pan, ok = bool(ls >> a.x >> a.y);
        else if (verb == "dolly") a.kind = Action::Kind::Dolly, ok = bool(ls >> a.x);
        else if (verb == "raise") a.kind = Action::Kind::Raise, ok = bool(ls >> a.x);
        else if (verb == "reset") a.kind = Action::Kind::Reset;
        else if (verb == "sample") a.kind = Action::Kind::Sample, ok = bool(ls >> a.value);
        else if (verb == "step") a.kind = Action::Kind::Step, ok = bool(ls >> a.value);
        else if (verb == "nearest") a.kind = Action::Kind::Nearest;
        else if (verb == "param") a.kind = Action::Kind::Param, ok = bool(ls >> a.name >> a.value);
        else if (verb == "profile") a.kind = Action::Kind::Profile, ok = bool(ls >> a.name);
        else if (verb == "threads") a.kind = Action::Kind::Threads, ok = bool(ls >> a.value);
        else if (verb == "screenshot") a.kind = Action::Kind::Screenshot;
        else fail("unknown action '" + verb + "'");
        if (!ok) fail("missing or malformed arguments");
        r.actions.push_back({frame, a});
    }
    if (!sawMagic) throw Error("record: empty or not a retroglass-view-record file");
    if (!sawEnd) {
        // A window killed mid-run: replay up to the last frame named.
        for (const auto& e : r.actions) r.frames = std::max(r.frames, e.frame + 1);
        for (const auto& h : r.hashes) r.frames = std::max(r.frames, h.first + 1);
    }
    return r;
}

Recording readRecordingFile(const std::string& path) {
    std::ifstream f(path);
    if (!f) throw Error("cannot open record file '" + path + "'");
    return readRecording(f);
}

}  // namespace rg::viewer
