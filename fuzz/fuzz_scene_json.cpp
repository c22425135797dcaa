// libFuzzer target: the scene-format reader rg::ray::parseSceneJson (docs/scene-format.md).
// Bad JSON and bad values must raise rg::Error. File references resolve against a folder
// that does not exist, so the target never reads the disk.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/error.h"
#include "raycore/scene_json.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    std::vector<std::string> warnings;
    try {
        (void)rg::ray::parseSceneJson(text, "/nonexistent-retroglass-fuzz", "fuzz input", &warnings);
    } catch (const rg::Error&) {
    }
    return 0;
}
