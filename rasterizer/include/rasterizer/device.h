// The emulated graphics device: a Direct3D 7-style immediate-mode pipeline on one
// hardware profile, drawing into an RGBA8 framebuffer.
//
//   vertices ─▶ transform (world·view·projection) ─▶ texture-coordinate generation
//            ─▶ clip (near/far; guard band in x/y) ─▶ viewport, snap to fixed point
//            ─▶ setup (edge functions, top-left rule, cull) ─▶ rasterize 2×2 quads
//            ─▶ texture stages (texunit/) ─▶ specular add ─▶ alpha test ─▶ depth test
//            ─▶ blend ─▶ colour write mask ─▶ framebuffer
//
// Every arithmetic step is specified in docs/hardware.md. The reference path runs that
// specification literally on one thread; the fast path bins primitives into screen tiles
// that threads own, keeps each pixel's primitive order, and must produce identical bytes.
#pragma once

#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "core/color.h"
#include "core/path.h"
#include "core/profile.h"
#include "rasterizer/counters.h"
#include "rasterizer/framebuffer.h"
#include "rasterizer/state.h"
#include "rasterizer/vertex.h"
#include "texunit/texture_units.h"

namespace rg::raster {

class TraceRecorder;  // rasterizer/trace.h

struct DeviceOptions {
    Path path = Path::Fast;
    int threads = 0;  // 0: all cores
};

// One entry per Device::beginPass(): what the pass inspector shows.
struct PassRecord {
    std::string label;
    uint64_t drawCalls = 0;
};

class Device {
  public:
    // Throws rg::InvalidState for a zero-size or over-limit framebuffer and
    // rg::UnsupportedFeature for a depth format the profile lacks.
    Device(const Profile& profile, int width, int height, DepthFormat depth,
           DeviceOptions options = {});
    ~Device();
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    const Profile& profile() const;
    const DeviceOptions& options() const;
    void setPath(Path path);
    void setThreads(int threads);

    // ---- state ---------------------------------------------------------------------------
    void setState(const PipelineState& state);  // validated at draw time
    const PipelineState& state() const;
    void setTransforms(const glm::mat4& world, const glm::mat4& view, const glm::mat4& projection);
    const glm::mat4& world() const;
    const glm::mat4& view() const;
    const glm::mat4& projection() const;
    void setViewport(const Viewport& viewport);  // throws for zero size or outside the target
    void setScissor(const Rect& rect);
    const Viewport& viewport() const;
    const Rect& scissor() const;
    // The texture side of the device (stages, bindings, texgen, colour tables, pixel
    // texture). Configure it through texunit's API; it is validated at draw time.
    tex::TextureUnits& textureUnits();
    const tex::TextureUnits& textureUnits() const;

    // ---- frames and passes --------------------------------------------------------------
    void beginFrame();                       // resets the counters and the pass list
    void beginPass(std::string label);       // counts a geometry pass (the papers' unit)
    const std::vector<PassRecord>& passes() const;
    // Optional hook run after each pass ends (next beginPass or endFrame): pass inspector.
    void setPassObserver(std::function<void(const PassRecord&, const Framebuffer&)> observer);
    // Optional instrumentation hook (the PEM rendering matrix): called for every rasterized
    // 2×2 quad with its FragmentQuad (attributes as the texture units saw them) and the
    // mask of pixels that passed the alpha and depth tests and were written. While set,
    // draws rasterize in the reference order on the calling thread, so the calls come in
    // submission order; the bytes are the same as on either path. Empty function: off.
    using FragmentObserver = std::function<void(const tex::FragmentQuad&, uint8_t passed)>;
    void setFragmentObserver(FragmentObserver observer);
    void endFrame();
    // Capture (rasterizer/trace.h, docs/trace-format.md): from now on every command is
    // recorded with the state it reads. Attaching writes the profile, the framebuffer
    // size and its current contents; nullptr detaches (the recorder keeps its bytes).
    void setRecorder(std::shared_ptr<TraceRecorder> recorder);

    // ---- commands -----------------------------------------------------------------------
    // Clears colour and/or depth inside the viewport (and scissor when enabled).
    void clear(bool color, Rgba8 colorValue, bool depth, float depthValue);
    // Draws `count` vertices (indices == empty) or indexed primitives. Invalid vertices
    // (NaN/Inf) drop their triangles and count in trianglesInvalid.
    void draw(Primitive primitive, VertexSpace space, std::span<const Vertex> vertices,
              std::span<const uint32_t> indices = {});
    // The same draw of untransformed D3DFVF_XYZ | D3DFVF_DIFFUSE vertices (toVertex of
    // each): the same bytes and counters, a trace records it as that Vertex draw.
    void draw(Primitive primitive, std::span<const VertexXyzDiffuse> vertices,
              std::span<const uint32_t> indices = {});
    // Pixel transfer: writes `pixels` (width×height, rows top to bottom) at window (x, y)
    // through the pixel-transfer stage (SGIX_pixel_texture when enabled).
    void drawPixels(int x, int y, int width, int height, std::span<const Rgba8> pixels);
    // Copies a window rectangle through the pixel-transfer stage to (dstX, dstY).
    void copyPixels(int srcX, int srcY, int width, int height, int dstX, int dstY);
    // Reads back a rectangle of the colour buffer (counts bytesReadBack).
    std::vector<Rgba8> readPixels(int x, int y, int width, int height);

    // ---- batches -----------------------------------------------------------------------
    // Between beginBatch() and endBatch() draws are checked, counted and recorded as they
    // are issued but not run. On the fast path with more than one thread, endBatch runs the
    // vertex stage and the setup of every queued draw shared over the threads, bins all
    // their triangles into the tiles, and rasterizes each tile's triangles draw by draw in
    // the order issued: three forks and joins for the batch instead of three per draw
    // (llvmpipe defers a frame's draws to its scene the same way). Otherwise the draws run
    // one by one at endBatch. The pixels and counters are those of drawing one by one: a
    // pixel's fragments still meet the blender in submission order (tests/rasterizer,
    // DrawBatch). A batched draw keeps copies of its vertices, indices, state, transforms
    // and texture-unit state; the caller keeps the contents of every texture a draw reads
    // unchanged until endBatch and reads the framebuffer only after it. Inside a batch,
    // clear, the pixel transfers, beginFrame, beginPass, endFrame, attaching a recorder or
    // an observer, setPath, setThreads and a second beginBatch are errors (InvalidState)
    // that leave the batch open. The destructor drops a batch left open.
    void beginBatch();
    void endBatch();
    bool batching() const;

    Framebuffer& framebuffer();
    const Framebuffer& framebuffer() const;
    const Counters& counters() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// A batch for a scope: beginBatch at construction, end() runs it. The destructor runs a
// batch end() did not (the scope left by an exception: the draws issued are not lost) and
// drops any error from it.
class DrawBatch {
  public:
    explicit DrawBatch(Device& device) : device_(device) { device_.beginBatch(); }
    ~DrawBatch() {
        if (device_.batching()) {
            try {
                device_.endBatch();
            } catch (const std::exception&) {
            }
        }
    }
    DrawBatch(const DrawBatch&) = delete;
    DrawBatch& operator=(const DrawBatch&) = delete;
    void end() { device_.endBatch(); }

  private:
    Device& device_;
};

}  // namespace rg::raster
