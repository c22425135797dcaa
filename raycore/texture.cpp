// Texture evaluation: dispatch to the pattern or the image lookup.
#include "raycore/texture.h"

#include "core/error.h"
#include "raycore/texture_procedural.h"

namespace rg::ray {

glm::vec3 Texture::eval(glm::vec2 uv) const {
    switch (kind) {
        case TextureKind::Checker: return checkerPattern(uv, scale, colorA, colorB);
        case TextureKind::Bricks: return bricksPattern(uv, scale, colorA, colorB);
        case TextureKind::WoodRings: return woodRingsPattern(uv, scale, colorA, colorB);
        case TextureKind::Gradient: return gradientPattern(uv, colorA, colorB);
        case TextureKind::Image:
            return image ? sampleBilinearWrap(*image, uv * scale) : glm::vec3(1, 0, 1);
    }
    return glm::vec3(1, 0, 1);
}

Image bakeTexture(const Texture& t, int width, int height) {
    Image img(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            img.setRgb(x, y, t.eval({(float(x) + 0.5f) / float(width), (float(y) + 0.5f) / float(height)}));
    return img;
}

const char* textureKindName(TextureKind k) {
    switch (k) {
        case TextureKind::Checker: return "checker";
        case TextureKind::Bricks: return "bricks";
        case TextureKind::WoodRings: return "wood";
        case TextureKind::Gradient: return "gradient";
        case TextureKind::Image: return "image";
    }
    return "?";
}

TextureKind textureKindFromName(const std::string& n) {
    for (TextureKind k : {TextureKind::Checker, TextureKind::Bricks, TextureKind::WoodRings,
                          TextureKind::Gradient, TextureKind::Image})
        if (n == textureKindName(k)) return k;
    throw Error("unknown texture kind '" + n + "' (checker, bricks, wood, gradient, image)");
}

}  // namespace rg::ray
