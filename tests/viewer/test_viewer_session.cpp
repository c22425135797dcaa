// The viewer's parts that need no window: the record format, the orbit camera, the PEM
// demo's choice of samples, and the gamepad-to-action mapping.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "core/error.h"
#include "gamepad_control.h"
#include "orbit_camera.h"
#include "pem_demo.h"
#include "viewer_session.h"

using namespace rg::viewer;

TEST(ViewerRecord, RoundTripKeepsEveryActionAndFloatBits) {
    Recording r;
    r.demo = "pem";
    r.profile = "geforce256";
    r.scene = "";
    std::vector<Action> actions = {
        {Action::Kind::Orbit, 0.1f, -1.0f / 3.0f, 0, ""},
        {Action::Kind::Dolly, 0.97f, 0, 0, ""},
        {Action::Kind::Pan, 1e-7f, 12345.678f, 0, ""},
        {Action::Kind::Raise, -0.01f, 0, 0, ""},
        {Action::Kind::Reset, 0, 0, 0, ""},
        {Action::Kind::Sample, 0, 0, 5, ""},
        {Action::Kind::Step, 0, 0, -1, ""},
        {Action::Kind::Nearest, 0, 0, 0, ""},
        {Action::Kind::Param, 0, 0, 2, "em"},
        {Action::Kind::Profile, 0, 0, 0, "geforce8800"},
        {Action::Kind::Threads, 0, 0, 3, ""},
        {Action::Kind::Screenshot, 0, 0, 0, ""},
    };
    std::stringstream s;
    writeRecordingHeader(s, r);
    for (size_t i = 0; i < actions.size(); ++i) writeAction(s, int64_t(i / 2), actions[i]);
    writeHash(s, 3, 0x0123456789abcdefull);
    writeEnd(s, 7);
    Recording back = readRecording(s);
    EXPECT_EQ(back.demo, "pem");
    EXPECT_EQ(back.profile, "geforce256");
    EXPECT_EQ(back.scene, "");
    EXPECT_EQ(back.frames, 7);
    ASSERT_EQ(back.actions.size(), actions.size());
    for (size_t i = 0; i < actions.size(); ++i) {
        EXPECT_EQ(back.actions[i].frame, int64_t(i / 2));
        EXPECT_EQ(back.actions[i].action, actions[i]) << i;
    }
    ASSERT_EQ(back.hashes.size(), 1u);
    EXPECT_EQ(back.hashes[0].second, 0x0123456789abcdefull);
}

TEST(ViewerRecord, MalformedLinesNameTheLine) {
    auto parse = [](const std::string& text) {
        std::istringstream in(text);
        return readRecording(in);
    };
    const std::string head = "retroglass-view-record 1\ndemo pem\nprofile geforce256\n";
    EXPECT_THROW(parse(""), rg::Error);
    EXPECT_THROW(parse("retroglass-view-record 2\n"), rg::Error);
    EXPECT_THROW(parse(head + "3 fly 1 2\n"), rg::Error);
    EXPECT_THROW(parse(head + "3 orbit 1\n"), rg::Error);
    EXPECT_THROW(parse(head + "-1 reset\n"), rg::Error);
    EXPECT_THROW(parse(head + "x reset\n"), rg::Error);
    EXPECT_THROW(parse(head + "3 hash 12\n"), rg::Error);
    try {
        parse(head + "0 reset\n5 orbit one two\n");
        FAIL();
    } catch (const rg::Error& e) {
        EXPECT_NE(std::string(e.what()).find("line 5"), std::string::npos) << e.what();
    }
    // No end line (a window that was killed): the frames named so far.
    Recording r = parse(head + "4 reset\n9 hash 0000000000000001\n");
    EXPECT_EQ(r.frames, 10);
}

TEST(ViewerOrbitCamera, ReachesCameraOnCircleExactlyEnough) {
    for (float angle : {0.0f, 14.0f, 90.0f, 200.0f, -45.0f}) {
        rg::ray::Camera c = rg::ray::cameraOnCircle({0, 1.5f, 0}, 8.0f, 2.5f, angle, 40.0f);
        OrbitCamera o = OrbitCamera::fromCamera(c);
        rg::ray::Camera back = o.camera();
        EXPECT_NEAR(glm::length(back.eye - c.eye), 0.0f, 1e-4f) << angle;
        EXPECT_EQ(back.target, c.target);
    }
}

