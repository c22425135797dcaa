// A precompute split by --views ranges (demos/common/shards.h): views written whole or not
// at all, and `retroglass merge` refusing, with the offending file named and nothing
// written, every way shards can fail to belong together (issue 21, "Bad input").
#include <gtest/gtest.h>

#include <fstream>
#include <functional>

#include "core/error.h"
#include "scratch_dir.h"
#include "shards.h"

namespace fs = std::filesystem;

namespace rg::demos {
namespace {

ShardIdentity identity() {
    ShardIdentity id;
    id.paper = "fake";
    id.quality = "quick";
    id.profile = "geforce256";
    id.codeVersion = codeVersion();
    id.settingsSha256 = sha256OfBytes("settings");
    id.sceneSha256 = sha256OfBytes("scene");
    id.views = 6;
    return id;
}

void writeText(const fs::path& p, const std::string& text) {
    std::ofstream f(p, std::ios::binary);
    f << text;
}

std::string readText(const fs::path& p) {
    std::ifstream f(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(f), {});
}

// A shard as `reproduce --views A:B` leaves it: a shared file and one folder per view.
fs::path makeShard(const fs::path& out, int begin, int end, ShardIdentity id = identity()) {
    ViewStore store(out / id.paper / "assets", id);
    writeText(store.dir() / "manifest.json", "{\"size\": 8}\n");
    store.addRange(ViewRange{begin, end, false});
    for (int v = begin; v < end; ++v) {
        const fs::path d = store.beginView(v);
        writeText(d / "map.bin", "texels of view " + std::to_string(v) + std::string(100, 'x'));
        writeText(d / "view.json", "{\"view\": " + std::to_string(v) + "}\n");
        store.commitView(v);
    }
    return out;
}

// merge must throw an rg::Error mentioning `names`, and leave no output behind.
void expectRefused(const std::vector<fs::path>& shards, const fs::path& out,
                   const std::string& names) {
    try {
        mergeShards(shards, out);
        ADD_FAILURE() << "merge accepted shards it should refuse (expected to name " << names << ")";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(names), std::string::npos)
            << "the error does not name " << names << ": " << e.what();
    }
    EXPECT_FALSE(fs::exists(out / "fake" / "assets")) << "a refused merge wrote its output";
    EXPECT_FALSE(fs::exists(out / "fake" / "assets.partial"));
}

TEST(Shards, MergeJoinsDisjointRangesIntoTheWholePrecompute) {
    const fs::path d = test::scratchDir("shards");
    makeShard(d / "a", 0, 2);
    makeShard(d / "b", 2, 5);
    makeShard(d / "c", 5, 6);
    const MergeResult m = mergeShards({d / "c", d / "a", d / "b"}, d / "merged");
    EXPECT_EQ(m.views, 6);
    EXPECT_EQ(m.paper, "fake");
    ViewStore merged(m.assets, identity());
    for (int v = 0; v < 6; ++v) {
        ASSERT_TRUE(merged.finished(v)) << v;
        EXPECT_NO_THROW(merged.verifyView(v));
        EXPECT_EQ(readText(merged.viewDir(v) / "map.bin"),
                  "texels of view " + std::to_string(v) + std::string(100, 'x'));
    }
    EXPECT_EQ(readText(m.assets / "manifest.json"), "{\"size\": 8}\n");
}

TEST(Shards, MergeRefusesShardsOfOtherInputs) {
    const std::vector<std::pair<std::string, std::function<void(ShardIdentity&)>>> changes = {
        {"settings", [](ShardIdentity& i) { i.settingsSha256 = sha256OfBytes("other"); }},
        {"scene", [](ShardIdentity& i) { i.sceneSha256 = sha256OfBytes("other"); }},
        {"profile", [](ShardIdentity& i) { i.profile = "voodoo2"; }},
        {"quality", [](ShardIdentity& i) { i.quality = "paper"; }},
        {"code version", [](ShardIdentity& i) { i.codeVersion = "0123abc"; }},
        {"view count", [](ShardIdentity& i) { i.views = 7; }}};
    for (const auto& [what, change] : changes) {
        SCOPED_TRACE(what);
        const fs::path d = test::scratchDir("shards");
        makeShard(d / "a", 0, 3);
        ShardIdentity other = identity();
        change(other);
        makeShard(d / "b", 3, 6, other);
        expectRefused({d / "a", d / "b"}, d / "merged", (d / "b" / "fake" / "assets" / "shard.json").string());
        expectRefused({d / "a", d / "b"}, d / "merged", what);
    }
}

TEST(Shards, MergeRefusesViewsOfAnotherCodeVersionEvenWhenTheyAgree) {
    const fs::path d = test::scratchDir("shards");
    ShardIdentity old = identity();
    old.codeVersion = "0123abc";
    makeShard(d / "a", 0, 3, old);
    makeShard(d / "b", 3, 6, old);
    expectRefused({d / "a", d / "b"}, d / "merged", "made by code version 0123abc");
}

TEST(Shards, MergeRefusesMissingDuplicatedAndOverlappingRanges) {
    const fs::path d = test::scratchDir("shards");
    makeShard(d / "a", 0, 3);
    makeShard(d / "b", 4, 6);
    expectRefused({d / "a", d / "b"}, d / "merged", "views 3 of 6 are in none");
    makeShard(d / "dup", 0, 3);
    expectRefused({d / "a", d / "dup", d / "b"}, d / "merged", (d / "dup" / "fake" / "assets" / "view_000").string());
    makeShard(d / "over", 2, 4);
    expectRefused({d / "a", d / "over", d / "b"}, d / "merged", "overlapping");
}

TEST(Shards, MergeRefusesTruncatedAndCorruptFiles) {
    const fs::path d = test::scratchDir("shards");
    makeShard(d / "a", 0, 3);
    makeShard(d / "b", 3, 6);
    const fs::path file = d / "b" / "fake" / "assets" / "view_004" / "map.bin";
    const std::string good = readText(file);
    writeText(file, good.substr(0, good.size() / 2));
    expectRefused({d / "a", d / "b"}, d / "merged", file.string() + ": ");
    expectRefused({d / "a", d / "b"}, d / "merged", "truncated");
    std::string bad = good;
    bad[20] ^= 1;
    writeText(file, bad);
    expectRefused({d / "a", d / "b"}, d / "merged", "corrupt");
    writeText(file, good);
    fs::remove(d / "a" / "fake" / "assets" / "view_001" / "files.json");
    expectRefused({d / "a", d / "b"}, d / "merged", (d / "a" / "fake" / "assets" / "view_001" / "files.json").string());
}

TEST(Shards, MergeRefusesARangeThatDidNotFinish) {
    const fs::path d = test::scratchDir("shards");
    makeShard(d / "a", 0, 3);
    makeShard(d / "b", 3, 5);
    // b's task was asked for 3:6 and killed while view 5 was being written.
    ViewStore b(d / "b" / "fake" / "assets", identity());
    b.addRange(ViewRange{3, 6, false});
    writeText(b.beginView(5) / "map.bin", "half a vi");
    expectRefused({d / "a", d / "b"}, d / "merged", "range 3:6 did not finish (views 5 missing)");
}

TEST(Shards, MergeNeverOverwritesAnExistingOutput) {
    const fs::path d = test::scratchDir("shards");
    makeShard(d / "a", 0, 6);
    fs::create_directories(d / "merged" / "fake" / "assets");
    writeText(d / "merged" / "fake" / "assets" / "keep.txt", "mine");
    EXPECT_THROW(mergeShards({d / "a"}, d / "merged"), Error);
    EXPECT_EQ(readText(d / "merged" / "fake" / "assets" / "keep.txt"), "mine");
}

TEST(Shards, AStoreOfOtherInputsIsRefusedAndKept) {
    const fs::path d = test::scratchDir("shards");
    makeShard(d / "a", 0, 2);
    ShardIdentity other = identity();
    other.sceneSha256 = sha256OfBytes("another scene");
    const fs::path assets = d / "a" / "fake" / "assets";
    try {
        ViewStore store(assets, other);
        ADD_FAILURE() << "a store of another scene was opened";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find((assets / "shard.json").string()), std::string::npos)
            << e.what();
    }
    EXPECT_TRUE(fs::exists(assets / "view_000" / "map.bin"));
    EXPECT_TRUE(fs::exists(assets / "view_001" / "map.bin"));
}

