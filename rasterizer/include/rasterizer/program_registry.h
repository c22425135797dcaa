// Programs registered by name, so that a trace can name the program a draw ran
// (docs/trace-format.md, version 2) and a player can run it again.
//
// A programmable draw is `device.draw(vp, fp, primitive, vertices, indices)` with C++
// types for the vertex program, the fragment program and the vertex (program.h). A trace
// cannot hold code, so each (VP, FP, V) triple a trace may contain is registered once
// under a stable name by the module that owns the types:
//
//   void registerPrograms() {  // the module's registration function, called at startup
//       rg::raster::registerProgram<QuadVP, BinarySearchQuadFP, QuadVertex>("bench/binary_search");
//   }
//
// A registered program's objects are trivially copyable, so their bytes are their
// constants and uniforms: the recorder stores the vertex program's, the fragment
// program's and the vertices' bytes, and the player rebuilds the objects from them and
// draws through the function registration instantiated for the triple. A program type
// must therefore hold its uniforms by value (no pointers: a pointer's bytes mean nothing
// in another process) and should have no padding (padding bytes are recorded as they are,
// which makes two captures of one frame differ in bytes though they replay the same).
// An empty program type is recorded as zero bytes.
//
// A program may also have a GLSL twin registered under the same name (registerGlslTwin):
// the same computation written for OpenGL 3.0, which `retroglass replay --backend mesa`,
// `retroglass conform` and `retroglass bench --trace` run on llvmpipe
// (conformance/mesa_program_player.cpp). The twin is data here; nothing in rasterizer/
// compiles it.
//
// Who calls the registration functions: `retroglass` at startup (demos/cli/main.cpp,
// registerTracePrograms: the bench workloads' programs and every Reproduction's
// registerPrograms()), and any tool that reads programmable traces (tests, fuzz target).
// Registering the same triple under the same name again is a no-op, so registration
// functions may be called more than once.
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <new>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <typeindex>
#include <typeinfo>
#include <vector>

#include "rasterizer/programmable_device.h"

namespace rg::raster {

// Draws with a registered program from recorded bytes: the vertex and fragment program
// objects' bytes (empty for an empty type), vertexCount · sizeof(V) bytes of vertices, the
// indices (empty: not indexed). Sizes are checked by the trace reader before this runs.
using RecordedDrawFn = void (*)(ProgrammableDevice& device, std::span<const uint8_t> vertexProgram,
                                std::span<const uint8_t> fragmentProgram, ProgramPrimitive primitive,
                                std::span<const uint8_t> vertices, std::span<const uint32_t> indices);

struct RegisteredProgram {
    std::string name;           // what traces store
    std::type_index key;        // typeid(detail::ProgramTriple<VP, FP, V>)
    std::string types;          // "VP, FP, V" as the compiler names them, for messages
    uint32_t vertexProgramBytes = 0;    // sizeof(VP), 0 for an empty type
    uint32_t fragmentProgramBytes = 0;  // sizeof(FP), 0 for an empty type
    uint32_t vertexBytes = 0;           // sizeof(V): the stride of a draw's vertices
    uint32_t units = 0;                 // FP::kUnits | VP::kVertexUnits: the texture units a draw reads
    uint32_t targets = 0;               // FP::kTargets
    RecordedDrawFn draw = nullptr;
};

// The uniforms of a GLSL twin, set by the twin's `uniforms` function from the recorded
// program bytes. The Mesa player implements it with glUniform* on the linked program; a
// name the linked program does not have (optimised out) is ignored, as GL does.
class GlslUniforms {
  public:
    virtual ~GlslUniforms() = default;
    // float, vec2, vec3 or vec4 (components 1 to 4); `values` holds count · components.
    virtual void setFloat(std::string_view name, int components, std::span<const float> values) = 0;
    virtual void setInt(std::string_view name, std::span<const int32_t> values) = 0;
    // mat4, column-major as glm stores it (16 floats per matrix).
    virtual void setMat4(std::string_view name, std::span<const float> values) = 0;
};

// One vertex input of the twin: `components` floats at byte `offset` of the vertex type.
struct GlslAttribute {
    std::string name;
    int components = 4;
    uint32_t offset = 0;
};

// The GLSL 1.30 twin of a registered program. The Mesa player renders with Direct3D's
// conventions (glClipControl(GL_UPPER_LEFT, GL_ZERO_TO_ONE)), so window row 0 is the top
// row as on ours, gl_FragCoord is our fragCoord() and clip z runs from 0 to w: a twin
// computes exactly what the C++ program computes, with no flips of its own.
struct GlslTwin {
    std::string vertexShader;    // "#version 130" ...
    std::string fragmentShader;
    std::vector<GlslAttribute> attributes;  // bound to locations 0, 1, ... in this order
    std::vector<std::string> samplers;      // sampler uniform of unit i ("" for none)
    std::vector<bool> compareSamplers;      // unit i is a shadow sampler (sampleCompare)
    std::vector<std::string> outputs;       // fragment output of target k
    // Sets the uniforms standing for the program objects' bytes; empty when none.
    std::function<void(std::span<const uint8_t> vertexProgram, std::span<const uint8_t> fragmentProgram,
                       GlslUniforms& uniforms)>
        uniforms;
};

namespace detail {

template <class T>
constexpr uint32_t kRecordedBytes = std::is_empty_v<T> ? 0u : uint32_t(sizeof(T));

// A program object from its recorded bytes. An empty type's one byte is zero.
template <class T>
T fromRecordedBytes(std::span<const uint8_t> bytes) {
    std::array<std::byte, sizeof(T)> raw{};
    // An empty type's bytes are an empty span, whose data() may be null: no memcpy then.
    if (!bytes.empty()) std::memcpy(raw.data(), bytes.data(), std::min(bytes.size(), sizeof(T)));
    return std::bit_cast<T>(raw);
}

// The vertices of a recorded draw in storage aligned for V (the trace's bytes are not).
template <class V>
class RecordedVertices {
  public:
    explicit RecordedVertices(std::span<const uint8_t> bytes) : count_(bytes.size() / sizeof(V)) {
        storage_ = ::operator new(std::max<size_t>(bytes.size(), 1), std::align_val_t{alignof(V)});
        if (!bytes.empty()) std::memcpy(storage_, bytes.data(), bytes.size());
    }
    ~RecordedVertices() { ::operator delete(storage_, std::align_val_t{alignof(V)}); }
    RecordedVertices(const RecordedVertices&) = delete;
    RecordedVertices& operator=(const RecordedVertices&) = delete;
    std::span<const V> span() const { return {std::launder(static_cast<const V*>(storage_)), count_}; }

