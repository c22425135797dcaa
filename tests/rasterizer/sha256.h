// A small SHA-256 (FIPS 180-4) for golden hashes of raw framebuffer bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace rg::testing {

std::string sha256Hex(const void* data, size_t size);

}  // namespace rg::testing
