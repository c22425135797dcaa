#include "figures.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>

#include "core/error.h"
#include "rasterizer/framebuffer.h"

namespace rg::demos {

ray::Image framebufferImage(const raster::Framebuffer& fb, ray::Image* drawn) {
    ray::Image img(fb.width(), fb.height(), 3);
    if (drawn) *drawn = ray::Image(fb.width(), fb.height(), 1);
    for (int y = 0; y < fb.height(); ++y)
        for (int x = 0; x < fb.width(); ++x) {
            Rgba8 c = fb.pixel(x, y);
            img.setRgb(x, y, glm::vec3(c.r, c.g, c.b) / 255.0f);
            if (drawn) drawn->at(x, y, 0) = c.a > 0 ? 1.0f : 0.0f;
        }
    return img;
}

ray::Image masked(const ray::Image& image, const ray::Image& mask) {
    ray::Image out = image;
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x)
            if (mask.at(x, y, 0) <= 0.0f) out.setRgb(x, y, glm::vec3(0.0f));
    return out;
}

ray::Image hstack(const std::vector<ray::Image>& images, int gap) {
    int w = 0, h = 0;
    for (const auto& im : images) w += im.width + gap, h = std::max(h, im.height);
    ray::Image out(std::max(1, w - gap), std::max(1, h), 3, 1.0f);
    int x0 = 0;
    for (const auto& im : images) {
        for (int y = 0; y < im.height; ++y)
            for (int x = 0; x < im.width; ++x) out.setRgb(x0 + x, y, im.rgb(x, y));
        x0 += im.width + gap;
    }
    return out;
}

ray::Image vstack(const std::vector<ray::Image>& images, int gap) {
    int w = 0, h = 0;
    for (const auto& im : images) h += im.height + gap, w = std::max(w, im.width);
    ray::Image out(std::max(1, w), std::max(1, h - gap), 3, 1.0f);
    int y0 = 0;
    for (const auto& im : images) {
        for (int y = 0; y < im.height; ++y)
            for (int x = 0; x < im.width; ++x) out.setRgb(x, y0 + y, im.rgb(x, y));
        y0 += im.height + gap;
    }
    return out;
}

namespace {

// `text` in black on a white strip `width` × `height` (clipped at the strip's edge).
ray::Image labelStrip(const std::string& text, int width, int height) {
    ray::Image strip(std::max(1, width), height, 3, 1.0f);
    if (text.empty()) return strip;
    OIIO::ImageBuf buf(OIIO::ImageSpec(strip.width, strip.height, 3, OIIO::TypeDesc::FLOAT),
                       strip.pixels.data());
    const int size = std::max(8, height - 5);
    const float black[3] = {0.0f, 0.0f, 0.0f};
    if (!OIIO::ImageBufAlgo::render_text(buf, 2, height - 5, text, size, "DejaVuSans", black))
        throw Error("figure label '" + text + "': cannot render text (" + buf.geterror() +
                    "); the DejaVu fonts (Debian package fonts-dejavu-core) are needed");
    return strip;
}

}  // namespace

ray::Image labelledGrid(const std::vector<Cell>& cells, int columns, int labelHeight) {
    if (columns < 1) throw Error("labelled grid: columns must be at least 1");
    std::vector<ray::Image> rows;
    for (size_t i = 0; i < cells.size(); i += size_t(columns)) {
        std::vector<ray::Image> row;
        for (size_t j = i; j < std::min(cells.size(), i + size_t(columns)); ++j)
            row.push_back(vstack({labelStrip(cells[j].label, cells[j].image.width, labelHeight),
                                  cells[j].image},
                                 0));
        rows.push_back(hstack(row, 6));
    }
    return vstack(rows, 6);
}

}  // namespace rg::demos
