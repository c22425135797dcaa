// libFuzzer target: the mesh loaders rg::ray::loadMesh (assimp: OBJ, PLY, STL, OFF, glTF).
// The first byte picks the file extension, the rest is the file. Malformed files must
// raise rg::Error. loadMesh takes a path, so the input goes through a per-process
// temporary file.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "raycore/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    static const char* kExt[] = {".obj", ".ply", ".stl", ".off", ".gltf"};
    const std::filesystem::path file = std::filesystem::temp_directory_path() /
        ("retroglass-fuzz-mesh-" + std::to_string(::getpid()) + kExt[data[0] % 5]);
    {
        std::ofstream f(file, std::ios::binary | std::ios::trunc);
        f.write(reinterpret_cast<const char*>(data + 1), std::streamsize(size - 1));
    }
    try {
        (void)rg::ray::loadMesh(file);
    } catch (const rg::Error&) {
    }
    std::error_code ec;
    std::filesystem::remove(file, ec);
    return 0;
}