TEST(ViewerOrbitCamera, ControlsStayInRange) {
    OrbitCamera o;
    o.distance = 5;
    o.orbit(0, 200);
    EXPECT_LE(o.elevationDegrees, 89.0f);
    o.dolly(100, 1, 10);
    EXPECT_EQ(o.distance, 10.0f);
    o.dolly(1e-6f, 1, 10);
    EXPECT_EQ(o.distance, 1.0f);
    o.orbit(720.5f, 0);
    EXPECT_LE(std::abs(o.azimuthDegrees), 180.0f);
    OrbitCamera p = o;
    p.pan(0.1f, 0.0f);
    EXPECT_NEAR(glm::length(p.target - o.target), 0.1f * o.distance, 1e-4f);
    float eyeY = o.camera().eye.y;
    o.raise(0.1f);
    EXPECT_NEAR(o.camera().eye.y, eyeY + 0.1f, 1e-3f);
}

TEST(ViewerPemSamples, BlendWeightFromAngle) {
    rg::ray::ViewpointPath path;
    path.startDegrees = 10.0f;
    path.stepDegrees = 4.0f;
    path.count = 8;
    auto b = rg::pem::blendForAngle(path, 10.0f, true);   // on sample 0
    EXPECT_EQ(b.a, 0);
    EXPECT_EQ(b.b, 0);
    b = rg::pem::blendForAngle(path, 15.0f, true);        // a quarter past sample 1
    EXPECT_EQ(b.a, 1);
    EXPECT_EQ(b.b, 2);
    EXPECT_FLOAT_EQ(b.w, 0.25f);
    b = rg::pem::blendForAngle(path, 15.0f, false);       // nearest alone
    EXPECT_EQ(b.a, 1);
    EXPECT_EQ(b.b, 1);
    b = rg::pem::blendForAngle(path, 17.0f, false);
    EXPECT_EQ(b.a, 2);
    b = rg::pem::blendForAngle(path, 1000.0f, true);      // past the end: the last sample
    EXPECT_EQ(b.a, 7);
    EXPECT_EQ(b.b, 7);
    b = rg::pem::blendForAngle(path, 13.99999f, true);    // weight rounds to TFACTOR 255
    EXPECT_EQ(b.a, 1);
    EXPECT_EQ(b.b, 1);
    rg::ray::Camera c = rg::ray::cameraOnCircle(path.center, path.radius, path.height, 18.5f);
    EXPECT_NEAR(rg::pem::angleOnPath(path, c), 18.5f, 1e-3f);
    c = rg::ray::cameraOnCircle(path.center, path.radius, path.height, 18.5f + 360.0f);
    EXPECT_NEAR(rg::pem::angleOnPath(path, c), 18.5f, 1e-3f);
}

TEST(ViewerGamepadActions, SticksAndButtonEdges) {
    PadBindings b;
    rg::viewer::pad::PadState idle, s;
    EXPECT_TRUE(padActions(idle, idle, b).empty());
    s.lx = 1.0f;                                // full right: orbit at full rate
    auto a = padActions(s, idle, b);
    ASSERT_EQ(a.size(), 1u);
    EXPECT_EQ(a[0].kind, Action::Kind::Orbit);
    EXPECT_FLOAT_EQ(a[0].x, b.orbitDegreesPerFrame);
    s = idle;
    s.lx = 0.05f;                               // inside the dead zone
    EXPECT_TRUE(padActions(s, idle, b).empty());
    s = idle;
    s.buttons = rg::viewer::pad::R1;
    a = padActions(s, idle, b);
    ASSERT_EQ(a.size(), 1u);
    EXPECT_EQ(a[0].kind, Action::Kind::Step);
    EXPECT_EQ(a[0].value, 1);
    EXPECT_TRUE(padActions(s, s, b).empty());   // held: one step only
    s.buttons = rg::viewer::pad::South;
    a = padActions(s, idle, b);
    ASSERT_EQ(a.size(), 1u);
    EXPECT_EQ(a[0].kind, Action::Kind::Screenshot);
    s = idle;
    s.ry = 1.0f, s.rx = -1.0f;
    a = padActions(s, idle, b);
    ASSERT_EQ(a.size(), 2u);
    EXPECT_EQ(a[0].kind, Action::Kind::Dolly);
    EXPECT_LT(a[0].x, 1.0f);                    // pushed forward: closer
    EXPECT_EQ(a[1].kind, Action::Kind::Raise);
    EXPECT_LT(a[1].x, 0.0f);
}

