// Triangle setup: snap to fixed point, cull, edge functions with the top-left rule, the
// pixel bounding box and the attribute planes (docs/hardware.md, "Setup and
// rasterization" and "Interpolation").
#include <algorithm>
#include <cmath>

#include "pipeline.h"

namespace rg::raster::detail {

bool setupTriangle(const DrawContext& dc, const ProcessedVertex& v0, const ProcessedVertex& v1,
                   const ProcessedVertex& v2, Rgba8 flatDiffuse, Rgba8 flatSpecular,
                   SetupTriangle& t, std::vector<Plane>& texPool) {
    const ProcessedVertex* v[3] = {&v0, &v1, &v2};
    for (const ProcessedVertex* p : v)
        if (!std::isfinite(p->wx) || !std::isfinite(p->wy) || !std::isfinite(p->wz) ||
            !std::isfinite(p->invW))
            return false;

    // ---- snap to fixed point ------------------------------------------------------------
    const int s = dc.subpixelBits;
    int64_t X[3], Y[3];
    for (int i = 0; i < 3; ++i) {
        X[i] = v[i]->sx;
        Y[i] = v[i]->sy;
    }

    // ---- orientation and culling (y points down: area > 0 is clockwise on screen) -------
    int64_t area = (X[1] - X[0]) * (Y[2] - Y[0]) - (X[2] - X[0]) * (Y[1] - Y[0]);
    if (area == 0) return false;
    if (dc.st.cull == CullMode::CW && area > 0) return false;
    if (dc.st.cull == CullMode::CCW && area < 0) return false;
    if (area < 0) {  // rasterize every triangle clockwise; vertex 0 stays first
        std::swap(X[1], X[2]);
        std::swap(Y[1], Y[2]);
        std::swap(v[1], v[2]);
        area = -area;
    }
    // 1/area in pixels², started early so that the division overlaps the edge setup.
    // double(area)·2^−2s equals dx1·dy2 − dx2·dy1 below exactly: every term is an integer
    // multiple of 2^−2s below 2^53.
    const double invArea = 1.0 / (double(area) * (1.0 / double(int64_t{1} << (2 * s))));

    // ---- pixel box: samples at pixel centres (X << s) + half ---------------------------
    const int64_t half = int64_t{1} << (s - 1);
    int64_t minXf = std::min({X[0], X[1], X[2]}), maxXf = std::max({X[0], X[1], X[2]});
    int64_t minYf = std::min({Y[0], Y[1], Y[2]}), maxYf = std::max({Y[0], Y[1], Y[2]});
    int64_t one = int64_t{1} << s;
    t.minX = int(std::max<int64_t>(dc.clipX0, (minXf - half + one - 1) >> s));
    t.minY = int(std::max<int64_t>(dc.clipY0, (minYf - half + one - 1) >> s));
    t.maxX = int(std::min<int64_t>(dc.clipX1 - 1, (maxXf - half) >> s));
    t.maxY = int(std::min<int64_t>(dc.clipY1 - 1, (maxYf - half) >> s));
    if (t.minX > t.maxX || t.minY > t.maxY) return false;

    // ---- edge functions with the top-left rule -----------------------------------------
    // E(P) = (b.x − a.x)(P.y − a.y) − (b.y − a.y)(P.x − a.x), positive inside. A sample on
    // an edge belongs to the triangle only when the edge is a top edge (horizontal, the
    // triangle below it) or a left edge (going up on screen, the triangle to its right).
    for (int e = 0; e < 3; ++e) {
        int a = e, b = (e + 1) % 3;
        int64_t dxe = X[b] - X[a], dye = Y[b] - Y[a];
        bool topLeft = dye < 0 || (dye == 0 && dxe > 0);
        t.A[e] = -dye;
        t.B[e] = dxe;
        t.C[e] = dye * X[a] - dxe * Y[a] - (topLeft ? 0 : 1);
    }
    t.quadCoverage = quadCoverageOf(t, s);

    // ---- attribute planes --------------------------------------------------------------
    const double inv = 1.0 / double(one);
    double x0 = double(X[0]) * inv, y0 = double(Y[0]) * inv;
    double dx1 = double(X[1]) * inv - x0, dy1 = double(Y[1]) * inv - y0;
    double dx2 = double(X[2]) * inv - x0, dy2 = double(Y[2]) * inv - y0;
    t.x0 = float(x0);
    t.y0 = float(y0);

    if (dc.depthOn) {  // only the depth test reads z
        double a0 = v[0]->wz, a1 = v[1]->wz, a2 = v[2]->wz;
        double da1 = a1 - a0, da2 = a2 - a0;
        t.zc = a0;
        t.zdx = (da1 * dy2 - da2 * dy1) * invArea;
        t.zdy = (da2 * dx1 - da1 * dx2) * invArea;
    }
    const bool needInvW = (dc.gouraud && dc.perspectiveColor) || dc.numTexSets > 0;
    if (needInvW)
        t.invW = makePlane(v[0]->invW, v[1]->invW, v[2]->invW, dx1, dy1, dx2, dy2, invArea);
    auto attrPlane = [&](int a, bool perspective) {
        double w0 = perspective ? double(v[0]->invW) : 1.0;
        double w1 = perspective ? double(v[1]->invW) : 1.0;
        double w2 = perspective ? double(v[2]->invW) : 1.0;
        return makePlane(v[0]->attr[a] * w0, v[1]->attr[a] * w1, v[2]->attr[a] * w2, dx1, dy1,
                         dx2, dy2, invArea);
    };
    if (dc.gouraud) {
        int colors = dc.needSpecular ? 8 : 4;
        for (int a = 0; a < colors; ++a) {
            Plane p = attrPlane(a, dc.perspectiveColor);
            t.colorC[a] = p.c;
            t.colorDx[a] = p.dx;
            t.colorDy[a] = p.dy;
        }
    }
    t.texPlanes = uint32_t(texPool.size());
    for (int a = kColorAttrs; a < dc.numAttrs; ++a) texPool.push_back(attrPlane(a, true));
    t.flatDiffuse = flatDiffuse;
    t.flatSpecular = flatSpecular;
    return true;
}

}  // namespace rg::raster::detail
