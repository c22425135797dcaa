// Docs that can't go stale: every repository path docs/ names in backquotes must exist
// (STYLE.md, "Docs that can't go stale").
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

TEST(Docs, PathsNamedInDocsExist) {
    const fs::path root = RETROGLASS_SOURCE_DIR;
    // `folder/…/file.ext` or `folder/` where folder is one of the project's top folders.
    const std::regex pathRe(
        R"(`((?:core|rasterizer|texunit|raycore|demos|tests|docs|bench|data)/[A-Za-z0-9_./-]*)`)");
    int checked = 0;
    for (const auto& entry : fs::directory_iterator(root / "docs")) {
        if (entry.path().extension() != ".md") continue;
        std::ifstream in(entry.path());
        std::stringstream ss;
        ss << in.rdbuf();
        std::string text = ss.str();
        for (std::sregex_iterator it(text.begin(), text.end(), pathRe), end; it != end; ++it) {
            std::string p = (*it)[1];
            if (p.find('*') != std::string::npos || p.find("<") != std::string::npos) continue;
            EXPECT_TRUE(fs::exists(root / p))
                << entry.path().filename() << " names `" << p << "`, which does not exist";
            ++checked;
        }
    }
    EXPECT_GT(checked, 0) << "docs/ names no paths at all";
}

TEST(Docs, HardwareSpecOpensWithPinnedChoices) {
    std::ifstream in(fs::path(RETROGLASS_SOURCE_DIR) / "docs" / "hardware.md");
    ASSERT_TRUE(in) << "docs/hardware.md is missing";
    std::stringstream ss;
    ss << in.rdbuf();
    EXPECT_NE(ss.str().find("Pinned choices"), std::string::npos);
}

}  // namespace
