// Registration of the bench workloads' programs and their GLSL twins (bench_programs.h).
#include "bench_programs.h"

#include "binary_search_retroglass.h"
#include "rasterizer/program_registry.h"

namespace rg::bench {

namespace {

// The binary search as the C++ programs compute it: uv from the pixel centre
// (gl_FragCoord.xy / 512, exactly (x + ½)/512), the eight steps of
// bench/binary_search_workload.h. The Mesa player renders with Direct3D's window origin
// (row 0 at the top, as ours), so gl_FragCoord is our fragCoord() and the twin needs no
// flip. The same algorithm as bench/binary_search_mesa.cpp's benchmark shader, which
// takes uv from a varying instead (the GL programmer's way; both are exact here).
raster::GlslTwin binarySearchTwin() {
    raster::GlslTwin t;
    t.vertexShader = R"(#version 130
in vec4 clip;
void main() {
    gl_Position = clip;
}
)";
    t.fragmentShader = R"(#version 130
uniform sampler2D depthTexture;
out vec4 colour;
void main() {
    vec2 uv = gl_FragCoord.xy / 512.0;
    vec3 a = vec3(uv, 0.0);
    vec3 b = vec3(uv + vec2(0.125, 0.0625), 1.0);
    float lo = 0.0, hi = 1.0, d = 0.0;
    for (int step = 0; step < 8; ++step) {
        float mid = 0.5 * (lo + hi);
        vec3 p = a + (b - a) * mid;
        d = textureLod(depthTexture, p.xy, 0.0).r;
        if (p.z > d) hi = mid; else lo = mid;
    }
    colour = vec4(0.5 * (lo + hi), d, 0.0, 1.0);
}
)";
    t.attributes = {{"clip", 4, 0}};  // QuadVertex::clip
    t.samplers = {"depthTexture"};    // unit 0
    t.outputs = {"colour"};           // target 0
    return t;  // no uniforms: QuadVP and the fragment programs are empty types
}

}  // namespace

void registerPrograms() {
    using namespace binary_search;
    static_assert(bs::kWidth == 512 && bs::kHeight == 512 && bs::kSteps == 8,
                  "the GLSL twin spells the workload's constants out");
    raster::registerProgram<QuadVP, BinarySearchQuadFP, QuadVertex>("bench/binary_search");
    raster::registerProgram<QuadVP, BinarySearchFP, QuadVertex>("bench/binary_search_scalar");
    raster::registerGlslTwin("bench/binary_search", binarySearchTwin());
    raster::registerGlslTwin("bench/binary_search_scalar", binarySearchTwin());
}

}  // namespace rg::bench
