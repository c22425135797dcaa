#include "figures.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "core/error.h"
#include "rasterizer/framebuffer.h"
#include "report.h"

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

void writeLinePlot(const std::filesystem::path& path, const std::string& title,
                   const std::string& xLabel, const std::string& yLabel,
                   const std::vector<double>& x, const std::vector<Series>& series,
                   bool yFromData) {
    if (x.empty()) throw Error(path.string() + ": a plot needs at least one x value");
    const int W = 560, H = 340, L = 70, R = 20, T = 36, B = 50;
    double ymin = 0, ymax = 0, lo = INFINITY, hi = -INFINITY;
    for (const Series& s : series)
        for (double v : s.y)
            if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
    if (yFromData && lo <= hi) {
        const double pad = hi > lo ? 0.1 * (hi - lo) : 1.0;
        ymin = lo - pad;
        ymax = hi + pad;
    } else {
        ymax = hi > 0 ? hi * 1.1 : 1.0;
    }
    const double xmin = x.front(), xmax = x.back() > x.front() ? x.back() : x.front() + 1;
    auto px = [&](double v) { return L + (v - xmin) / (xmax - xmin) * (W - L - R); };
    auto py = [&](double v) { return H - B - (v - ymin) / (ymax - ymin) * (H - T - B); };
    std::ofstream f(path);
    if (!f) throw Error(path.string() + ": cannot write");
    char b[512];
    f << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
      << "\" font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    f << "<text x=\"" << W / 2 << "\" y=\"20\" text-anchor=\"middle\" font-size=\"14\">" << htmlEscape(title)
      << "</text>\n";
    std::snprintf(b, sizeof b, "<line x1=\"%d\" y1=\"%d\" x2=\"%d\" y2=\"%d\" stroke=\"black\"/>\n", L, H - B, W - R, H - B);
    f << b;
    std::snprintf(b, sizeof b, "<line x1=\"%d\" y1=\"%d\" x2=\"%d\" y2=\"%d\" stroke=\"black\"/>\n", L, T, L, H - B);
    f << b;
    for (double v : x) {
        std::snprintf(b, sizeof b, "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">%g</text>\n", px(v), H - B + 16, v);
        f << b;
    }
    for (int k = 0; k <= 4; ++k) {
        const double v = ymin + (ymax - ymin) * k / 4;
        std::snprintf(b, sizeof b,
                      "<text x=\"%d\" y=\"%.1f\" text-anchor=\"end\">%.3g</text><line x1=\"%d\" y1=\"%.1f\" x2=\"%d\" "
                      "y2=\"%.1f\" stroke=\"#ddd\"/>\n",
                      L - 6, py(v) + 4, v, L, py(v), W - R, py(v));
        f << b;
    }
    f << "<text x=\"" << (L + W - R) / 2 << "\" y=\"" << H - 12 << "\" text-anchor=\"middle\">" << htmlEscape(xLabel)
      << "</text>\n";
    f << "<text x=\"16\" y=\"" << (T + H - B) / 2 << "\" text-anchor=\"middle\" transform=\"rotate(-90 16 " << (T + H - B) / 2
      << ")\">" << htmlEscape(yLabel) << "</text>\n";
    int legend = 0;
    for (const Series& s : series) {
        std::string pts;
        for (size_t i = 0; i < x.size() && i < s.y.size(); ++i) {
            if (!std::isfinite(s.y[i])) continue;
            std::snprintf(b, sizeof b, "%.1f,%.1f ", px(x[i]), py(s.y[i]));
            pts += b;
        }
        f << "<polyline fill=\"none\" stroke=\"" << s.colour << "\" stroke-width=\"2\" points=\"" << pts << "\"/>\n";
        for (size_t i = 0; i < x.size() && i < s.y.size(); ++i)
            if (std::isfinite(s.y[i])) {
                std::snprintf(b, sizeof b, "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"3\" fill=\"%s\"/>\n", px(x[i]), py(s.y[i]),
                              s.colour.c_str());
                f << b;
            }
        std::snprintf(b, sizeof b, "<text x=\"%d\" y=\"%d\" fill=\"%s\">%s</text>\n", W - R - 220, T + 14 + 16 * legend,
                      s.colour.c_str(), htmlEscape(s.name).c_str());
        f << b;
        ++legend;
    }
    f << "</svg>\n";
    if (!f) throw Error(path.string() + ": write failed");
}

}  // namespace rg::demos
