#include "shards.h"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/error.h"
#include "rasterizer/trace.h"

namespace fs = std::filesystem;

namespace rg::demos {

namespace {

constexpr const char* kIdentityFile = "shard.json";
constexpr const char* kFilesFile = "files.json";
constexpr const char* kPartial = ".partial";

std::string readAll(const fs::path& file) {
    std::ifstream f(file, std::ios::binary);
    if (!f) throw Error(file.string() + ": cannot read");
    std::ostringstream s;
    s << f.rdbuf();
    if (f.bad()) throw Error(file.string() + ": read error");
    return s.str();
}

nlohmann::json readJson(const fs::path& file) {
    try {
        return nlohmann::json::parse(readAll(file));
    } catch (const nlohmann::json::exception& e) {
        throw Error(file.string() + ": not valid JSON (" + e.what() + ")");
    }
}

// Writes `text` to `file` through a temporary and a rename, so a reader never sees half of it.
void writeAtomically(const fs::path& file, const std::string& text) {
    const fs::path tmp = file.string() + kPartial;
    {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        f << text;
        f.flush();
        if (!f) {
            std::error_code ec;
            fs::remove(tmp, ec);
            throw Error(file.string() + ": cannot write (disk full or read-only?)");
        }
    }
    fs::rename(tmp, file);
}

// view_007 → 7; −1 for any other name (view_007.partial included).
int viewOfFolder(const std::string& name) {
    if (name.size() < 6 || name.rfind("view_", 0) != 0) return -1;
    int v = 0;
    for (size_t i = 5; i < name.size(); ++i) {
        if (name[i] < '0' || name[i] > '9') return -1;
        v = v * 10 + (name[i] - '0');
    }
    return v;
}

std::string shortHash(const std::string& h) { return h.substr(0, 12); }

// The finished views of a store, in order.
std::vector<int> finishedViews(const fs::path& dir) {
    std::vector<int> views;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.is_directory())
            if (int v = viewOfFolder(e.path().filename().string()); v >= 0) views.push_back(v);
    std::sort(views.begin(), views.end());
    return views;
}

void verifyViewFolder(const fs::path& vd) {
    const fs::path list = vd / kFilesFile;
    if (!fs::exists(list))
        throw Error(list.string() + ": missing (the view was not finished by this code)");
    const nlohmann::json files = readJson(list);
    if (!files.is_object() || files.empty()) throw Error(list.string() + ": lists no file");
    for (const auto& [name, f] : files.items()) {
        const fs::path file = vd / name;
        if (!fs::exists(file)) throw Error(file.string() + ": missing (listed in files.json)");
        const uint64_t bytes = fs::file_size(file);
        if (bytes != f.at("bytes").get<uint64_t>())
            throw Error(file.string() + ": " + std::to_string(bytes) + " bytes, files.json says " +
                        std::to_string(f.at("bytes").get<uint64_t>()) + " (truncated or altered)");
        if (sha256OfFile(file) != f.at("sha256").get<std::string>())
            throw Error(file.string() + ": SHA-256 differs from files.json (corrupt)");
    }
}

std::string rangesText(const std::vector<int>& views) {
    std::string s;
    for (size_t i = 0; i < views.size();) {
        size_t j = i;
        while (j + 1 < views.size() && views[j + 1] == views[j] + 1) ++j;
        if (!s.empty()) s += ", ";
        s += std::to_string(views[i]) + (j > i ? ".." + std::to_string(views[j]) : "");
        i = j + 1;
    }
    return s;
}

}  // namespace

std::string sha256OfBytes(const std::string& bytes) {
    return raster::sha256Hex(bytes.data(), bytes.size());
}

std::string sha256OfFile(const fs::path& file) { return sha256OfBytes(readAll(file)); }

nlohmann::json ShardIdentity::toJson() const {
    return {{"format", "retroglass-shard"},
            {"paper", paper},
            {"quality", quality},
            {"profile", profile},
            {"code_version", codeVersion},
            {"settings_sha256", settingsSha256},
            {"scene_sha256", sceneSha256},
            {"views", views}};
}

