// Image files through OpenImageIO, and the texel lookups the textures and environment use.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "raycore/image.h"

namespace rg::ray {

glm::vec3 Image::rgb(int x, int y) const {
    const float* p = &pixels[(size_t(y) * width + x) * channels];
    if (channels >= 3) return {p[0], p[1], p[2]};
    return glm::vec3(p[0]);
}

void Image::setRgb(int x, int y, glm::vec3 v) {
    float* p = &pixels[(size_t(y) * width + x) * channels];
    if (channels >= 3) {
        p[0] = v.x;
        p[1] = v.y;
        p[2] = v.z;
    } else {
        p[0] = v.x;
    }
}

uint8_t quantize8(float v) {
    if (!(v > 0.0f)) return 0;  // also NaN
    if (v >= 1.0f) return 255;
    return uint8_t(std::lround(v * 255.0f));
}

std::vector<uint8_t> toBytes8(const Image& image) {
    std::vector<uint8_t> out(image.pixels.size());
    for (size_t i = 0; i < out.size(); ++i) out[i] = quantize8(image.pixels[i]);
    return out;
}

Image readImage(const std::filesystem::path& path) {
    const std::string file = path.string();
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) throw Error(file + ": image file not found");
    auto in = OIIO::ImageInput::open(file);
    if (!in) throw Error(file + ": cannot read image (" + OIIO::geterror() + ")");
    const OIIO::ImageSpec& spec = in->spec();
    if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0)
        throw Error(file + ": image has no pixels");
    Image img(spec.width, spec.height, spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, img.pixels.data()))
        throw Error(file + ": cannot decode image (" + in->geterror() + ")");
    in->close();
    return img;
}

void writeImage(const std::filesystem::path& path, const Image& image) {
    const std::string file = path.string();
    if (image.empty()) throw Error(file + ": refusing to write an empty image");
    if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
    auto out = OIIO::ImageOutput::create(file);
    if (!out) throw Error(file + ": no image writer for this extension (" + OIIO::geterror() + ")");
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    const bool floatFormat = ext == ".exr" || ext == ".hdr" || ext == ".pfm";
    if (floatFormat) {
        OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::FLOAT);
        // OpenImageIO's EXR writer stamps the time of writing (capDate) unless DateTime is
        // given; given empty, the stamp is empty: the same image is then the same file
        // bytes, run after run (ImageIO.FilesAreTheSameBytesOnEveryWrite).
        spec.attribute("DateTime", "");
        if (!out->open(file, spec) ||
            !out->write_image(OIIO::TypeDesc::FLOAT, image.pixels.data()))
            throw Error(file + ": cannot write image (" + out->geterror() + ")");
    } else {
        // Our own quantization (quantize8), not OIIO's, so the bytes are pinned.
        std::vector<uint8_t> bytes = toBytes8(image);
        OIIO::ImageSpec spec(image.width, image.height, image.channels, OIIO::TypeDesc::UINT8);
        if (!out->open(file, spec) || !out->write_image(OIIO::TypeDesc::UINT8, bytes.data()))
            throw Error(file + ": cannot write image (" + out->geterror() + ")");
    }
    out->close();
}

glm::vec3 sampleBilinearWrap(const Image& image, glm::vec2 uv, bool clampV) {
    if (image.empty()) return glm::vec3(1.0f, 0.0f, 1.0f);
    float x = uv.x * image.width - 0.5f, y = uv.y * image.height - 0.5f;
    float fx = std::floor(x), fy = std::floor(y);
    float ax = x - fx, ay = y - fy;
    auto wrap = [](long v, int n) { return int(((v % n) + n) % n); };
    int x0 = wrap(long(fx), image.width), x1 = wrap(long(fx) + 1, image.width);
    auto clamp = [](long v, int n) { return int(v < 0 ? 0 : (v >= n ? n - 1 : v)); };
    int y0 = clampV ? clamp(long(fy), image.height) : wrap(long(fy), image.height);
    int y1 = clampV ? clamp(long(fy) + 1, image.height) : wrap(long(fy) + 1, image.height);
    glm::vec3 a = glm::mix(image.rgb(x0, y0), image.rgb(x1, y0), ax);
    glm::vec3 b = glm::mix(image.rgb(x0, y1), image.rgb(x1, y1), ax);
    return glm::mix(a, b, ay);
}

}  // namespace rg::ray
