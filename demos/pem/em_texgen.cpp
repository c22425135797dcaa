#include "em_texgen.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <tbb/parallel_for.h>

#include "raycore/image.h"

namespace rg::pem {

void generateEmTexCoords(const PemPart& part, const glm::vec3& eye, EmTexCoords& out) {
    size_t n = part.positions.size();
    out.local.resize(n);
    out.distant.resize(n);
    out.infinite.resize(n);
    out.fresnel.resize(n);
    std::vector<uint8_t> escaped(n, 0);
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
        const glm::vec3 p = part.positions[i];
        glm::vec3 nrm = part.normals[i];
        glm::vec3 v = glm::normalize(p - eye);
        float vn = glm::dot(v, nrm);
        // Two-sided: a normal facing away from the eye is flipped (the teapot is not closed
        // under the lid; the ray tracer shades the side the ray arrives on).
        if (vn > 0.0f) {
            nrm = -nrm;
            vn = -vn;
        }
        glm::vec3 r = v - 2.0f * vn * nrm;
        bool esc = false;
        out.local[i] = glm::vec4(part.local.index(p, r, &esc), 1.0f);
        out.distant[i] = glm::vec4(part.distant.index(p, r, &esc), 1.0f);
        out.infinite[i] = glm::vec4(r, 1.0f);
        out.fresnel[i] = glm::vec4(std::clamp(-vn, 0.0f, 1.0f), 0.0f, 0.0f, 1.0f);
        escaped[i] = esc;
    });
    out.escaped = 0;
    for (uint8_t e : escaped) out.escaped += e;
}

std::shared_ptr<tex::Texture> makeFresnelTexture(tex::TextureMemory& memory, const glm::vec3& f0,
                                                 int size) {
    tex::TextureDesc d;
    d.target = tex::TextureTarget::Texture1D;
    d.format = tex::TexelFormat::RGBA8;
    d.width = size;
    d.levels = 1;
    auto t = memory.create(d);
    std::vector<uint8_t> bytes(size_t(size) * 4);
    for (int i = 0; i < size; ++i) {
        double c = (i + 0.5) / size, k = std::pow(1.0 - c, 5.0);
        for (int ch = 0; ch < 3; ++ch)
            bytes[4 * size_t(i) + ch] = ray::quantize8(float(f0[ch] + (1.0 - f0[ch]) * k));
        bytes[4 * size_t(i) + 3] = 255;
    }
    memory.upload(*t, 0, 0, bytes);
    return t;
}

}  // namespace rg::pem