ShardIdentity ShardIdentity::fromJson(const nlohmann::json& j, const fs::path& file) {
    try {
        if (j.at("format").get<std::string>() != "retroglass-shard")
            throw Error(file.string() + ": not a retroglass shard");
        ShardIdentity id;
        id.paper = j.at("paper").get<std::string>();
        id.quality = j.at("quality").get<std::string>();
        id.profile = j.at("profile").get<std::string>();
        id.codeVersion = j.at("code_version").get<std::string>();
        id.settingsSha256 = j.at("settings_sha256").get<std::string>();
        id.sceneSha256 = j.at("scene_sha256").get<std::string>();
        id.views = j.at("views").get<int>();
        return id;
    } catch (const nlohmann::json::exception& e) {
        throw Error(file.string() + ": " + e.what());
    }
}

std::string ShardIdentity::differenceFrom(const ShardIdentity& o) const {
    std::string d;
    auto cmp = [&](const char* what, const std::string& a, const std::string& b, bool hash) {
        if (a == b) return;
        if (!d.empty()) d += "; ";
        d += std::string(what) + " " + (hash ? shortHash(a) : a) + " vs " +
             (hash ? shortHash(b) : b);
    };
    cmp("paper", paper, o.paper, false);
    cmp("quality", quality, o.quality, false);
    cmp("profile", profile, o.profile, false);
    cmp("code version", codeVersion, o.codeVersion, false);
    cmp("settings (sha256)", settingsSha256, o.settingsSha256, true);
    cmp("scene (sha256)", sceneSha256, o.sceneSha256, true);
    cmp("view count", std::to_string(views), std::to_string(o.views), false);
    return d;
}

std::string viewFolderName(int view) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "view_%03d", view);
    return buf;
}

fs::path assetsFolder(const fs::path& paperOut, const std::string& quality) {
    return paperOut / (quality == "quick" ? std::string("assets") : "assets-" + quality);
}

// ---- ViewStore ----------------------------------------------------------------------------

ViewStore::ViewStore(fs::path dir, ShardIdentity identity)
    : dir_(std::move(dir)), identity_(std::move(identity)) {
    const fs::path idFile = dir_ / kIdentityFile;
    // Views of older code, in a folder that only ever held whole runs (no --views shard):
    // what `reproduce` did before shards, and what every commit would otherwise refuse in
    // the default out/; they could not be mixed with this code's views anyway.
    auto startAfresh = [&](const std::string& why) {
        std::printf("%s: %s: %s; computing its views again\n", identity_.paper.c_str(),
                    dir_.string().c_str(), why.c_str());
        for (int v : finishedViews(dir_)) fs::remove_all(viewDir(v));
        writeIdentity(nlohmann::json::array());
    };
    if (fs::exists(idFile)) {
        const nlohmann::json j = readJson(idFile);
        const ShardIdentity stored = ShardIdentity::fromJson(j, idFile);
        ShardIdentity sameCode = stored;
        sameCode.codeVersion = identity_.codeVersion;
        bool wholeRuns = true;
        for (const auto& r : j.value("ranges", nlohmann::json::array()))
            wholeRuns = wholeRuns && r == nlohmann::json::array({0, stored.views});
        if (identity_ == sameCode && stored.codeVersion != identity_.codeVersion && wholeRuns) {
            startAfresh("made by code version " + stored.codeVersion);
        } else if (const std::string d = identity_.differenceFrom(stored); !d.empty()) {
            // Other settings, scene, profile or quality (a mistaken --out), or a shard of
            // other code (a --views run, made to be merged): kept, never cleared.
            throw Error(idFile.string() + ": these views were made with other inputs (" + d +
                        "); nothing was changed: remove the folder or choose another --out");
        }
    } else if (fs::exists(dir_) && !finishedViews(dir_).empty()) {
        startAfresh("views without shard.json, made before views were checksummed");
    } else {
        fs::create_directories(dir_);
        writeIdentity(nlohmann::json::array());
    }
    // A view still named .partial was being written when its run stopped.
    std::vector<fs::path> partial;
    for (const auto& e : fs::directory_iterator(dir_))
        if (e.path().extension() == kPartial) partial.push_back(e.path());
    for (const fs::path& p : partial) {
        std::printf("%s: removing %s, left unfinished by an interrupted run\n",
                    identity_.paper.c_str(), p.filename().string().c_str());
        fs::remove_all(p);
    }
}

