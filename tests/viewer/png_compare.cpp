// viewer_png_compare A.png B.png [--rgb] [--crop W H]
// viewer_png_compare A.png --raw B.rgba W H
// Exit 0 when the 8-bit pixels are equal: all channels (RGBA), or RGB only with --rgb,
// over the top-left W×H of both with --crop. Alpha is read unassociated, so the bytes are
// the file's bytes. With --raw, B is bare RGBA8 bytes of W×H (what `retroglass replay
// --raw` writes), and the counts of pixels with alpha 0, 255 and in between are printed.
// Prints the first differing pixel otherwise (exit 1); 2 on bad input.
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

struct Pixels {
    int width = 0, height = 0, channels = 0;
    std::vector<unsigned char> data;
};

bool load(const char* path, Pixels& p) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(path, &config);
    if (!in) {
        std::fprintf(stderr, "cannot read %s: %s\n", path, OIIO::geterror().c_str());
        return false;
    }
    const OIIO::ImageSpec& s = in->spec();
    p.width = s.width, p.height = s.height, p.channels = s.nchannels;
    p.data.resize(size_t(p.width) * p.height * p.channels);
    bool ok = in->read_image(0, 0, 0, p.channels, OIIO::TypeDesc::UINT8, p.data.data());
    in->close();
    return ok;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr, "usage: %s A.png B.png [--rgb] [--crop W H]\n", argv[0]);
        return 2;
    }
    bool rgb = false;
    int cw = -1, ch = -1;
    if (argc == 6 && !std::strcmp(argv[2], "--raw")) {
        Pixels a, b;
        if (!load(argv[1], a)) return 2;
        b.width = std::atoi(argv[4]), b.height = std::atoi(argv[5]), b.channels = 4;
        FILE* f = std::fopen(argv[3], "rb");
        if (!f) return std::fprintf(stderr, "cannot read %s\n", argv[3]), 2;
        b.data.resize(size_t(b.width) * size_t(b.height) * 4);
        const size_t got = std::fread(b.data.data(), 1, b.data.size(), f);
        const bool more = std::fgetc(f) != EOF;
        std::fclose(f);
        if (got != b.data.size() || more)
            return std::fprintf(stderr, "%s: not %dx%d RGBA8 bytes\n", argv[3], b.width, b.height), 1;
        if (a.width != b.width || a.height != b.height || a.channels != 4)
            return std::fprintf(stderr, "%s is %dx%dx%d, not %dx%dx4\n", argv[1], a.width, a.height, a.channels,
                                b.width, b.height), 1;
        long zero = 0, full = 0, partial = 0, differing = 0;
        for (size_t i = 0; i < b.data.size(); i += 4) {
            const int alpha = b.data[i + 3];
            (alpha == 0 ? zero : alpha == 255 ? full : partial)++;
            for (int c = 0; c < 4; ++c)
                if (a.data[i + size_t(c)] != b.data[i + size_t(c)] && differing++ == 0)
                    std::fprintf(stderr, "first difference at pixel %zu channel %d: %d vs %d (alpha %d)\n", i / 4, c,
                                 a.data[i + size_t(c)], b.data[i + size_t(c)], alpha);
        }
        std::printf("alpha 0: %ld, 255: %ld, between: %ld pixels\n", zero, full, partial);
        if (differing) return std::fprintf(stderr, "%ld channel values differ\n", differing), 1;
        std::printf("equal: %s holds the bytes of %s\n", argv[1], argv[3]);
        return 0;
    }
    for (int i = 3; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--rgb")) rgb = true;
        else if (!std::strcmp(argv[i], "--crop") && i + 2 < argc) cw = std::atoi(argv[i + 1]), ch = std::atoi(argv[i + 2]), i += 2;
        else return std::fprintf(stderr, "unknown argument %s\n", argv[i]), 2;
    }
    Pixels a, b;
    if (!load(argv[1], a) || !load(argv[2], b)) return 2;
    const int w = cw > 0 ? cw : a.width, h = ch > 0 ? ch : a.height;
    if (w > a.width || w > b.width || h > a.height || h > b.height) {
        std::fprintf(stderr, "sizes: %s %dx%d, %s %dx%d, compared %dx%d\n", argv[1], a.width,
                     a.height, argv[2], b.width, b.height, w, h);
        return 1;
    }
    const int n = rgb ? 3 : 4;
    if (a.channels < n || b.channels < n) {
        std::fprintf(stderr, "need %d channels (have %d and %d)\n", n, a.channels, b.channels);
        return 1;
    }
    long differing = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < n; ++c) {
                int va = a.data[(size_t(y) * a.width + x) * a.channels + c];
                int vb = b.data[(size_t(y) * b.width + x) * b.channels + c];
                if (va != vb && differing++ == 0)
                    std::fprintf(stderr, "first difference at (%d, %d) channel %d: %d vs %d\n", x, y, c, va, vb);
            }
    if (differing) {
        std::fprintf(stderr, "%ld channel values differ over %dx%d\n", differing, w, h);
        return 1;
    }
    std::printf("equal: %s and %s over %dx%d, %s\n", argv[1], argv[2], w, h, rgb ? "RGB" : "RGBA");
    return 0;
}
