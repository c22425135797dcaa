// cgal:NAME meshes (cgal_meshes.h), read from the installed libcgal-demo archive with
// libarchive.
#include "raycore/cgal_meshes.h"

#include <archive.h>
#include <archive_entry.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <vector>

#include "core/error.h"
#include "raycore/mesh_io.h"

namespace fs = std::filesystem;

namespace rg::ray {

namespace {

fs::path cacheDir() {
    if (const char* x = std::getenv("XDG_CACHE_HOME"); x && *x) return fs::path(x) / "retroglass" / "cgal";
    if (const char* h = std::getenv("HOME"); h && *h) return fs::path(h) / ".cache" / "retroglass" / "cgal";
    return fs::temp_directory_path() / ("retroglass-cgal-" + std::to_string(::getuid()));
}

// The member's bytes, or an error naming what is missing.
std::vector<char> extractMember(const fs::path& archivePath, const std::string& member) {
    std::unique_ptr<archive, int (*)(archive*)> a(archive_read_new(), archive_read_free);
    archive_read_support_filter_all(a.get());
    archive_read_support_format_all(a.get());
    if (archive_read_open_filename(a.get(), archivePath.c_str(), 1 << 16) != ARCHIVE_OK)
        throw Error(archivePath.string() + ": cannot read (" + archive_error_string(a.get()) + ")");
    archive_entry* entry = nullptr;
    int rc;
    while ((rc = archive_read_next_header(a.get(), &entry)) == ARCHIVE_OK) {
        if (member != archive_entry_pathname(entry)) continue;
        std::vector<char> bytes;
        char buf[1 << 16];
        la_ssize_t n;
        while ((n = archive_read_data(a.get(), buf, sizeof buf)) > 0) bytes.insert(bytes.end(), buf, buf + n);
        if (n < 0) throw Error(archivePath.string() + ": " + member + ": " + archive_error_string(a.get()));
        return bytes;
    }
    if (rc != ARCHIVE_EOF)
        throw Error(archivePath.string() + ": corrupt archive (" + archive_error_string(a.get()) + ")");
    return {};
}

}  // namespace

fs::path cgalDataArchive() {
    if (const char* p = std::getenv("RETROGLASS_CGAL_DATA"); p && *p) return p;
    return "/usr/share/doc/libcgal-dev/data.tar.gz";
}

Mesh loadCgalMesh(const std::string& name) {
    if (name.empty() || name.find('/') != std::string::npos || name.find("..") != std::string::npos)
        throw Error("cgal:" + name + ": not a mesh name (e.g. cgal:armadillo)");
    const fs::path cached = cacheDir() / (name + ".off");
    std::error_code ec;
    if (!fs::exists(cached, ec)) {
        const fs::path archivePath = cgalDataArchive();
        if (!fs::exists(archivePath, ec))
            throw Error("cgal:" + name + ": " + archivePath.string() +
                        " is missing; install Debian's libcgal-demo package (./retroglass "
                        "installs it), or set RETROGLASS_CGAL_DATA to CGAL's data.tar.gz");
        const std::vector<char> bytes = extractMember(archivePath, "data/meshes/" + name + ".off");
        if (bytes.empty())
            throw Error("cgal:" + name + ": no data/meshes/" + name + ".off in " + archivePath.string());
        fs::create_directories(cached.parent_path());
        // Written beside and renamed: a concurrent reader sees the whole file or none.
        const fs::path part = cached.string() + "." + std::to_string(::getpid()) + ".part";
        {
            std::ofstream f(part, std::ios::binary);
            f.write(bytes.data(), std::streamsize(bytes.size()));
            if (!f.flush()) throw Error(part.string() + ": cannot write the extracted mesh");
        }
        fs::rename(part, cached);
    }
    Mesh m = loadMesh(cached);
    m.name = name;
    m.source = {"file", "cgal:" + name, {}};
    return m;
}

int fillHoles(Mesh& mesh) {
    // Directed edges; a boundary edge a→b has no b→a.
    std::map<std::pair<uint32_t, uint32_t>, int> edges;
    const size_t triangles = mesh.triangleCount();
    for (size_t t = 0; t < triangles; ++t)
        for (int e = 0; e < 3; ++e)
            ++edges[{mesh.indices[3 * t + size_t(e)], mesh.indices[3 * t + size_t((e + 1) % 3)]}];
    // The hole's polygon runs against the boundary: next[b] = a for each boundary edge a→b.
    std::map<uint32_t, uint32_t> next;
    for (const auto& [e, count] : edges)
        if (!edges.count({e.second, e.first})) next[e.second] = e.first;
    int added = 0;
    while (!next.empty()) {
        std::vector<uint32_t> loop{next.begin()->first};
        for (;;) {
            auto it = next.find(loop.back());
            if (it == next.end()) break;  // an open chain (non-manifold boundary): fan what we have
            const uint32_t v = it->second;
            next.erase(it);
            if (v == loop.front()) break;
            loop.push_back(v);
        }
        for (size_t i = 1; i + 1 < loop.size(); ++i) {
            mesh.indices.insert(mesh.indices.end(), {loop[0], loop[i], loop[i + 1]});
            ++added;
        }
    }
    if (added && !mesh.parts.empty()) mesh.parts.back().triangleCount += uint32_t(added);
    return added;
}

}  // namespace rg::ray