void ViewStore::writeIdentity(const nlohmann::json& ranges) const {
    nlohmann::json j = identity_.toJson();
    j["ranges"] = ranges;
    writeAtomically(dir_ / kIdentityFile, j.dump(2) + "\n");
}

void ViewStore::addRange(const ViewRange& range) {
    nlohmann::json ranges = readJson(dir_ / kIdentityFile).value("ranges", nlohmann::json::array());
    const nlohmann::json r = {range.begin, range.end};
    if (std::find(ranges.begin(), ranges.end(), r) == ranges.end()) ranges.push_back(r);
    writeIdentity(ranges);
}

bool ViewStore::finished(int view) const { return fs::is_directory(viewDir(view)); }

fs::path ViewStore::viewDir(int view) const { return dir_ / viewFolderName(view); }

fs::path ViewStore::beginView(int view) const {
    const fs::path p = dir_ / (viewFolderName(view) + kPartial);
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
}

void ViewStore::commitView(int view) const {
    const fs::path p = dir_ / (viewFolderName(view) + kPartial);
    nlohmann::json files = nlohmann::json::object();
    std::vector<fs::path> names;
    for (const auto& e : fs::directory_iterator(p))
        if (e.is_regular_file()) names.push_back(e.path().filename());
    std::sort(names.begin(), names.end());
    for (const fs::path& n : names)
        files[n.string()] = {{"bytes", fs::file_size(p / n)}, {"sha256", sha256OfFile(p / n)}};
    writeAtomically(p / kFilesFile, files.dump(2) + "\n");
    // Replacing a finished view (one recomputed with more maps): set the old one aside
    // first, so some complete version of the view exists at every moment.
    const fs::path final = viewDir(view), old = dir_ / (viewFolderName(view) + ".old.partial");
    if (fs::exists(final)) fs::rename(final, old);
    fs::rename(p, final);
    fs::remove_all(old);
}

void ViewStore::verifyView(int view) const { verifyViewFolder(viewDir(view)); }

// ---- merge --------------------------------------------------------------------------------

