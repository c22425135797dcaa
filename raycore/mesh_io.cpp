// Mesh files through assimp. assimp is lenient (it happily returns an empty scene for a
// truncated file), so the result is validated here and every failure names the file.
#include "raycore/mesh_io.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <cctype>
#include <cmath>
#include <fstream>
#include <string>

#include "core/error.h"

namespace rg::ray {

Mesh loadMesh(const std::filesystem::path& path) {
    const std::string file = path.string();
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw Error(file + ": mesh file not found");
    if (std::filesystem::file_size(path, ec) == 0) throw Error(file + ": mesh file is empty");
    // assimp 5.2's PLY reader loops forever when the header never ends (found by
    // fuzz/fuzz_mesh_loader.cpp): a PLY file must have its end_header line in the first MiB.
    // The check covers every file assimp may hand to that reader: it accepts any file whose
    // first three bytes are `ply` or `PLY`, whatever follows and whatever the extension (a
    // .gltf that is not glTF falls through to it). STL is the exception: a binary STL's
    // 80-byte header is free text, and assimp's STL importer claims .stl by its extension.
    {
        std::ifstream in(path, std::ios::binary);
        std::string head(4, '\0');
        in.read(head.data(), 4);
        std::string ext = path.extension().string();
        for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
        const bool plyMagic = head.compare(0, 3, "ply") == 0 || head.compare(0, 3, "PLY") == 0;
        if (in.gcount() >= 3 && plyMagic && ext != ".stl") {
            head.resize(1 << 20);
            in.read(head.data() + 4, std::streamsize(head.size() - 4));
            head.resize(4 + size_t(in.gcount()));
            const size_t at = head.find("\nend_header");
            const char after = at == std::string::npos || at + 11 >= head.size() ? '\0' : head[at + 11];
            if (after != '\n' && after != '\r')
                throw Error(file + ": PLY header without an end_header line");
        }
    }
    Assimp::Importer importer;
    // JoinIdenticalVertices rebuilds the shared vertices OBJ faces index (it keeps seams:
    // vertices differing in normal or uv stay apart); GenSmoothNormals only acts where the
    // file has no normals. Malformed files must fail before those steps, which assert
    // (abort) inside assimp on broken input (fuzz/regressions/mesh_loader/): the import
    // runs with ValidateDataStructure alone (face indices past the vertices of a bad OFF),
    // faces without indices (a bad PLY) are refused here, then the steps run as one
    // ReadFile would have run them.
    const aiScene* s = importer.ReadFile(file, aiProcess_ValidateDataStructure);
    if (s && !(s->mFlags & AI_SCENE_FLAGS_INCOMPLETE)) {
        for (unsigned mi = 0; mi < s->mNumMeshes; ++mi)
            for (unsigned f = 0; f < s->mMeshes[mi]->mNumFaces; ++f)
                if (s->mMeshes[mi]->mFaces[f].mNumIndices == 0)
                    throw Error(file + ": face " + std::to_string(f) + " of mesh " +
                                std::to_string(mi) + " has no vertices");
        s = importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                         aiProcess_GenSmoothNormals | aiProcess_SortByPType);
    }
    if (!s || (s->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || s->mNumMeshes == 0)
        throw Error(file + ": cannot read mesh (" +
                    (s ? std::string("no meshes in the file") : std::string(importer.GetErrorString())) +
                    ")");
    Mesh out;
    out.name = path.stem().string();
    out.source = {"file", file, {}};
    for (unsigned mi = 0; mi < s->mNumMeshes; ++mi) {
        const aiMesh* am = s->mMeshes[mi];
        if (!(am->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;  // points, lines
        Mesh part;
        part.name = am->mName.length ? am->mName.C_Str() : "mesh" + std::to_string(mi);
        for (unsigned v = 0; v < am->mNumVertices; ++v) {
            const aiVector3D& p = am->mVertices[v];
            if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
                throw Error(file + ": vertex " + std::to_string(v) + " of mesh '" + part.name +
                            "' has a non-finite (NaN or infinite) position");
            part.positions.push_back({p.x, p.y, p.z});
            if (am->mNormals) {
                glm::vec3 n(am->mNormals[v].x, am->mNormals[v].y, am->mNormals[v].z);
                float len = glm::length(n);
                part.normals.push_back(std::isfinite(len) && len > 0.0f ? n / len
                                                                        : glm::vec3(0, 1, 0));
            }
            if (am->mTextureCoords[0])
                part.uvs.push_back({am->mTextureCoords[0][v].x, am->mTextureCoords[0][v].y});
        }
        for (unsigned f = 0; f < am->mNumFaces; ++f) {
            const aiFace& face = am->mFaces[f];
            if (face.mNumIndices != 3) continue;
            for (int k = 0; k < 3; ++k) {
                if (face.mIndices[k] >= am->mNumVertices)
                    throw Error(file + ": face " + std::to_string(f) + " of mesh '" + part.name +
                                "' uses a vertex that does not exist");
                part.indices.push_back(face.mIndices[k]);
            }
        }
        if (part.indices.empty()) continue;
        completeMesh(part);
        if (out.positions.empty() && s->mNumMeshes == 1) {
            MeshSource src = out.source;
            std::string nm = out.name;
            out = std::move(part);
            out.name = nm;
            out.source = src;
        } else {
            appendMesh(out, part, part.name);
        }
    }
    if (out.indices.empty()) throw Error(file + ": the file has no triangles");
    validateMesh(out, file);
    return out;
}

}  // namespace rg::ray
