// `retroglass raytrace` through its library entry point.
#include <gtest/gtest.h>

#include "raycore/image.h"
#include "raycore/raytrace_command.h"
#include "test_util.h"

namespace rg::ray {
namespace {

TEST(RaytraceCommand, WritesTheImageAndTheTermImages) {
    auto dir = test::tempDir("raytrace_command");
    RaytraceArgs a;
    a.scene = "mirror-sphere";
    a.width = 16;
    a.height = 12;
    a.quiet = true;
    a.out = (dir / "w.png").string();
    ASSERT_EQ(runRaytraceCommand(a), 0);
    Image w = readImage(dir / "w.png");
    EXPECT_EQ(w.width, 16);
    EXPECT_EQ(w.height, 12);
    a.mode = "two-term";
    a.spp = 2;
    a.out = (dir / "t.exr").string();
    ASSERT_EQ(runRaytraceCommand(a), 0);
    EXPECT_TRUE(std::filesystem::exists(dir / "t_reflect.exr"));
    EXPECT_TRUE(std::filesystem::exists(dir / "t_refract_confidence.exr"));
    a.scene = (test::sourceDir() / "data" / "scenes" / "example.json").string();
    a.mode = "pem-layers";
    a.camera = "circle:10";
    a.spp = 1;
    a.out = (dir / "p.png").string();
    ASSERT_EQ(runRaytraceCommand(a), 0);
    EXPECT_TRUE(std::filesystem::exists(dir / "p_teapot_local_alpha.png"));
}

TEST(RaytraceCommand, BadArgumentsReturnOneWithoutThrowing) {
    auto dir = test::tempDir("raytrace_command_bad");
    RaytraceArgs a;
    a.quiet = true;
    a.width = 8;
    a.height = 8;
    a.out = (dir / "x.png").string();
    a.scene = "no-such-scene";
    EXPECT_EQ(runRaytraceCommand(a), 1);
    a.scene = "mirror-sphere";
    a.mode = "photon-mapping";
    EXPECT_EQ(runRaytraceCommand(a), 1);
    a.mode = "whitted";
    a.camera = "nowhere:3";
    EXPECT_EQ(runRaytraceCommand(a), 1);
    a.camera = "";
    a.out = "";
    EXPECT_EQ(runRaytraceCommand(a), 1);
    EXPECT_FALSE(std::filesystem::exists(dir / "x.png"));
}

}  // namespace
}  // namespace rg::ray
