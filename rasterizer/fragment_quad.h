// One 2×2 quad of one triangle through the rest of the pipeline: interpolation, the
// texture stages, specular add, alpha test, depth test, blend and colour write mask.
//
// Shared by both paths. The template flags let the fast path compile the per-state
// branches away; with kSpecialized = false every decision is read from the state at run
// time (the reference path). Either way the arithmetic per pixel is the same sequence of
// IEEE single/double operations and integer steps, so the bytes cannot differ.
//
//      quad layout (FragmentQuad):   +---+---+
//                                    | 0 | 1 |   pixel i at (x + (i & 1), y + (i >> 1))
//                                    +---+---+
//                                    | 2 | 3 |
//                                    +---+---+
#pragma once

#include "pipeline.h"
#include "rasterizer/fragment_ops.h"

namespace rg::raster::detail {

template <bool kSpecialized, bool kDepth, bool kBlend, bool kPassThrough>
inline void processQuad(const DrawContext& dc, const SetupTriangle& t, int qx, int qy,
                        unsigned coverage, RasterCounters& rc) {
    const bool depthOn = kSpecialized ? kDepth : dc.depthOn;
    const bool blendOn = kSpecialized ? kBlend : dc.st.blend != 0;
    const bool passThrough = kSpecialized ? kPassThrough : dc.passThrough;
    const PipelineState& st = dc.st;

    // Helper pixels (coverage bit clear) are only interpolated when a texture stage needs
    // their derivatives; their values never reach the framebuffer.
    const unsigned evalMask = passThrough ? coverage : 0xFu;

    // ---- interpolation (docs/hardware.md, "Interpolation") -----------------------------
    float fx[4], fy[4], r[4] = {1, 1, 1, 1};
    for (int i = 0; i < 4; ++i) {
        fx[i] = (float(qx + (i & 1)) + 0.5f) - t.x0;
        fy[i] = (float(qy + (i >> 1)) + 0.5f) - t.y0;
    }
    const bool needR = (dc.gouraud && dc.perspectiveColor) || dc.numTexSets > 0;
    if (needR)
        for (int i = 0; i < 4; ++i)
            if (evalMask & (1u << i)) r[i] = 1.0f / t.invW.at(fx[i], fy[i]);

    std::array<Rgba8, 4> diffuse, specular;
    if (!dc.gouraud) {
        diffuse.fill(t.flatDiffuse);
        specular.fill(t.flatSpecular);
    } else {
        const int colors = dc.needSpecular ? 8 : 4;
        for (int i = 0; i < 4; ++i) {
            if (!(evalMask & (1u << i))) continue;
            uint8_t c[8] = {0, 0, 0, 0, 0, 0, 0, 0};
            for (int a = 0; a < colors; ++a) {
                float v = t.attr[a].at(fx[i], fy[i]);
                if (dc.perspectiveColor) v = v * r[i];
                c[a] = colorToByte(v);
            }
            diffuse[i] = Rgba8{c[0], c[1], c[2], c[3]};
            specular[i] = Rgba8{c[4], c[5], c[6], c[7]};
        }
    }

    // ---- texture stages (texunit/) ------------------------------------------------------
    const bool observed = !kSpecialized && dc.fragmentObserver != nullptr;
    std::array<Rgba8, 4> color;
    tex::FragmentQuad q;
    if (passThrough && !observed) {
        color = diffuse;
    } else {
        q.x = qx;
        q.y = qy;
        q.coverage = uint8_t(coverage);
        q.diffuse = diffuse;
        q.specular = specular;
        for (int k = 0; k < dc.numTexSets; ++k)
            for (int i = 0; i < 4; ++i)
                for (int c = 0; c < 4; ++c)
                    q.texCoord[dc.texSets[k]][i][c] =
                        t.attr[kColorAttrs + 4 * k + c].at(fx[i], fy[i]) * r[i];
        if (passThrough)
            color = diffuse;
        else
            dc.tu->shadeQuad(q, color, dc.path);
    }

    // ---- per-fragment operations --------------------------------------------------------
    Framebuffer& fb = *dc.fb;
    const int width = fb.width();
    unsigned written = 0;
    for (int i = 0; i < 4; ++i) {
        if (!(coverage & (1u << i))) continue;
        const int px = qx + (i & 1), py = qy + (i >> 1);
        ++rc.generated;
        Rgba8 c = color[i];
        if (st.specularEnable) c = addSpecular(c, specular[i]);
        if (st.alphaTest && !comparePasses(st.alphaFunc, c.a, st.alphaRef)) continue;
        const size_t idx = size_t(py) * size_t(width) + size_t(px);
        if (depthOn) {
            double z = (t.zc + t.zdx * ((double(px) + 0.5) - double(t.x0))) +
                       t.zdy * ((double(py) + 0.5) - double(t.y0));
            uint32_t q = quantizeDepth(z, dc.depthMax);
            uint32_t& stored = fb.depth()[idx];
            if (!comparePasses(st.depthFunc, q, stored)) continue;
            if (st.depthWrite) stored = q;
        }
        ++rc.written;
        written |= 1u << i;
        Rgba8& dst = fb.color()[idx];
        if (blendOn) {
            c = blendPixel(st.srcBlend, st.dstBlend, st.blendOp, c, dst);
            ++rc.blendOps;
        }
        dst = applyWriteMask(st.colorWriteMask, c, dst);
    }
    if (observed) (*dc.fragmentObserver)(q, uint8_t(written));
}

}  // namespace rg::raster::detail
