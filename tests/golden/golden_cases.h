// The golden traces: each case builds a small frame through the Device API (or, for the
// programmable profile, the ProgrammableDevice API) with a TraceRecorder attached
// (tests/golden/golden_cases.cpp). `retroglass_golden write`
// regenerates tests/golden/*.trace from them; the suite replays each file and compares
// the SHA-256 of the framebuffer with tests/golden/manifest.txt.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "rasterizer/framebuffer.h"

namespace rg::golden {

struct GoldenCase {
    std::string name;    // the state it covers: the CTest name is golden.<name>
    std::string covers;  // one line for the manifest and the failure message
};

const std::vector<GoldenCase>& goldenCases();
// Registers the programs the programmable golden traces draw with (bench/bench_programs.h):
// call before reading one of them.
void registerGoldenPrograms();
// The trace bytes of case `name` (throws rg::Error for an unknown name). `live`, when
// given, receives the capturing device's framebuffer: what a replay must reproduce.
std::vector<uint8_t> buildGoldenTrace(const std::string& name, raster::Framebuffer* live = nullptr);

}  // namespace rg::golden
