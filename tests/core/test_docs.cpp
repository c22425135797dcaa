// Docs that can't go stale: every repository path docs/ names in backquotes must exist
// (STYLE.md, "Docs that can't go stale").
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <cctype>
#include <regex>
#include <set>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace {

TEST(Docs, PathsNamedInDocsExist) {
    const fs::path root = RETROGLASS_SOURCE_DIR;
    // `folder/…/file.ext` or `folder/` where folder is one of the project's top folders.
    const std::regex pathRe(
        R"(`((?:core|rasterizer|texunit|raycore|demos|tests|docs|bench|data|tools|cmake)/[A-Za-z0-9_./-]*)`)");
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

// A link to a section of the specification (`[…](hardware.md#anchor)`, the way
// docs/trace-format.md points at the rule it relies on) names a heading that exists, as
// GitHub derives anchors: lower case, spaces to hyphens, punctuation dropped.
TEST(Docs, LinksToHardwareSectionsNameExistingHeadings) {
    const fs::path root = RETROGLASS_SOURCE_DIR;
    auto read = [](const fs::path& p) {
        std::ifstream in(p);
        std::stringstream ss;
        ss << in.rdbuf();
        return ss.str();
    };
    auto slug = [](const std::string& heading) {
        std::string out;
        for (unsigned char c : heading) {
            if (std::isalnum(c)) out += char(std::tolower(c));
            else if (c == ' ' || c == '-') out += '-';
            else if (c >= 0x80) out += char(c);  // UTF-8 letters stay
        }
        return out;
    };
    std::set<std::string> anchors;
    const std::string spec = read(root / "docs" / "hardware.md");
    const std::regex headingRe(R"((?:^|\n)#{1,6} ([^\n]+))");
    for (std::sregex_iterator it(spec.begin(), spec.end(), headingRe), end; it != end; ++it)
        anchors.insert(slug((*it)[1]));
    const std::regex linkRe(R"(\]\((?:docs/)?hardware\.md#([^)]+)\))");
    int checked = 0;
    for (const auto& entry : fs::directory_iterator(root / "docs")) {
        if (entry.path().extension() != ".md") continue;
        const std::string text = read(entry.path());
        for (std::sregex_iterator it(text.begin(), text.end(), linkRe), end; it != end; ++it) {
            EXPECT_TRUE(anchors.count((*it)[1])) << entry.path().filename() << " links to hardware.md#" << (*it)[1]
                                                 << ", a section that does not exist";
            ++checked;
        }
    }
    EXPECT_GT(checked, 10) << "docs/trace-format.md should link the sections it relies on";
}

TEST(Docs, HardwareSpecOpensWithPinnedChoices) {
    std::ifstream in(fs::path(RETROGLASS_SOURCE_DIR) / "docs" / "hardware.md");
    ASSERT_TRUE(in) << "docs/hardware.md is missing";
    std::stringstream ss;
    ss << in.rdbuf();
    EXPECT_NE(ss.str().find("Pinned choices"), std::string::npos);
}

}  // namespace
