// Clears and pixel transfers (docs/hardware.md, "Framebuffer and pixel transfer").
#include <cstring>
#include <iterator>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/error.h"
#include "device_impl.h"
#include "rasterizer/trace.h"
#include "rasterizer/device.h"
#include "rasterizer/fragment_ops.h"
#include "core/tsan_annotations.h"

namespace rg::raster {

namespace {

// Rectangle ∩ target; false when empty. int64 so that no corner can overflow.
bool clipRect(const Framebuffer& fb, int64_t& x0, int64_t& y0, int64_t& x1, int64_t& y1) {
    x0 = std::max<int64_t>(x0, 0);
    y0 = std::max<int64_t>(y0, 0);
    x1 = std::min<int64_t>(x1, fb.width());
    y1 = std::min<int64_t>(y1, fb.height());
    return x0 < x1 && y0 < y1;
}

void checkSize(const char* what, int width, int height) {
    if (width < 0 || height < 0)
        throw InvalidState(std::string(what) + " size " + std::to_string(width) + "x" +
                           std::to_string(height) + " is negative");
}

}  // namespace

// IDirect3DDevice7::Clear: the viewport rectangle, further limited by the scissor when
// the scissor test is on. Colour is written whole (D3D7 Clear ignores the write mask);
// depth is quantized like a fragment's.
void Device::clear(bool color, Rgba8 colorValue, bool depth, float depthValue) {
    impl_->notInBatch("clear");
    if (impl_->recorder) impl_->recorder->clear(*this, color, colorValue, depth, depthValue);
    if (depth && !(depthValue >= 0.0f && depthValue <= 1.0f))
        throw InvalidState("depth clear value " + std::to_string(depthValue) +
                           " is not inside [0, 1]");
    Framebuffer& fb = framebuffer();
    const Viewport& vp = impl_->viewport;
    int64_t x0 = vp.x, y0 = vp.y, x1 = int64_t(vp.x) + vp.width, y1 = int64_t(vp.y) + vp.height;
    if (state().scissorTest) {
        const Rect& s = impl_->scissor;
        x0 = std::max<int64_t>(x0, s.x);
        y0 = std::max<int64_t>(y0, s.y);
        x1 = std::min<int64_t>(x1, int64_t(s.x) + s.width);
        y1 = std::min<int64_t>(y1, int64_t(s.y) + s.height);
    }
    if (!clipRect(fb, x0, y0, x1, y1)) return;
    const bool hasDepth = depth && fb.depthFormat() != DepthFormat::None;
    const uint32_t z = hasDepth ? quantizeDepth(depthValue, fb.depthMax()) : 0;
    // The colour as a 32-byte block of eight pixels, copied whole: std::fill of the
    // four-byte struct compiled to byte stores, five instructions a pixel (measured).
    Rgba8 block[8];
    std::fill(std::begin(block), std::end(block), colorValue);
    auto fillColor = [&](Rgba8* p, int64_t n) {
        for (; n >= 8; n -= 8, p += 8) std::memcpy(p, block, sizeof block);
        std::memcpy(p, block, size_t(n) * sizeof(Rgba8));
    };
    auto clearRows = [&](int64_t ya, int64_t yb) {
        for (int64_t y = ya; y < yb; ++y) {
            const size_t row = size_t(y) * size_t(fb.width());
            if (color) fillColor(fb.color().data() + row + x0, x1 - x0);
            if (hasDepth)
                std::fill(fb.depth().begin() + row + x0, fb.depth().begin() + row + x1, z);
        }
    };
    // A whole target's clear is a memory-bound fill that the threads share by rows (each
    // row written by one of them, the same bytes in any order); a small one is not worth
    // waking them.
    constexpr int64_t kParallelPixels = 1 << 16;
    tbb::task_arena& arena = *impl_->arena;
    if (arena.max_concurrency() == 1 || (x1 - x0) * (y1 - y0) < kParallelPixels) {
        clearRows(y0, y1);
        return;
    }
    [[maybe_unused]] int forkJoin = 0;  // the address TSan's fork/join edges name
    RG_TSAN_RELEASE(&forkJoin);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int64_t>(y0, y1, 16),
                          [&](const tbb::blocked_range<int64_t>& r) {
                              RG_TSAN_ACQUIRE(&forkJoin);
                              clearRows(r.begin(), r.end());
                              RG_TSAN_RELEASE(&forkJoin);
                          });
    });
    RG_TSAN_ACQUIRE(&forkJoin);
}

