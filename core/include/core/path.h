// Which implementation of an emulated stage runs: the plain scalar reference that reads
// like docs/hardware.md, or the fast path (binning, tiles, threads, SIMD). The two must
// give the same bytes; tests compare them under random input.
#pragma once

#include <string_view>

namespace rg {

enum class Path { Reference, Fast };

inline std::string_view pathName(Path p) { return p == Path::Reference ? "reference" : "fast"; }

}  // namespace rg
