#include <gtest/gtest.h>

#include <set>
#include <string>

#include "core/error.h"
#include "core/profile.h"

namespace rg {
namespace {

TEST(Profiles, AllFiveMachinesExistByName) {
    for (const char* name :
         {"geforce256", "geforce3", "sgi-octane-mxe", "sgi-o2", "geforce8800"}) {
        const Profile& p = profileByName(name);
        EXPECT_EQ(p.name, name);
        EXPECT_EQ(&profile(p.id), &p);
    }
    EXPECT_EQ(allProfiles().size(), 5u);
}

TEST(Profiles, UnknownNameListsTheKnownOnes) {
    try {
        profileByName("voodoo2");
        FAIL() << "expected rg::Error";
    } catch (const Error& e) {
        std::string msg = e.what();
        EXPECT_NE(msg.find("voodoo2"), std::string::npos);
        EXPECT_NE(msg.find("geforce256"), std::string::npos);
    }
}

// The PEM paper's pass count follows from this number: 5 texture accesses at 2 per pass.
TEST(Profiles, GeForce256HasTwoStagesAndCubeMapsButNoPixelTexture) {
    const Profile& p = profileByName("geforce256");
    EXPECT_EQ(p.maxTextureStages, 2);
    EXPECT_TRUE(p.has(Feature::CubeMap));
    EXPECT_TRUE(p.has(Feature::TextureStages));
    EXPECT_FALSE(p.has(Feature::PixelTexture));
    EXPECT_FALSE(p.has(Feature::FloatRenderTarget));
    EXPECT_EQ(profileByName("geforce3").maxTextureStages, 4);
}

TEST(Profiles, MissingFeatureIsAnErrorNamingProfileAndFeature) {
    const Profile& p = profileByName("geforce256");
    try {
        p.require(Feature::PixelTexture);
        FAIL() << "expected rg::UnsupportedFeature";
    } catch (const UnsupportedFeature& e) {
        EXPECT_EQ(e.profile(), "geforce256");
        EXPECT_NE(std::string(e.what()).find("SGIX_pixel_texture"), std::string::npos);
    }
    EXPECT_NO_THROW(profileByName("sgi-octane-mxe").require(Feature::PixelTexture));
    // The O2 ran the lookup in software (Heidrich et al. 1999 §4, the Fig. 3 text): no pixel texture.
    EXPECT_THROW(profileByName("sgi-o2").require(Feature::PixelTexture), UnsupportedFeature);
    EXPECT_THROW(profileByName("sgi-o2").require(Feature::Texture4D), UnsupportedFeature);
    EXPECT_NO_THROW(profileByName("sgi-o2").require(Feature::TextureColorTable));
}

TEST(Profiles, LimitsAreErrorsPastTheMaximum) {
    const Profile& p = profileByName("geforce256");
    EXPECT_NO_THROW(p.requireLimit("texture size", 2048, p.maxTextureSize));
    EXPECT_THROW(p.requireLimit("texture size", 4096, p.maxTextureSize), UnsupportedFeature);
}

TEST(Profiles, EveryFeatureHasAName) {
    std::set<std::string_view> names;
    for (uint32_t f = 0; f < uint32_t(Feature::Count); ++f) {
        auto n = featureName(Feature(f));
        EXPECT_NE(n, "unknown feature");
        names.insert(n);
    }
    EXPECT_EQ(names.size(), size_t(Feature::Count));
}

}  // namespace
}  // namespace rg