// ---- a demo that is not PEM: the viewer session drives it unchanged ------------------------

namespace {

// Two passes: a flat triangle, then the same triangle added over itself (ONE/ONE) when
// `double` is on. Its colour is the `red` parameter.
class TwoPassDemo final : public Demo {
  public:
    TwoPassDemo() {
        Param red;
        red.name = "red";
        red.label = "red";
        red.kind = Param::Kind::Int;
        red.min = 0, red.max = 255, red.value = 100;
        Param twice;
        twice.name = "double";
        twice.label = "add twice";
        twice.kind = Param::Kind::Bool;
        twice.value = 1;
        params_ = {red, twice};
    }
    std::string name() const override { return "twopass"; }
    std::string title() const override { return "a test demo"; }
    std::string defaultProfile() const override { return "geforce256"; }
    std::pair<int, int> frameSize() const override { return {64, 48}; }
    OrbitRig rig() const override {
        OrbitRig r;
        r.start = rg::ray::cameraOnCircle({0, 0, 0}, 5, 1, 30);
        return r;
    }
    std::vector<ViewpointSample> viewpointSamples() const override {
        return {{"a", rg::ray::cameraOnCircle({0, 0, 0}, 5, 1, 0)},
                {"b", rg::ray::cameraOnCircle({0, 0, 0}, 5, 1, 90)}};
    }
    std::vector<Param>& params() override { return params_; }
    std::vector<std::string> passDescriptions() const override { return {"flat", "added"}; }
    FrameNotes render(rg::raster::Device& d, const rg::ray::Camera& camera) override {
        using namespace rg::raster;
        // The camera's azimuth moves the triangle, so camera actions change the bytes.
        float shift = std::fmod(std::abs(camera.eye.x), 10.0f);
        d.beginFrame();
        d.clear(true, {0, 0, 0, 255}, true, 1.0f);
        std::vector<Vertex> v(3);
        v[0].position = {4 + shift, 4, 0.5f, 1};
        v[1].position = {60, 8, 0.5f, 1};
        v[2].position = {10, 44, 0.5f, 1};
        for (auto& x : v) x.diffuse = {uint8_t(paramValue(params_, "red")), 20, 30, 255};
        PipelineState s;
        s.cull = CullMode::None;
        s.depthTest = 0;
        d.setState(s);
        d.beginPass("flat");
        d.draw(Primitive::TriangleList, VertexSpace::Pretransformed, v);
        if (paramValue(params_, "double") != 0) {
            d.beginPass("added");
            s.blend = 1;
            s.srcBlend = BlendFactor::One;
            s.dstBlend = BlendFactor::One;
            d.setState(s);
            d.draw(Primitive::TriangleList, VertexSpace::Pretransformed, v);
        }
        d.endFrame();
        return {{"shift", std::to_string(shift)}};
    }

  private:
    std::vector<Param> params_;
};

}  // namespace

TEST(ViewerSessionAnyDemo, PassSnapshotsCarryTheStateThatDrewThem) {
    ViewerSession s(std::make_unique<TwoPassDemo>(), "", 1);
    s.render(true);
    const auto& snaps = s.passSnapshots();
    ASSERT_EQ(snaps.size(), 2u);
    EXPECT_EQ(snaps[0].record.label, "flat");
    EXPECT_NE(snaps[0].state.find("blend off"), std::string::npos) << snaps[0].state;
    EXPECT_NE(snaps[1].state.find("blend ONE / ONE"), std::string::npos) << snaps[1].state;
    EXPECT_NE(snaps[1].state.find("profile geforce256"), std::string::npos);
    // After pass 1 the triangle is red 100; after pass 2, 200 (the final frame).
    const auto& fb = s.device().framebuffer();
    EXPECT_EQ(snaps[0].color[size_t(20 * 64 + 20)].r, 100);
    EXPECT_EQ(snaps[1].color[size_t(20 * 64 + 20)].r, 200);
    EXPECT_EQ(fb.pixel(20, 20).r, 200);
    s.render(false);
    EXPECT_TRUE(s.passSnapshots().empty());
}

