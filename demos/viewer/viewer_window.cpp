// The viewer's window: SDL2 (software renderer, a streaming texture holding the emulated
// framebuffer 1:1 at the top left) and a Dear ImGui panel to its right.
//
//   ┌──────────────────────────┬───────────────┐
//   │ emulated framebuffer     │ panel: demo,  │
//   │ (or a pass, inspector)   │ params, HUD,  │
//   │                          │ passes, keys  │
//   └──────────────────────────┴───────────────┘
//
// Per frame: events → actions (keys, mouse, gamepad, panel) → ViewerSession::apply →
// render → present. Every applied action is recorded with its frame number (--record), so a
// headless replay reproduces each frame's bytes.
#include <SDL.h>
#include <imgui.h>
#include <backends/imgui_impl_sdl.h>

#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <fstream>
#include <optional>

#include "core/error.h"
#include "core/profile.h"
#include "gamepad_control.h"
#include "imgui_sdl_renderer.h"
#include "view_command.h"

namespace fs = std::filesystem;

namespace rg::viewer {

namespace {

constexpr int kPanelWidth = 440;
constexpr float kKeyOrbitDegrees = 1.0f;   // per frame while held
constexpr float kKeyDolly = 0.97f;
constexpr float kKeyPan = 0.01f;
constexpr float kKeyRaise = 0.01f;

Action act(Action::Kind k, float x = 0, float y = 0, double v = 0, std::string name = {}) {
    Action a;
    a.kind = k, a.x = x, a.y = y, a.value = v, a.name = std::move(name);
    return a;
}

struct Hud {
    std::deque<double> frameMs;   // wall-clock per loop iteration
    double fps() const {
        if (frameMs.empty()) return 0;
        double s = 0;
        for (double v : frameMs) s += v;
        return s > 0 ? 1000.0 * double(frameMs.size()) / s : 0;
    }
};

}  // namespace

void requireDisplay() {
    if (SDL_Init(SDL_INIT_VIDEO) != 0)
        throw Error(std::string("SDL_Init: ") + SDL_GetError() +
                    " (no display? set DISPLAY, or use --replay FILE --headless)");
    // Without a display SDL falls back to its invisible offscreen driver; a window nobody
    // sees would run until killed. Only an explicit SDL_VIDEODRIVER may choose it.
    const char* driver = SDL_GetCurrentVideoDriver();
    const std::string d = driver ? driver : "";
    SDL_Quit();
    if ((d == "offscreen" || d == "dummy") && !SDL_getenv("SDL_VIDEODRIVER"))
        throw Error("no display to open a window on (SDL chose its '" + d +
                    "' driver): set DISPLAY, or replay a recording with --replay FILE --headless");
}

int runWindow(ViewerSession& session, const ViewOptions& o) {
    // ---- window -------------------------------------------------------------------------
    requireDisplay();
    SDL_SetHint(SDL_HINT_RENDER_DRIVER, "software");
    if (SDL_Init(SDL_INIT_VIDEO | SDL_INIT_EVENTS) != 0) throw Error(std::string("SDL_Init: ") + SDL_GetError());
    auto [fbW, fbH] = session.demo().frameSize();
    const int winW = fbW + kPanelWidth, winH = std::max(fbH, 760);
    std::string title = "retroglass view " + session.demo().name() + " — " + session.demo().title();
    SDL_Window* window = SDL_CreateWindow(title.c_str(), SDL_WINDOWPOS_CENTERED, SDL_WINDOWPOS_CENTERED,
                                          winW, winH, SDL_WINDOW_SHOWN);
    if (!window) throw Error(std::string("SDL_CreateWindow: ") + SDL_GetError());
    SDL_Renderer* renderer = SDL_CreateRenderer(window, -1, SDL_RENDERER_SOFTWARE);
    if (!renderer) throw Error(std::string("SDL_CreateRenderer: ") + SDL_GetError());
    // The colour buffer's RGB as a monitor shows it: bytes R, G, B, A in memory read as
    // XBGR8888 (alpha ignored). An alpha format would be blended over the window.
    SDL_Texture* fbTexture = SDL_CreateTexture(renderer, SDL_PIXELFORMAT_XBGR8888,
                                               SDL_TEXTUREACCESS_STREAMING, fbW, fbH);
    SDL_SetTextureBlendMode(fbTexture, SDL_BLENDMODE_NONE);
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;   // nothing hidden in a file: same layout every start
    ImGui::StyleColorsDark();
    ImGui_ImplSDL2_InitForSDLRenderer(window);
    imguiSdlRendererInit(renderer);

    // ---- record / replay ----------------------------------------------------------------
    std::ofstream record;
    if (!o.record.empty()) {
        if (fs::path(o.record).has_parent_path()) fs::create_directories(fs::path(o.record).parent_path());
        record.open(o.record);
        if (!record) throw Error("cannot write record file '" + o.record + "'");
        Recording header;
        header.demo = session.demo().name();
        header.profile = session.profile();
        header.scene = o.scene;
        writeRecordingHeader(record, header);
    }
    std::optional<Recording> replay;
    size_t replayNext = 0;
    if (!o.replay.empty()) replay = readRecordingFile(o.replay);

    GamepadManager gamepad;
    PadBindings padBindings;
    pad::PadState padBefore;
    std::vector<std::string> log;
    auto say = [&](const std::string& s) {
        std::printf("view: %s\n", s.c_str());
        std::fflush(stdout);
        log.push_back(s);
        if (log.size() > 12) log.erase(log.begin());
    };
    say("window " + std::to_string(winW) + "x" + std::to_string(winH) + ", framebuffer " +
        std::to_string(fbW) + "x" + std::to_string(fbH) + " on profile " + session.profile());

    bool running = true, showPanel = true, inspector = false;
    int inspectPass = 0;
    Hud hud;
    int64_t frame = 0;
    auto last = std::chrono::steady_clock::now();
    int mouseButtons = 0;
    std::vector<std::string> profileNames;
    for (const Profile& p : allProfiles()) profileNames.emplace_back(p.name);
    std::string error;

    while (running) {
        std::vector<Action> actions;
        bool screenshot = false, inspectorToggled = false;
        // ---- events -----------------------------------------------------------------------
        SDL_Event e;
        while (SDL_PollEvent(&e)) {
            ImGui_ImplSDL2_ProcessEvent(&e);
            const ImGuiIO& io = ImGui::GetIO();
            if (e.type == SDL_QUIT) running = false;
            if (replay) {
                if (e.type == SDL_KEYDOWN && e.key.keysym.sym == SDLK_ESCAPE) running = false;
                continue;  // a replay in the window takes no other input
            }
            if (e.type == SDL_KEYDOWN && !io.WantCaptureKeyboard) {
                const SDL_Keycode k = e.key.keysym.sym;
                const bool repeat = e.key.repeat != 0;
                switch (k) {
                    case SDLK_ESCAPE: running = false; break;
                    // A press moves one step at once, so a tap between two frames counts.
                    case SDLK_LEFT: if (!repeat) actions.push_back(act(Action::Kind::Orbit, -kKeyOrbitDegrees)); break;
                    case SDLK_RIGHT: if (!repeat) actions.push_back(act(Action::Kind::Orbit, kKeyOrbitDegrees)); break;
                    case SDLK_UP: if (!repeat) actions.push_back(act(Action::Kind::Orbit, 0, kKeyOrbitDegrees)); break;
                    case SDLK_DOWN: if (!repeat) actions.push_back(act(Action::Kind::Orbit, 0, -kKeyOrbitDegrees)); break;
                    case SDLK_HOME:
                    case SDLK_0: actions.push_back(act(Action::Kind::Reset)); break;
                    case SDLK_n: actions.push_back(act(Action::Kind::Nearest)); break;
                    case SDLK_PAGEUP:
                    case SDLK_RIGHTBRACKET: actions.push_back(act(Action::Kind::Step, 0, 0, 1)); break;
                    case SDLK_PAGEDOWN:
                    case SDLK_LEFTBRACKET: actions.push_back(act(Action::Kind::Step, 0, 0, -1)); break;
                    case SDLK_TAB: showPanel = !showPanel; break;
                    case SDLK_F12:
                    case SDLK_p: screenshot = true; break;
                    case SDLK_i:
                        inspector = !inspector;
                        inspectorToggled = true;
                        break;
                    case SDLK_MINUS:
                    case SDLK_KP_MINUS:
                    case SDLK_EQUALS:
                    case SDLK_KP_PLUS:
                        if (auto a = nudgeAction(session.demo().params(),
                                                 k == SDLK_MINUS || k == SDLK_KP_MINUS ? -1 : 1))
                            actions.push_back(*a);
                        break;
                    case SDLK_COMMA: inspectPass = std::max(0, inspectPass - 1); break;
                    case SDLK_PERIOD: ++inspectPass; break;
                    default: break;
                }
            }
            if (e.type == SDL_MOUSEBUTTONDOWN && !io.WantCaptureMouse) mouseButtons |= SDL_BUTTON(e.button.button);
            if (e.type == SDL_MOUSEBUTTONUP) mouseButtons &= ~SDL_BUTTON(e.button.button);
            if (e.type == SDL_MOUSEMOTION && mouseButtons && !io.WantCaptureMouse) {
                const float dx = float(e.motion.xrel), dy = float(e.motion.yrel);
                const bool shift = SDL_GetModState() & KMOD_SHIFT;
                if ((mouseButtons & SDL_BUTTON_MMASK) || ((mouseButtons & SDL_BUTTON_LMASK) && shift))
                    actions.push_back(act(Action::Kind::Pan, -dx * 0.002f, dy * 0.002f));
                else if (mouseButtons & SDL_BUTTON_LMASK)
                    actions.push_back(act(Action::Kind::Orbit, dx * 0.3f, dy * 0.3f));
                else if (mouseButtons & SDL_BUTTON_RMASK)
                    actions.push_back(act(Action::Kind::Dolly, std::pow(1.005f, dy)));
            }
            if (e.type == SDL_MOUSEWHEEL && !io.WantCaptureMouse && e.wheel.y != 0)
                actions.push_back(act(Action::Kind::Dolly, std::pow(0.9f, float(e.wheel.y))));
        }
        // ---- held keys --------------------------------------------------------------------
        if (!replay && !ImGui::GetIO().WantCaptureKeyboard) {
            const Uint8* keys = SDL_GetKeyboardState(nullptr);
            auto held = [&](SDL_Scancode s) { return keys[s] != 0; };
            float daz = 0, del = 0;
            if (held(SDL_SCANCODE_LEFT)) daz -= kKeyOrbitDegrees;
            if (held(SDL_SCANCODE_RIGHT)) daz += kKeyOrbitDegrees;
            if (held(SDL_SCANCODE_UP)) del += kKeyOrbitDegrees;
            if (held(SDL_SCANCODE_DOWN)) del -= kKeyOrbitDegrees;
            // The first frame of a press already stepped in the event loop.
            bool pressedNow = false;
            for (const Action& a : actions) pressedNow |= a.kind == Action::Kind::Orbit;
            if ((daz != 0 || del != 0) && !pressedNow) actions.push_back(act(Action::Kind::Orbit, daz, del));
            if (held(SDL_SCANCODE_W)) actions.push_back(act(Action::Kind::Dolly, kKeyDolly));
            if (held(SDL_SCANCODE_S)) actions.push_back(act(Action::Kind::Dolly, 1.0f / kKeyDolly));
            float px = 0, py = 0;
            if (held(SDL_SCANCODE_A)) px -= kKeyPan;
            if (held(SDL_SCANCODE_D)) px += kKeyPan;
            if (held(SDL_SCANCODE_Q)) py -= kKeyPan;
            if (held(SDL_SCANCODE_E)) py += kKeyPan;
            if (px != 0 || py != 0) actions.push_back(act(Action::Kind::Pan, px, py));
            if (held(SDL_SCANCODE_R)) actions.push_back(act(Action::Kind::Raise, kKeyRaise));
            if (held(SDL_SCANCODE_F)) actions.push_back(act(Action::Kind::Raise, -kKeyRaise));
        }
        // ---- gamepad ----------------------------------------------------------------------
        if (auto s = gamepad.poll(); s && !replay) {
            for (Action& a : padActions(*s, padBefore, padBindings)) {
                if (a.kind == Action::Kind::Screenshot) screenshot = true;
                else actions.push_back(std::move(a));
            }
            if (const int n = padNudge(*s, padBefore); n != 0)
                if (auto a = nudgeAction(session.demo().params(), n)) actions.push_back(*a);
            padBefore = *s;
        }
        for (const std::string& m : gamepad.takeMessages()) say(m);

        // ---- panel ------------------------------------------------------------------------
        ImGui_ImplSDL2_NewFrame();
        ImGui::NewFrame();
        if (showPanel) {
            ImGui::SetNextWindowPos(ImVec2(float(fbW), 0));
            ImGui::SetNextWindowSize(ImVec2(float(kPanelWidth), float(winH)));
            ImGui::Begin("retroglass", nullptr,
                         ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
            Demo& demo = session.demo();
            ImGui::TextWrapped("%s", demo.title().c_str());
            if (ImGui::CollapsingHeader("Demo", ImGuiTreeNodeFlags_DefaultOpen) && !replay) {
                for (Param& p : demo.params()) {
                    double v = p.value;
                    switch (p.kind) {
                        case Param::Kind::Bool: {
                            bool b = v != 0;
                            if (ImGui::Checkbox(p.label.c_str(), &b)) v = b ? 1 : 0;
                            break;
                        }
                        case Param::Kind::Int: {
                            int i = int(v);
                            if (ImGui::SliderInt(p.label.c_str(), &i, int(p.min), int(p.max))) v = i;
                            break;
                        }
                        case Param::Kind::Float: {
                            float f = float(v);
                            if (ImGui::SliderFloat(p.label.c_str(), &f, float(p.min), float(p.max))) v = f;
                            break;
                        }
                        case Param::Kind::Enum: {
                            int i = int(v);
                            if (ImGui::BeginCombo(p.label.c_str(), p.choices.at(size_t(i)).c_str())) {
                                for (size_t c = 0; c < p.choices.size(); ++c)
                                    if (ImGui::Selectable(p.choices[c].c_str(), int(c) == i)) v = double(c);
                                ImGui::EndCombo();
                            }
                            break;
                        }
                    }
                    if (ImGui::IsItemHovered() && !p.help.empty()) ImGui::SetTooltip("%s", p.help.c_str());
                    if (v != p.value) actions.push_back(act(Action::Kind::Param, 0, 0, v, p.name));
                }
                // profile and threads
                if (ImGui::BeginCombo("profile", session.profile().c_str())) {
                    for (const std::string& n : profileNames)
                        if (ImGui::Selectable(n.c_str(), n == session.profile()))
                            actions.push_back(act(Action::Kind::Profile, 0, 0, 0, n));
                    ImGui::EndCombo();
                }
                int threads = session.threads();
                if (ImGui::SliderInt("threads (0 = all)", &threads, 0, 64))
                    actions.push_back(act(Action::Kind::Threads, 0, 0, threads));
                const auto& samples = session.samples();
                if (!samples.empty()) {
                    ImGui::Text("viewpoint samples (%zu):", samples.size());
                    for (size_t i = 0; i < samples.size(); ++i) {
                        if (i % 10) ImGui::SameLine();
                        if (ImGui::SmallButton(std::to_string(i).c_str()))
                            actions.push_back(act(Action::Kind::Sample, 0, 0, double(i)));
                    }
                }
                if (ImGui::Button("reset camera")) actions.push_back(act(Action::Kind::Reset));
                ImGui::SameLine();
                if (ImGui::Button("nearest sample")) actions.push_back(act(Action::Kind::Nearest));
                ImGui::SameLine();
                if (ImGui::Button("screenshot")) screenshot = true;
            }
            if (inspectorToggled) ImGui::SetNextItemOpen(inspector, ImGuiCond_Always);
            if (ImGui::CollapsingHeader("Pass inspector")) {
                ImGui::Checkbox("inspect passes (I)", &inspector);
                const auto& snaps = session.passSnapshots();
                if (inspector && !snaps.empty()) {
                    inspectPass = std::clamp(inspectPass, 0, int(snaps.size()) - 1);
                    int shown = inspectPass + 1;
                    if (ImGui::SliderInt("after pass", &shown, 1, int(snaps.size()))) inspectPass = shown - 1;
                    const PassSnapshot& s = snaps[size_t(inspectPass)];
                    ImGui::TextWrapped("%s (%" PRIu64 " draws)", s.record.label.c_str(), s.record.drawCalls);
                    if (!s.range.empty()) ImGui::Text("shown range %s", s.range.c_str());
                    // The value under the mouse, in the target's own texels.
                    int mx = 0, my = 0;
                    SDL_GetMouseState(&mx, &my);
                    if (mx >= 0 && my >= 0 && mx < fbW && my < fbH) {
                        if (!s.image.values.empty()) {
                            const int tx = mx * s.image.width / fbW, ty = my * s.image.height / fbH;
                            const glm::vec4 v = s.image.values[size_t(ty) * size_t(s.image.width) + size_t(tx)];
                            ImGui::Text("texel (%d, %d) = (%.5g, %.5g, %.5g, %.5g)", tx, ty, v.x, v.y, v.z, v.w);
                        } else {
                            const Rgba8 c = s.color[size_t(my) * size_t(fbW) + size_t(mx)];
                            ImGui::Text("pixel (%d, %d) = (%d, %d, %d, %d)", mx, my, c.r, c.g, c.b, c.a);
                        }
                    }
                    ImGui::PushTextWrapPos(0.0f);
                    ImGui::TextUnformatted(s.state.c_str());
                    ImGui::PopTextWrapPos();
                }
                for (const std::string& d : session.demo().passDescriptions()) ImGui::TextWrapped("- %s", d.c_str());
            }
            if (ImGui::CollapsingHeader("HUD", ImGuiTreeNodeFlags_DefaultOpen)) {
                ImGui::Text("frame %" PRId64 "   %.1f FPS   emulated frame %.2f ms", frame, hud.fps(),
                            session.frameMs());
                const OrbitCamera& c = session.camera();
                ray::Camera rc = c.camera();
                ImGui::Text("camera az %.2f° el %.2f° dist %.3f fov %.1f°", c.azimuthDegrees,
                            c.elevationDegrees, c.distance, c.fovYDegrees);
                ImGui::Text("eye (%.3f, %.3f, %.3f) target (%.3f, %.3f, %.3f)", rc.eye.x, rc.eye.y,
                            rc.eye.z, rc.target.x, rc.target.y, rc.target.z);
                ImGui::Text("profile %s, %dx%d, threads %d", session.profile().c_str(), fbW, fbH,
                            session.threads());
                for (const auto& [k, v] : session.notes()) ImGui::Text("%s: %s", k.c_str(), v.c_str());
                ImGui::Separator();
                const auto& passes = session.device().passes();
                ImGui::Text("passes: %zu", passes.size());
                for (size_t i = 0; i < passes.size(); ++i)
                    ImGui::BulletText("%zu %s (%" PRIu64 " draws)", i + 1, passes[i].label.c_str(),
                                      passes[i].drawCalls);
                ImGui::Separator();
                ImGui::TextUnformatted(session.device().counters().toString().c_str());
                ImGui::Text("gamepad: %s", gamepad.status().c_str());
                if (!o.record.empty()) ImGui::Text("recording to %s", o.record.c_str());
                if (replay) ImGui::Text("replaying %s", o.replay.c_str());
            }
            if (ImGui::CollapsingHeader("Bindings")) {
                for (const auto& [k, v] : keyBindings()) ImGui::BulletText("%s: %s", k.c_str(), v.c_str());
            }
            if (!error.empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", error.c_str());
            for (const std::string& m : log) ImGui::TextWrapped("%s", m.c_str());
            ImGui::End();
        }
        ImGui::Render();

        // ---- replayed input ---------------------------------------------------------------
        if (replay) {
            actions.clear();
            for (; replayNext < replay->actions.size() && replay->actions[replayNext].frame <= frame; ++replayNext) {
                const Action& a = replay->actions[replayNext].action;
                if (a.kind == Action::Kind::Screenshot) screenshot = true;
                else actions.push_back(a);
            }
            if (frame + 1 >= replay->frames) running = false;
        }

        // ---- apply, record, render ------------------------------------------------------------
        if (screenshot) actions.push_back(act(Action::Kind::Screenshot));
        for (const Action& a : actions) {
            try {
                session.apply(a);
                error.clear();
                if (record.is_open()) writeAction(record, frame, a);
            } catch (const Error& ex) {
                error = std::string("refused: ") + ex.what();
                say(error);
            }
        }
        session.render(inspector);
        if (record.is_open()) writeHash(record, frame, session.frameHash());

        // ---- present ----------------------------------------------------------------------
        const raster::Framebuffer& fb = session.device().framebuffer();
        const Rgba8* shown = fb.color().data();
        const auto& snaps = session.passSnapshots();
        if (inspector && !snaps.empty())
            shown = snaps[size_t(std::clamp(inspectPass, 0, int(snaps.size()) - 1))].color.data();
        SDL_UpdateTexture(fbTexture, nullptr, shown, fbW * 4);
        SDL_SetRenderDrawColor(renderer, 24, 24, 28, 255);
        SDL_RenderClear(renderer);
        SDL_Rect dst{0, 0, fbW, fbH};
        SDL_RenderCopy(renderer, fbTexture, nullptr, &dst);
        imguiSdlRendererDraw(ImGui::GetDrawData());
        if (screenshot) {
            char base[96];
            std::snprintf(base, sizeof base, "%s_%05" PRId64, session.demo().name().c_str(), frame);
            fs::path dir(o.shots);
            writeFramebufferPng((dir / (std::string(base) + ".png")).string(), fb);
            std::vector<Rgba8> win(size_t(winW) * size_t(winH));
            if (SDL_RenderReadPixels(renderer, nullptr, SDL_PIXELFORMAT_RGBA32, win.data(), winW * 4) == 0)
                writePixelsPng((dir / (std::string(base) + "_window.png")).string(), winW, winH, win);
            say("screenshot " + (dir / (std::string(base) + ".png")).string() + " (+ _window.png)");
        }
        SDL_RenderPresent(renderer);

        auto now = std::chrono::steady_clock::now();
        hud.frameMs.push_back(std::chrono::duration<double, std::milli>(now - last).count());
        if (hud.frameMs.size() > 30) hud.frameMs.pop_front();
        last = now;
        ++frame;
        if (o.maxFrames > 0 && frame >= o.maxFrames) running = false;
    }
    if (record.is_open()) {
        writeEnd(record, frame);
        say("recorded " + std::to_string(frame) + " frames to " + o.record);
    }
    imguiSdlRendererShutdown();
    ImGui_ImplSDL2_Shutdown();
    ImGui::DestroyContext();
    SDL_DestroyTexture(fbTexture);
    SDL_DestroyRenderer(renderer);
    SDL_DestroyWindow(window);
    SDL_Quit();
    return 0;
}

}  // namespace rg::viewer