TEST(Shards, OlderCodesViewsAreRecomputedAfterAWholeRunButAShardOfThemIsRefused) {
    const fs::path d = test::scratchDir("shards");
    ShardIdentity old = identity();
    old.codeVersion = "0123abc";
    makeShard(d / "whole", 0, 6, old);  // a whole run, as `reproduce` without --views
    {
        ViewStore store(d / "whole" / "fake" / "assets", identity());
        EXPECT_FALSE(store.finished(0)) << "a view of older code was kept for this code";
    }
    makeShard(d / "part", 0, 3, old);  // a --views shard, made to be merged
    const fs::path assets = d / "part" / "fake" / "assets";
    try {
        ViewStore store(assets, identity());
        ADD_FAILURE() << "a shard of older code was opened";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("code version"), std::string::npos) << e.what();
    }
    EXPECT_TRUE(fs::exists(assets / "view_002" / "map.bin"));
}

TEST(Shards, AViewKilledMidWriteIsNeitherFinishedNorKept) {
    const fs::path d = test::scratchDir("shards");
    makeShard(d / "a", 0, 2);
    const fs::path assets = d / "a" / "fake" / "assets";
    {
        ViewStore store(assets, identity());
        writeText(store.beginView(2) / "map.bin", "half");  // the kill: no commitView
        EXPECT_FALSE(store.finished(2));
        EXPECT_TRUE(store.finished(1));
    }
    ViewStore reopened(assets, identity());  // the resumed run
    EXPECT_FALSE(fs::exists(assets / "view_002.partial"));
    EXPECT_FALSE(reopened.finished(2));
    EXPECT_NO_THROW(reopened.verifyView(0));
    EXPECT_NO_THROW(reopened.verifyView(1));
}

TEST(Shards, RecommittingAViewReplacesItWhole) {
    const fs::path d = test::scratchDir("shards");
    makeShard(d / "a", 0, 1);
    ViewStore store(d / "a" / "fake" / "assets", identity());
    const fs::path p = store.beginView(0);
    writeText(p / "map.bin", "more maps");
    store.commitView(0);
    EXPECT_EQ(readText(store.viewDir(0) / "map.bin"), "more maps");
    EXPECT_FALSE(fs::exists(store.viewDir(0) / "view.json")) << "a file of the old view was left";
    EXPECT_NO_THROW(store.verifyView(0));
}

}  // namespace
}  // namespace rg::demos
