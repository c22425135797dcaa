// The shared report pieces (demos/common): claims and their margins, the three files a
// Report writes, the gallery read back by a real browser (headless Chromium), figures.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>

#include "core/error.h"
#include "figures.h"
#include "gallery.h"
#include "raycore/image.h"
#include "report.h"
#include "reproduction.h"
#include "scratch_dir.h"

namespace fs = std::filesystem;

namespace rg::demos {
namespace {

// A folder of this process and test alone (tests/scratch_dir.h: ctest -j runs tests at once).
fs::path testDir() { return test::scratchDir("out"); }

std::string readText(const fs::path& p) {
    std::ifstream f(p);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

// A paper for the tests: reproduce() writes two figures and three claims.
class FakeReproduction final : public Reproduction {
  public:
    std::string name() const override { return "fake"; }
    std::string paper() const override { return "Somebody, \"A fake paper\", 1999"; }
    std::string profile() const override { return "geforce256"; }
    nlohmann::json settings(Quality) const override { return {{"size", 8}}; }
    nlohmann::json reproduce(const ReproduceOptions& o) const override {
        Report rep(*this, o.quality);
        ray::Image red(24, 16, 3), blue(24, 16, 3);
        for (int y = 0; y < 16; ++y)
            for (int x = 0; x < 24; ++x) red.setRgb(x, y, {1, 0, 0}), blue.setRgb(x, y, {0, 0, 1});
        ray::writeImage(o.outDir / "figure1.png", labelledGrid({{red, "red"}, {blue, "blue"}}, 2));
        ray::writeImage(o.outDir / "figure2.png", blue);
        rep.figure("figure1.png", "Figure 1 analogue: red and blue.");
        rep.heading("Numbers");
        rep.table({{"", "paper", "ours"}, {{"fps", "22", "61.5"}}});
        rep.figure("figure2.png", "Figure 2 analogue.");
        rep.claim(claimAtLeast("a_beats_b", "§5", "A beats B", "a", 30.0, "b", 25.0, 0.5, "dB"));
        rep.claim(claimAtLeast("c_beats_d", "§6", "C beats D", "c", 25.2, "d", 25.0, 0.5, "dB"));
        rep.claim(claimWithin("e_near_f", "§7", "E is close to F", "e", 1.0, "f", 1.2, 0.25, ""));
        return rep.write(o.outDir, {{"psnr_db", 30.0}});
    }
};

TEST(Claims, MarginsDecide) {
    EXPECT_TRUE(claimAtLeast("x", "§1", "s", "a", 10.5, "b", 10.0, 0.5, "dB").holds);
    EXPECT_FALSE(claimAtLeast("x", "§1", "s", "a", 10.49, "b", 10.0, 0.5, "dB").holds);
    EXPECT_FALSE(claimAtLeast("x", "§1", "s", "a", 9.0, "b", 10.0, 0.0, "dB").holds);
    EXPECT_TRUE(claimWithin("x", "§1", "s", "a", 1.0, "b", 1.25, 0.25, "").holds);
    EXPECT_FALSE(claimWithin("x", "§1", "s", "a", 1.0, "b", 1.26, 0.25, "").holds);
    Claim c = claimAtLeast("x", "§1", "s", "a", 10.7, "b", 10.0, 0.5, "dB");
    EXPECT_NEAR(c.measured["difference"].get<double>(), 0.7, 1e-12);
    EXPECT_EQ(c.test, "a − b ≥ 0.50 dB");
}

TEST(Report, WritesMarkdownHtmlAndResultsWithClaims) {
    const fs::path out = testDir() / "fake";
    ReproduceOptions o;
    o.outDir = out;
    fs::create_directories(out);
    nlohmann::json r = FakeReproduction().reproduce(o);
    // results.json: the paper's keys plus the common ones, read back from the file.
    nlohmann::json file = nlohmann::json::parse(readText(out / "results.json"));
    EXPECT_EQ(file, r);
    EXPECT_EQ(file["psnr_db"].get<double>(), 30.0);
    EXPECT_EQ(file["name"], "fake");
    EXPECT_EQ(file["quality"], "quick");
    EXPECT_EQ(file["claims_total"].get<int>(), 3);
    EXPECT_EQ(file["claims_held"].get<int>(), 2);
    ASSERT_EQ(file["claims"].size(), 3u);
    EXPECT_EQ(file["claims"][1]["id"], "c_beats_d");
    EXPECT_FALSE(file["claims"][1]["holds"].get<bool>());
    EXPECT_EQ(file["claims"][1]["section"], "§6");
    EXPECT_NEAR(file["claims"][1]["measured"]["difference"].get<double>(), 0.2, 1e-12);
    EXPECT_EQ(file["figures"][0]["file"], "figure1.png");
    // report.md: the claims table first, then the body; index.html the same as HTML.
    const std::string md = readText(out / "report.md");
    EXPECT_NE(md.find("## The paper's claims: 2 of 3 hold"), std::string::npos);
    EXPECT_NE(md.find("| ✘ does not hold | §6 | C beats D |"), std::string::npos) << md;
    EXPECT_NE(md.find("![Figure 1 analogue: red and blue.](figure1.png)"), std::string::npos);
    const std::string html = readText(out / "index.html");
    EXPECT_NE(html.find("<img src=\"figure1.png\""), std::string::npos) << html;
    EXPECT_NE(html.find("<td>61.5</td>"), std::string::npos) << html;  // tables became HTML
    EXPECT_NE(html.find("href=\"../index.html\""), std::string::npos);
    EXPECT_EQ(claimsLine("fake", file), "fake: 2 of 3 claims hold\n    does not hold: c_beats_d");
}

TEST(Report, ShowsQuickAndPaperSideBySideWhenBothRanIntoTheFolder) {
    const fs::path out = testDir() / "fake";
    fs::create_directories(out);
    ReproduceOptions o;
    o.outDir = out;
    FakeReproduction().reproduce(o);
    EXPECT_EQ(readText(out / "report.md").find("side by side"), std::string::npos)
        << "a side-by-side table with only one quality run";
    // The paper run: one claim measured differently, so the columns can be told apart.
    FakeReproduction fake;
    Report rep(fake, Quality::Paper);
    rep.claim(claimAtLeast("a_beats_b", "§5", "A beats B", "a", 31.0, "b", 25.0, 0.5, "dB"));
    rep.claim(claimAtLeast("c_beats_d", "§6", "C beats D", "c", 26.0, "d", 25.0, 0.5, "dB"));
    rep.write(out, {});
    const std::string md = readText(out / "report.md");
    EXPECT_NE(md.find("## Quick and paper quality side by side"), std::string::npos) << md;
    // quick: c − d = 0.2 does not hold; paper: 1.0 holds.
    const size_t row = md.find("| `c_beats_d` | ");
    ASSERT_NE(row, std::string::npos) << md;
    const std::string line = md.substr(row, md.find('\n', row) - row);
    const size_t quick = line.find("✘"), paper = line.find("✔");
    EXPECT_TRUE(quick != std::string::npos && paper != std::string::npos && quick < paper) << line;
    EXPECT_NE(line.find("difference = 0.200"), std::string::npos) << line;
    EXPECT_NE(line.find("difference = 1.000"), std::string::npos) << line;
    EXPECT_NE(md.find("| claims hold | 2 | 2 |"), std::string::npos) << md;
    EXPECT_TRUE(fs::exists(out / "results-quick.json"));
    EXPECT_EQ(nlohmann::json::parse(readText(out / "results-paper.json"))["quality"], "paper");
}

TEST(Report, RefusesAMissingFigureAndATwiceGivenClaim) {
    const fs::path out = testDir();
    FakeReproduction fake;
    Report rep(fake, Quality::Paper);
    rep.figure("never_written.png", "a figure nobody wrote");
    EXPECT_THROW(rep.write(out, {}), Error);
    EXPECT_FALSE(fs::exists(out / "results.json"));
    Report rep2(fake, Quality::Quick);
    rep2.claim(claimAtLeast("same", "§1", "s", "a", 1, "b", 0, 0, ""));
    EXPECT_THROW(rep2.claim(claimAtLeast("same", "§2", "s", "a", 1, "b", 0, 0, "")), Error);
    EXPECT_THROW(Table({{"a", "b"}, {{"only one"}}}).markdown(), Error);
}

TEST(Figures, LabelledGridPlacesCellsAndDrawsLabels) {
    ray::Image red(10, 6, 3), green(10, 6, 3);
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 10; ++x) red.setRgb(x, y, {1, 0, 0}), green.setRgb(x, y, {0, 1, 0});
    const int label = 14;
    ray::Image g = labelledGrid({{red, "r"}, {green, "g"}, {red, ""}}, 2, label);
    // Two columns 6 apart, two rows 6 apart, each cell label + image tall.
    EXPECT_EQ(g.width, 10 + 6 + 10);
    EXPECT_EQ(g.height, 2 * (label + 6) + 6);
    EXPECT_EQ(g.rgb(0, label), glm::vec3(1, 0, 0));           // first image under its label
    EXPECT_EQ(g.rgb(16, label + 5), glm::vec3(0, 1, 0));      // second column
    EXPECT_EQ(g.rgb(3, label + 6 + 6 + label), glm::vec3(1, 0, 0));  // second row
    // A label is dark ink on white; an empty label is all white.
    float darkest = 1.0f;
    for (int y = 0; y < label; ++y)
        for (int x = 0; x < 10; ++x) darkest = std::min(darkest, g.rgb(x, y).x);
    EXPECT_LT(darkest, 0.5f);
    for (int y = 26; y < 26 + label; ++y)
        for (int x = 0; x < 10; ++x) EXPECT_EQ(g.rgb(x, y), glm::vec3(1.0f)) << x << "," << y;
}

// ---- the gallery in a real browser -------------------------------------------------------

struct BrowserVerdict {
    nlohmann::json result;
    std::string raw;
};

// Opens tests/demos/gallery_check.html beside `root`/index.html in headless Chromium; it
// visits every linked page, waits for every image and reports what failed.
BrowserVerdict checkInBrowser(const fs::path& root) {
    fs::copy_file(fs::path(RETROGLASS_SOURCE_DIR) / "tests/demos/gallery_check.html",
                  root / "gallery_check.html", fs::copy_options::overwrite_existing);
    const fs::path dump = root / "dom.txt";
    const std::string cmd = "timeout 120 chromium --headless --no-sandbox --disable-gpu "
                            "--user-data-dir='" + (root / "chromium-profile").string() +
                            "' --allow-file-access-from-files --virtual-time-budget=60000 "
                            "--dump-dom 'file://" + fs::absolute(root / "gallery_check.html").string() +
                            "' > '" + dump.string() + "' 2>/dev/null";
    const int rc = std::system(cmd.c_str());
    BrowserVerdict v;
    v.raw = readText(dump);
    EXPECT_EQ(rc, 0) << "chromium failed (the launcher installs Debian's chromium): " << cmd;
    std::smatch m;
    static const std::regex result("RESULT:(\\{.*\\})</pre>");
    if (std::regex_search(v.raw, m, result)) v.result = nlohmann::json::parse(m[1].str());
    return v;
}

TEST(Gallery, EveryImageLoadsAndEveryLinkResolvesInABrowser) {
    const fs::path root = testDir();
    FakeReproduction fake;
    PlannedReproduction planned("planned", "Nobody, \"Not yet\", 2007", "geforce8800");
    ReproduceOptions o;
    o.outDir = root / "fake";
    fs::create_directories(o.outDir);
    fake.reproduce(o);
    writeGallery(root, {&fake, &planned});
    const std::string index = readText(root / "index.html");
    EXPECT_NE(index.find("2 of 3 claims hold"), std::string::npos);
    EXPECT_NE(index.find("not built yet"), std::string::npos);

    BrowserVerdict v = checkInBrowser(root);
    ASSERT_TRUE(v.result.is_object()) << v.raw;
    EXPECT_EQ(v.result["broken"], nlohmann::json::array()) << v.result.dump(2);
    EXPECT_EQ(v.result["pages"].size(), 2u) << v.result.dump(2);  // the gallery, the paper's page
    EXPECT_EQ(v.result["images"].get<int>(), 3);  // thumbnail + two figures
    EXPECT_GE(v.result["links"].get<int>(), 6);

    // A screenshot of the gallery for whoever reads the test output: in a folder of its own
    // that stays after a pass (the rest, the browser profile included, goes).
    const fs::path shotFile = test::scratchDir("screenshot", test::Keep::Always) / "gallery.png";
    const std::string shot = "timeout 120 chromium --headless --no-sandbox --disable-gpu "
                             "--user-data-dir='" + (root / "chromium-profile").string() +
                             "' --window-size=1200,900 --screenshot='" + shotFile.string() +
                             "' 'file://" + fs::absolute(root / "index.html").string() +
                             "' >/dev/null 2>&1";
    EXPECT_EQ(std::system(shot.c_str()), 0);
    EXPECT_GT(fs::file_size(shotFile), 1000u);
    std::printf("gallery screenshot: %s\n", shotFile.string().c_str());

    // The check can fail: a figure gone and another corrupt are both reported.
    fs::remove(o.outDir / "figure2.png");
    std::ofstream(o.outDir / "figure1.png") << "not a png";
    BrowserVerdict broken = checkInBrowser(root);
    ASSERT_TRUE(broken.result.is_object()) << broken.raw;
    std::set<std::string> bad;
    for (const auto& b : broken.result["broken"]) bad.insert(b.value("src", ""));
    EXPECT_TRUE(bad.count("figure2.png")) << broken.result.dump(2);
    EXPECT_TRUE(bad.count("figure1.png")) << broken.result.dump(2);
    EXPECT_TRUE(bad.count("fake/figure1.png")) << broken.result.dump(2);  // the thumbnail
    // And a page that links to a file that is not there.
    fs::remove(o.outDir / "report.md");
    BrowserVerdict dangling = checkInBrowser(root);
    bool reported = false;
    for (const auto& b : dangling.result["broken"])
        reported = reported || (b["kind"] == "link" && b["href"].get<std::string>().ends_with("fake/report.md"));
    EXPECT_TRUE(reported) << dangling.result.dump(2);
}

TEST(Gallery, SaysWhatIsNotRunYet) {
    const fs::path root = testDir();
    FakeReproduction fake;
    writeGallery(root, {&fake});
    EXPECT_NE(readText(root / "index.html").find("not run yet: <code>./retroglass reproduce fake"),
              std::string::npos);
}

TEST(Registry, EveryPaperOnceWithItsProfile) {
    std::set<std::string> names;
    for (const Reproduction* r : reproductions()) {
        EXPECT_TRUE(names.insert(r->name()).second) << r->name();
        EXPECT_FALSE(r->paper().empty());
    }
    EXPECT_EQ(names, (std::set<std::string>{"pem", "hybrid", "lightfield", "impostors", "tir"}));
    EXPECT_EQ(findReproduction("pem").profile(), "geforce256");
    EXPECT_THROW(findReproduction("nonesuch"), Error);
    EXPECT_THROW(ViewRange::parse("3:2", 10), Error);
    EXPECT_THROW(ViewRange::parse("0:11", 10), Error);
    EXPECT_THROW(ViewRange::parse("-1:2", 10), Error);
    EXPECT_THROW(ViewRange::parse("1:2x", 10), Error);
    ViewRange r = ViewRange::parse("2:5", 10);
    EXPECT_EQ(r.begin, 2);
    EXPECT_EQ(r.end, 5);
    EXPECT_FALSE(r.all);
    EXPECT_TRUE(ViewRange::parse("", 10).all);
}

}  // namespace
}  // namespace rg::demos