// glDrawPixels at window (x, y), rows top to bottom, through the pixel-transfer stage;
// pixels outside the target are discarded (the raster position is inside it or the
// draw is clipped, as glDrawPixels clips fragments to the window).
void Device::drawPixels(int x, int y, int width, int height, std::span<const Rgba8> pixels) {
    impl_->notInBatch("drawPixels");
    if (impl_->recorder) impl_->recorder->drawPixels(*this, x, y, width, height, pixels);
    checkSize("drawPixels", width, height);
    if (pixels.size() != size_t(width) * size_t(height))
        throw InvalidState("drawPixels: " + std::to_string(pixels.size()) + " pixels for a " +
                           std::to_string(width) + "x" + std::to_string(height) + " rectangle");
    Framebuffer& fb = framebuffer();
    const tex::TextureUnits& units = textureUnits();
    if (units.pixelTexture().enabled) units.validatePixelTexture(profile());
    const Path path = impl_->options.path;
    // Rows of the target the rectangle meets; each row is transferred and written alone.
    const int64_t j0 = std::max<int64_t>(0, -int64_t(y)), j1 = std::min<int64_t>(height, int64_t(fb.height()) - y);
    const int64_t i0 = std::max<int64_t>(0, -int64_t(x)), i1 = std::min<int64_t>(width, int64_t(fb.width()) - x);
    if (j0 >= j1 || i0 >= i1) return;
    auto transferRows = [&](int64_t ja, int64_t jb) {
        std::vector<Rgba8> row(static_cast<size_t>(i1 - i0));
        for (int64_t j = ja; j < jb; ++j) {
            // Pixels outside the target are discarded before the transfer: no fragment, no
            // lookup (GL clips draw-pixels fragments to the window).
            std::copy(pixels.begin() + size_t(j) * width + i0, pixels.begin() + size_t(j) * width + i1,
                      row.begin());
            units.applyPixelTransfer(row, path);
            std::copy(row.begin(), row.end(), &fb.pixel(int(x + i0), int(y + j)));
        }
    };
    // The reference path: one thread, the rows in order. The fast path shares the rows out
    // (each written by one thread; every pixel's arithmetic is its own, so the bytes do not
    // depend on the thread count: PixelTransfer.FastPathAnyThreadCountEqualsReference).
    constexpr int64_t kParallelPixels = 1 << 14;
    tbb::task_arena& arena = *impl_->arena;
    if (path == Path::Reference || arena.max_concurrency() == 1 ||
        (j1 - j0) * (i1 - i0) < kParallelPixels) {
        transferRows(j0, j1);
        return;
    }
    [[maybe_unused]] int forkJoin = 0;
    RG_TSAN_RELEASE(&forkJoin);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<int64_t>(j0, j1, 8),
                          [&](const tbb::blocked_range<int64_t>& r) {
                              RG_TSAN_ACQUIRE(&forkJoin);
                              transferRows(r.begin(), r.end());
                              RG_TSAN_RELEASE(&forkJoin);
                          });
    });
    RG_TSAN_ACQUIRE(&forkJoin);
}

// glCopyPixels: the source is read whole first, so overlapping rectangles copy as if
// through a temporary buffer (the OpenGL 1.2 definition: read, then draw).
void Device::copyPixels(int srcX, int srcY, int width, int height, int dstX, int dstY) {
    impl_->notInBatch("copyPixels");
    checkSize("copyPixels", width, height);
    const Framebuffer& fb = framebuffer();
    if (srcX < 0 || srcY < 0 || int64_t(srcX) + width > fb.width() ||
        int64_t(srcY) + height > fb.height())
        throw InvalidState("copyPixels source rectangle lies outside the render target");
    std::vector<Rgba8> src(size_t(width) * size_t(height));
    for (int j = 0; j < height; ++j)
        for (int i = 0; i < width; ++i) src[size_t(j) * width + i] = fb.pixel(srcX + i, srcY + j);
    // Captured as one CopyPixels, not as the drawPixels it is made of.
    std::shared_ptr<TraceRecorder> recorder = std::move(impl_->recorder);
    if (recorder) recorder->copyPixels(*this, srcX, srcY, width, height, dstX, dstY);
    struct Restore {
        std::shared_ptr<TraceRecorder>& slot;
        std::shared_ptr<TraceRecorder>& saved;
        ~Restore() { slot = std::move(saved); }
    } restore{impl_->recorder, recorder};
    drawPixels(dstX, dstY, width, height, src);
}

std::vector<Rgba8> Device::readPixels(int x, int y, int width, int height) {
    impl_->notInBatch("readPixels");
    checkSize("readPixels", width, height);
    const Framebuffer& fb = framebuffer();
    if (x < 0 || y < 0 || int64_t(x) + width > fb.width() || int64_t(y) + height > fb.height())
        throw InvalidState("readPixels rectangle (" + std::to_string(x) + ", " +
                           std::to_string(y) + ") " + std::to_string(width) + "x" +
                           std::to_string(height) + " lies outside the render target");
    std::vector<Rgba8> out(size_t(width) * size_t(height));
    for (int j = 0; j < height && width > 0; ++j)
        std::copy_n(&fb.pixel(x, y + j), width, out.begin() + size_t(j) * width);
    impl_->counters.bytesReadBack += out.size() * sizeof(Rgba8);
    if (impl_->recorder) impl_->recorder->readPixels(x, y, width, height, out);
    return out;
}

}  // namespace rg::raster
