// Surface textures: procedural patterns (texture_procedural.cpp) and images
// (texture_image.cpp), all evaluated at a surface uv and returning linear RGB.
#pragma once

#include <glm/glm.hpp>

#include <memory>
#include <string>

#include "raycore/image.h"

namespace rg::ray {

enum class TextureKind { Checker, Bricks, WoodRings, Gradient, Image };

struct Texture {
    std::string name;
    TextureKind kind = TextureKind::Checker;
    glm::vec3 colorA{0.9f}, colorB{0.1f};  // checker squares; brick/mortar; light/dark wood;
                                           // gradient start/end
    float scale = 8.0f;                    // pattern repetitions per uv unit
    std::string path;                      // Image: the file, as written in the scene
    std::shared_ptr<const Image> image;    // Image: loaded pixels

    glm::vec3 eval(glm::vec2 uv) const;
};

// The texture sampled at texel centres over uv ∈ [0,1]² (v = 0 the top row): what the
// rasterizer demos upload to draw the same surfaces the ray tracer sees.
Image bakeTexture(const Texture& t, int width, int height);

const char* textureKindName(TextureKind k);
// Raises rg::Error for an unknown name.
TextureKind textureKindFromName(const std::string& name);

}  // namespace rg::ray