TEST(ViewerSessionAnyDemo, SameActionsSameBytesAnyThreadCount) {
    std::vector<Action> actions = {{Action::Kind::Orbit, 12.5f, 3, 0, ""},
                                   {Action::Kind::Param, 0, 0, 77, "red"},
                                   {Action::Kind::Step, 0, 0, 1, ""},
                                   {Action::Kind::Dolly, 0.8f, 0, 0, ""}};
    ViewerSession a(std::make_unique<TwoPassDemo>(), "", 1);
    ViewerSession b(std::make_unique<TwoPassDemo>(), "", 4);
    a.render(false);
    const uint64_t first = a.frameHash();
    for (const Action& x : actions) a.apply(x), b.apply(x);
    b.apply({Action::Kind::Threads, 0, 0, 2, ""});
    a.render(false);
    b.render(true);
    EXPECT_EQ(a.frameHash(), b.frameHash());
    EXPECT_NE(a.frameHash(), first);
    EXPECT_EQ(a.device().framebuffer().pixel(20, 20).r, 154);
    // Unknown parameters and profiles are refused; the session stays usable.
    EXPECT_THROW(a.apply({Action::Kind::Param, 0, 0, 1, "nope"}), rg::Error);
    EXPECT_ANY_THROW(a.apply({Action::Kind::Profile, 0, 0, 0, "no-such-machine"}));
    EXPECT_EQ(a.profile(), "geforce256");
    a.render(false);
    EXPECT_EQ(a.frameHash(), b.frameHash());
}

TEST(ViewerSessionAnyDemo, StepAndNearestReachTheSamples) {
    ViewerSession s(std::make_unique<TwoPassDemo>(), "", 1);
    s.apply({Action::Kind::Sample, 0, 0, 1, ""});
    EXPECT_EQ(s.nearestSample(), 1);
    EXPECT_NEAR(s.camera().azimuthDegrees, 90.0f, 1e-3f);
    s.apply({Action::Kind::Step, 0, 0, 1, ""});      // wraps to 0
    EXPECT_EQ(s.nearestSample(), 0);
    s.apply({Action::Kind::Orbit, 80, 0, 0, ""});
    s.apply({Action::Kind::Nearest, 0, 0, 0, ""});
    EXPECT_NEAR(s.camera().azimuthDegrees, 90.0f, 1e-3f);
    s.apply({Action::Kind::Reset, 0, 0, 0, ""});
    EXPECT_NEAR(s.camera().azimuthDegrees, 30.0f, 1e-3f);
}

// The programmable profile in the viewer: the tir demo draws its passes on its own
// geforce8800 device and hands the frame over by drawPixels.
#include "tir_demo.h"

TEST(ViewerProgrammable, TheTirFrameIsHandedOverAsItIsAndItsMapsAreInspected) {
    rg::viewer::DemoOptions o;
    o.scene = "prism";
    o.threads = 2;
    auto demo = std::make_unique<rg::tir::TirDemo>(o);
    rg::tir::TirDemo* tir = demo.get();
    ViewerSession s(std::move(demo), "", 2);
    EXPECT_EQ(s.profile(), "geforce8800");
    s.apply({Action::Kind::Param, 0, 0, 2, "bounces"});
    s.render(true);
    // The framebuffer holds the programmable frame byte for byte: the same settings on a
    // renderer of its own give the same bytes.
    rg::tir::TirScene scene = rg::tir::makeTirScene("prism");
    rg::tir::TirRenderer r(scene, 1);
    r.render(s.camera().camera(), tir->settings());
    const rg::Rgba8* px = const_cast<rg::tex::Texture&>(r.frameTexture()).renderData8(0, 0);
    const auto& fb = s.device().framebuffer();
    int differ = 0;
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x) {
            const rg::Rgba8 a = fb.pixel(x, y), b = px[size_t(y) * size_t(fb.width()) + size_t(x)];
            differ += (a.r != b.r || a.g != b.g || a.b != b.b || a.a != b.a) ? 1 : 0;
        }
    EXPECT_EQ(differ, 0);
    // The inspector: both maps of passes 1–3 and the frame, then the hand-over pass.
    const auto& snaps = s.passSnapshots();
    ASSERT_EQ(snaps.size(), 8u);
    EXPECT_NE(snaps[0].record.label.find("back faces"), std::string::npos) << snaps[0].record.label;
    EXPECT_EQ(snaps[0].image.kind, TargetImage::Kind::Normal);
    EXPECT_EQ(snaps[1].image.kind, TargetImage::Kind::Depth);
    EXPECT_FALSE(snaps[1].range.empty());  // the depth range shown
    EXPECT_EQ(snaps[4].image.kind, TargetImage::Kind::Float);
    EXPECT_FALSE(snaps[4].range.empty());
    EXPECT_EQ(snaps[6].image.kind, TargetImage::Kind::Color8);
    for (const auto& sn : snaps) EXPECT_EQ(sn.color.size(), size_t(fb.width()) * size_t(fb.height()));
    // A back-face texel's value is the map's: a unit normal facing away from the eye.
    const auto& n = snaps[0].image;
    int normals = 0;
    for (const glm::vec4& v : n.values)
        if (v.x != 0 || v.y != 0 || v.z != 0) {
            ++normals;
            EXPECT_NEAR(glm::length(glm::vec3(v)), 1.0f, 2e-3f);
        }
    EXPECT_GT(normals, 1000);
    // Parameters change the frame; another profile is refused with the reason.
    const uint64_t two = s.frameHash();
    s.apply({Action::Kind::Param, 0, 0, 0, "bounces"});
    s.render(false);
    EXPECT_NE(s.frameHash(), two);
    EXPECT_TRUE(s.passSnapshots().empty());
    try {
        s.apply({Action::Kind::Profile, 0, 0, 0, "geforce256"});
        FAIL() << "tir cannot run on a GeForce 256";
    } catch (const rg::Error& e) {
        EXPECT_NE(std::string(e.what()).find("geforce8800"), std::string::npos) << e.what();
    }
    EXPECT_EQ(s.profile(), "geforce8800");
}