MergeResult mergeShards(const std::vector<fs::path>& shardArgs, const fs::path& outDir) {
    if (shardArgs.empty()) throw Error("merge: no shard folder given");
    // ---- find each shard's store -------------------------------------------------------
    struct Shard {
        fs::path dir;
        ShardIdentity id;
        nlohmann::json ranges;
        std::vector<int> views;
    };
    std::vector<Shard> shards;
    for (const fs::path& arg : shardArgs) {
        std::vector<fs::path> found;
        if (fs::exists(arg / kIdentityFile)) {
            found.push_back(arg);
        } else if (fs::is_directory(arg)) {
            for (const auto& paper : fs::directory_iterator(arg))
                if (paper.is_directory())
                    for (const auto& e : fs::directory_iterator(paper.path()))
                        if (e.path().filename().string().rfind("assets", 0) == 0 &&
                            e.path().extension() != kPartial &&
                            fs::exists(e.path() / kIdentityFile))
                            found.push_back(e.path());
        }
        if (found.size() != 1)
            throw Error("merge: " + arg.string() +
                        (found.empty() ? ": no shard.json there (nor in <paper>/assets*/)"
                                       : ": holds more than one shard (papers or qualities); "
                                         "name its assets folder"));
        const fs::path idFile = found[0] / kIdentityFile;
        const nlohmann::json j = readJson(idFile);
        Shard s{found[0], ShardIdentity::fromJson(j, idFile), j.value("ranges", nlohmann::json::array()),
                finishedViews(found[0])};
        shards.push_back(std::move(s));
    }
    // ---- one identity, made by this code --------------------------------------------------
    const ShardIdentity& id = shards[0].id;
    for (const Shard& s : shards)
        if (const std::string d = id.differenceFrom(s.id); !d.empty())
            throw Error("merge: " + (s.dir / kIdentityFile).string() + " does not belong with " +
                        (shards[0].dir / kIdentityFile).string() + ": " + d);
    if (id.codeVersion != codeVersion())
        throw Error("merge: " + (shards[0].dir / kIdentityFile).string() +
                    ": made by code version " + id.codeVersion + ", this is " + codeVersion() +
                    "; evaluate with the code that made the views");
    // ---- every range finished, no view twice, none missing -----------------------------------
    std::map<int, fs::path> owner;
    for (const Shard& s : shards) {
        for (const auto& r : s.ranges) {
            std::vector<int> unfinished;
            for (int v = r.at(0).get<int>(); v < r.at(1).get<int>(); ++v)
                if (!std::binary_search(s.views.begin(), s.views.end(), v)) unfinished.push_back(v);
            if (!unfinished.empty())
                throw Error("merge: " + s.dir.string() + ": its range " +
                            std::to_string(r.at(0).get<int>()) + ":" +
                            std::to_string(r.at(1).get<int>()) + " did not finish (views " +
                            rangesText(unfinished) + " missing); rerun that task, it resumes");
        }
        for (int v : s.views) {
            if (v >= id.views)
                throw Error("merge: " + (s.dir / viewFolderName(v)).string() +
                            ": outside the precompute's " + std::to_string(id.views) + " views");
            auto [it, fresh] = owner.emplace(v, s.dir / viewFolderName(v));
            if (!fresh)
                throw Error("merge: " + (s.dir / viewFolderName(v)).string() + " is also in " +
                            it->second.string() + " (overlapping or duplicated --views ranges)");
        }
    }
    std::vector<int> missing;
    for (int v = 0; v < id.views; ++v)
        if (!owner.count(v)) missing.push_back(v);
    if (!missing.empty())
        throw Error("merge: views " + rangesText(missing) + " of " + std::to_string(id.views) +
                    " are in none of the shards (a missing --views range)");
    // ---- the paper's shared files agree; every view's files match their checksums ----------
    std::map<std::string, std::string> shared;  // file at the store's top → sha256
    for (const Shard& s : shards)
        for (const auto& e : fs::directory_iterator(s.dir)) {
            const std::string name = e.path().filename().string();
            if (!e.is_regular_file() || name == kIdentityFile) continue;
            const std::string h = sha256OfFile(e.path());
            auto [it, fresh] = shared.emplace(name, h);
            if (!fresh && it->second != h)
                throw Error("merge: " + e.path().string() + " differs from the same file in " +
                            shards[0].dir.string());
        }
    for (const auto& [v, dir] : owner) verifyViewFolder(dir);
    // ---- write: into a temporary folder, renamed into place at the end -----------------------
    const fs::path into = assetsFolder(outDir / id.paper, id.quality);
    if (fs::exists(into))
        throw Error("merge: " + into.string() + " exists; nothing was changed (merge writes a "
                    "new folder and overwrites none)");
    const fs::path tmp = into.string() + kPartial;
    fs::remove_all(tmp);
    fs::create_directories(tmp);  // creates <outDir>/<paper> too
    try {
        for (const auto& e : fs::directory_iterator(shards[0].dir))
            if (e.is_regular_file() && e.path().filename() != kIdentityFile)
                fs::copy_file(e.path(), tmp / e.path().filename());
        for (const auto& [v, dir] : owner)
            fs::copy(dir, tmp / viewFolderName(v), fs::copy_options::recursive);
        nlohmann::json j = id.toJson();
        j["ranges"] = nlohmann::json::array({nlohmann::json::array({0, id.views})});
        writeAtomically(tmp / kIdentityFile, j.dump(2) + "\n");
    } catch (const fs::filesystem_error& e) {
        std::error_code ec;
        fs::remove_all(tmp, ec);
        throw Error("merge: writing " + tmp.string() + ": " + e.what());
    }
    fs::rename(tmp, into);
    return {id.paper, into, int(owner.size())};
}

}  // namespace rg::demos
