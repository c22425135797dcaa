// libFuzzer target: the light-field parameter reader of demos/lightfield
// (rg::lightfield::parseLightFieldParams, the JSON of writeLightField). Every malformed,
// truncated or inconsistent file must raise rg::Error; the data file is never opened.
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.h"
#include "light_slab.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        uint64_t bytes = 0;
        std::string name;
        const rg::lightfield::LightField lf = rg::lightfield::parseLightFieldParams(text, "fuzz input", &bytes, &name);
        // What the reader promised: a validated slab and a size that matches it.
        if (bytes != lf.slab.samples() * uint64_t(lf.channels) || name.empty()) __builtin_trap();
    } catch (const rg::Error&) {
    }
    return 0;
}