// Dancsik & Minarik in the viewer: the impostors demo's frame is handed over as it is, the
// mode, DEPTH and the mover's place are live, its maps are inspected, and only geforce8800
// runs it.
#include "impostor_demo.h"

TEST(ViewerProgrammable, TheImpostorFrameIsHandedOverAsItIsAndTheMoverMovesLive) {
    rg::viewer::DemoOptions o;
    o.scene = "mirror-sphere";  // the sphere moves (a clear cube in a white world would look the same anywhere)
    o.threads = 2;
    auto demo = std::make_unique<rg::impostors::ImpostorDemo>(o);
    rg::impostors::ImpostorDemo* imp = demo.get();
    ViewerSession s(std::move(demo), "", 2);
    EXPECT_EQ(s.profile(), "geforce8800");
    s.apply({Action::Kind::Param, 0, 0, 0, "env_size"});  // 64²: a short test
    s.apply({Action::Kind::Param, 0, 0, 1, "depth"});
    s.render(true);
    // The framebuffer holds the programmable frame byte for byte: the same settings on a
    // renderer of its own give the same bytes.
    const rg::impostors::ImpostorScene scene = rg::impostors::impostorSceneFromFile("mirror-sphere");
    rg::impostors::ImpostorRenderer r(scene, 1);
    r.render(s.camera().camera(), imp->settings());
    const rg::Rgba8* px = const_cast<rg::tex::Texture&>(r.frameTexture()).renderData8(0, 0);
    const auto& fb = s.device().framebuffer();
    ASSERT_EQ(fb.width(), 600);
    int differ = 0;
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x) {
            const rg::Rgba8 a = fb.pixel(x, y), b = px[size_t(y) * size_t(fb.width()) + size_t(x)];
            differ += (a.r != b.r || a.g != b.g || a.b != b.b || a.a != b.a) ? 1 : 0;
        }
    EXPECT_EQ(differ, 0);
    // The inspector: the maps of the frame, then the hand-over pass; the mover's distance
    // impostor holds distances (the room's walls around the sphere).
    const auto& snaps = s.passSnapshots();
    ASSERT_GE(snaps.size(), 4u);
    int distances = 0;
    std::string labels;
    for (const auto& sn : snaps) {
        EXPECT_EQ(sn.color.size(), size_t(fb.width()) * size_t(fb.height()));
        labels += sn.record.label + "; ";
        if (sn.record.label.find("distance") != std::string::npos && sn.image.kind == TargetImage::Kind::Depth)
            for (const glm::vec4& v : sn.image.values) distances += v.x > 0.0f ? 1 : 0;
    }
    EXPECT_GT(distances, 1000) << labels;
    // The mover's place and the mode change the frame; the settings follow the parameters.
    const uint64_t first = s.frameHash();
    s.apply({Action::Kind::Param, 0, 0, 1.0, "mover"});
    s.render(false);
    EXPECT_EQ(imp->settings().moverU, 1.0f);
    EXPECT_NE(s.frameHash(), first);
    // - steps the moving piece back a twentieth of its path (its only Float parameter).
    const auto back = rg::viewer::nudgeAction(imp->params(), -1);
    ASSERT_TRUE(back.has_value());
    EXPECT_EQ(back->name, "mover");
    s.apply(*back);
    EXPECT_FLOAT_EQ(imp->settings().moverU, 0.95f);
    s.apply({Action::Kind::Param, 0, 0, 1, "mode"});
    EXPECT_EQ(imp->settings().mode, rg::impostors::Mode::Classical);
    // §7's caustics switch on live. This scene (a mirror sphere) has no board, a diffuse
    // object under the glass: no photon lands anywhere, and the frame keeps its bytes.
    EXPECT_FALSE(imp->settings().caustics);
    s.render(false);
    const uint64_t noCaustics = s.frameHash();
    s.apply({Action::Kind::Param, 0, 0, 1, "caustics"});
    EXPECT_TRUE(imp->settings().caustics);
    s.render(false);
    EXPECT_EQ(s.frameHash(), noCaustics);
    // Combinations the demo cannot draw are refused at the edit, naming why, and the old
    // value stays, so the next frame draws: mode A (refractor maps only) without a board, and
    // the height-map exit in mode A.
    auto refused = [&](const char* param, double value, const char* why) {
        try {
            s.apply({Action::Kind::Param, 0, 0, value, param});
            ADD_FAILURE() << param << " = " << value << " was taken";
        } catch (const rg::Error& e) {
            EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
        }
    };
    refused("mode", 3, "mode A needs a board");
    EXPECT_EQ(imp->settings().mode, rg::impostors::Mode::Classical);
    s.apply({Action::Kind::Param, 0, 0, 1, "exit"});
    EXPECT_EQ(imp->settings().exit, rg::impostors::Exit::HeightMap);
    refused("mode", 3, "mode A");
    EXPECT_EQ(imp->settings().mode, rg::impostors::Mode::Classical);
    s.render(false);  // the frame still draws
    s.apply({Action::Kind::Param, 0, 0, 0, "exit"});
    try {
        s.apply({Action::Kind::Profile, 0, 0, 0, "geforce256"});
        FAIL() << "impostors cannot run on a GeForce 256";
    } catch (const rg::Error& e) {
        EXPECT_NE(std::string(e.what()).find("geforce8800"), std::string::npos) << e.what();
    }
    EXPECT_EQ(s.profile(), "geforce8800");
}