  private:
    void* storage_ = nullptr;
    size_t count_ = 0;
};

template <class VP, class FP, class V>
void drawRecorded(ProgrammableDevice& device, std::span<const uint8_t> vertexProgram,
                  std::span<const uint8_t> fragmentProgram, ProgramPrimitive primitive,
                  std::span<const uint8_t> vertices, std::span<const uint32_t> indices) {
    const VP vp = fromRecordedBytes<VP>(vertexProgram);
    const FP fp = fromRecordedBytes<FP>(fragmentProgram);
    const RecordedVertices<V> v(vertices);
    device.draw(vp, fp, primitive, v.span(), indices);
}

// "VP, FP, V" demangled where the compiler allows.
std::string programTypeNames(const std::type_info& vp, const std::type_info& fp, const std::type_info& v);
// A program triple's key as the compiler names it, demangled ("...ProgramTriple<VP, FP, V>").
std::string programKeyName(std::type_index key);

const RegisteredProgram& addProgram(RegisteredProgram program);

}  // namespace detail

// Registers the triple under `name` (1 to 255 bytes of [a-z0-9_/.-]). Throws rg::Error
// when the name is taken by another triple, or the triple has another name.
template <class VP, class FP, class V>
const RegisteredProgram& registerProgram(std::string name) {
    static_assert(std::is_trivially_copyable_v<VP> && std::is_trivially_copyable_v<FP>,
                  "a registered program's bytes are its uniforms: it must be trivially copyable");
    static_assert(std::is_trivially_copyable_v<V>, "a registered program's vertex type must be trivially copyable");
    static_assert(sizeof(VP) < (1u << 24) && sizeof(FP) < (1u << 24) && sizeof(V) < (1u << 24),
                  "program and vertex objects are recorded with 32-bit sizes");
    RegisteredProgram p{std::move(name),
                        std::type_index(typeid(detail::ProgramTriple<VP, FP, V>)),
                        detail::programTypeNames(typeid(VP), typeid(FP), typeid(V)),
                        detail::kRecordedBytes<VP>,
                        detail::kRecordedBytes<FP>,
                        uint32_t(sizeof(V)),
                        FP::kUnits | detail::vertexUnitsOf<VP>(),
                        FP::kTargets,
                        &detail::drawRecorded<VP, FP, V>};
    return detail::addProgram(std::move(p));
}

// nullptr when nothing is registered under that name / for that triple.
const RegisteredProgram* findProgram(std::string_view name);
const RegisteredProgram* findProgram(std::type_index key);
// Every registered name, sorted.
std::vector<std::string> registeredProgramNames();

// The GLSL twin of the program registered (or to be registered) under `name`. Registering
// a second twin under one name is an error unless it is the same sources.
void registerGlslTwin(const std::string& name, GlslTwin twin);
const GlslTwin* findGlslTwin(std::string_view name);

}  // namespace rg::raster