// -/= and the d-pad step the first Float parameter by a twentieth of its range, clamped, as
// a Param action (so a recording replays it); a demo without one gets nothing.
TEST(ViewerNudge, TheFirstFloatParameterStepsWithinItsRange) {
    using rg::viewer::Param;
    std::vector<Param> params(3);
    params[0] = {"n", "n", "", Param::Kind::Int, 3, 0, 10, {}};
    params[1] = {"u", "u", "", Param::Kind::Float, 0.5, 0, 2, {}};
    params[2] = {"v", "v", "", Param::Kind::Float, 0.0, 0, 1, {}};
    auto a = rg::viewer::nudgeAction(params, 1);
    ASSERT_TRUE(a.has_value());
    EXPECT_EQ(a->kind, Action::Kind::Param);
    EXPECT_EQ(a->name, "u");
    EXPECT_DOUBLE_EQ(a->value, 0.6);
    params[1].value = 1.95;
    EXPECT_DOUBLE_EQ(rg::viewer::nudgeAction(params, 1)->value, 2.0);  // clamped at max
    params[1].value = 0.05;
    EXPECT_DOUBLE_EQ(rg::viewer::nudgeAction(params, -1)->value, 0.0);  // and at min
    params.erase(params.begin() + 1, params.end());
    EXPECT_FALSE(rg::viewer::nudgeAction(params, 1).has_value());
    // The d-pad: a press to the right or left steps once; holding it or up/down does not.
    pad::PadState idle, right, left, up;
    right.hat = 2;
    left.hat = 6;
    up.hat = 0;
    EXPECT_EQ(rg::viewer::padNudge(right, idle), 1);
    EXPECT_EQ(rg::viewer::padNudge(left, idle), -1);
    EXPECT_EQ(rg::viewer::padNudge(right, right), 0);
    EXPECT_EQ(rg::viewer::padNudge(up, idle), 0);
    EXPECT_EQ(rg::viewer::padNudge(idle, right), 0);
}
