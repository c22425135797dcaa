// The Utah teapot: parsing Newell's patch file and tessellating the bicubic Bézier patches.
#include "raycore/teapot.h"

#include <fstream>
#include <sstream>

#include "core/error.h"

namespace rg::ray {

TeapotPatches loadTeapotPatches(const std::filesystem::path& path) {
    std::ifstream in(path);
    if (!in) throw Error(path.string() + ": cannot open the teapot patch file");
    TeapotPatches t;
    std::string line;
    int lineNo = 0;
    size_t wantPatches = 0, wantPoints = 0;
    enum { Header, Patches, Points } state = Header;
    auto fail = [&](const std::string& what) {
        throw Error(path.string() + ":" + std::to_string(lineNo) + ": " + what);
    };
    while (std::getline(in, line)) {
        ++lineNo;
        if (line.empty() || line[0] == '#') continue;
        std::istringstream ls(line);
        std::string word;
        ls >> word;
        if (word == "patches") {
            if (!(ls >> wantPatches)) fail("expected a patch count");
            state = Patches;
            continue;
        }
        if (word == "vertices") {
            if (!(ls >> wantPoints)) fail("expected a vertex count");
            state = Points;
            continue;
        }
        if (state == Patches) {
            TeapotPatch p;
            p.group = word;
            for (uint32_t& c : p.controls) {
                long v;
                if (!(ls >> v)) fail("a patch needs 16 control-point indices");
                if (v < 1) fail("control-point indices are 1-based");
                c = uint32_t(v - 1);
            }
            t.patches.push_back(p);
        } else if (state == Points) {
            glm::vec3 p;
            std::istringstream ps(line);
            if (!(ps >> p.x >> p.y >> p.z)) fail("expected three coordinates");
            t.points.push_back(p);
        } else {
            fail("unexpected '" + word + "' before 'patches'");
        }
    }
    if (t.patches.size() != wantPatches || wantPatches == 0)
        throw Error(path.string() + ": expected " + std::to_string(wantPatches) + " patches, read " +
                    std::to_string(t.patches.size()));
    if (t.points.size() != wantPoints || wantPoints == 0)
        throw Error(path.string() + ": expected " + std::to_string(wantPoints) +
                    " vertices, read " + std::to_string(t.points.size()));
    for (const TeapotPatch& p : t.patches)
        for (uint32_t c : p.controls)
            if (c >= t.points.size())
                throw Error(path.string() + ": control point " + std::to_string(c + 1) +
                            " is past the " + std::to_string(t.points.size()) + " vertices");
    return t;
}

namespace {

void bernstein(float t, float b[4], float d[4]) {
    float s = 1.0f - t;
    b[0] = s * s * s;
    b[1] = 3.0f * t * s * s;
    b[2] = 3.0f * t * t * s;
    b[3] = t * t * t;
    d[0] = -3.0f * s * s;
    d[1] = 3.0f * s * s - 6.0f * t * s;
    d[2] = 6.0f * t * s - 3.0f * t * t;
    d[3] = 3.0f * t * t;
}

}  // namespace

glm::vec3 evalBezierPatch(const TeapotPatches& t, const TeapotPatch& p, float u, float v,
                          glm::vec3* dPdu, glm::vec3* dPdv) {
    float bu[4], du[4], bv[4], dv[4];
    bernstein(u, bu, du);
    bernstein(v, bv, dv);
    glm::vec3 P(0.0f), Pu(0.0f), Pv(0.0f);
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            const glm::vec3& c = t.points[p.controls[i * 4 + j]];
            P += bu[i] * bv[j] * c;
            Pu += du[i] * bv[j] * c;
            Pv += bu[i] * dv[j] * c;
        }
    if (dPdu) *dPdu = Pu;
    if (dPdv) *dPdv = Pv;
    return P;
}

namespace {

// The file is z up; the scenes are y up.
glm::vec3 toYUp(glm::vec3 p) { return {p.x, p.z, -p.y}; }

// Normal of the patch surface; at degenerate points (the lid tip and the bottom centre,
// where a whole row of control points coincides and one derivative vanishes) the normal is
// taken a little way into the patch, where it is defined and tends to the limit.
glm::vec3 patchNormal(const TeapotPatches& t, const TeapotPatch& p, float u, float v) {
    glm::vec3 pu, pv;
    evalBezierPatch(t, p, u, v, &pu, &pv);
    glm::vec3 n = glm::cross(pu, pv);
    if (glm::length(n) > 1e-6f) return glm::normalize(n);
    const float e = 1e-3f;
    evalBezierPatch(t, p, u < 0.5f ? u + e : u - e, v < 0.5f ? v + e : v - e, &pu, &pv);
    n = glm::cross(pu, pv);
    return glm::length(n) > 0.0f ? glm::normalize(n) : glm::vec3(0, 0, 1);
}

}  // namespace

Mesh tessellateTeapot(const TeapotPatches& t, int level) {
    if (level < 1) throw Error("teapot: tessellation level must be ≥ 1");
    Mesh m;
    m.name = "teapot";
    // Body first, lid second, so each part is one contiguous triangle range.
    for (int pass = 0; pass < 2; ++pass) {
        uint32_t firstTri = uint32_t(m.triangleCount());
        for (const TeapotPatch& p : t.patches) {
            bool isLid = p.group == "lid";
            if (isLid != (pass == 1)) continue;
            const uint32_t base = uint32_t(m.positions.size());
            for (int i = 0; i <= level; ++i)
                for (int j = 0; j <= level; ++j) {
                    float u = float(i) / level, v = float(j) / level;
                    // Newell's patches wind so that dP/du × dP/dv points into the
                    // teapot (checked patch by patch on the body, lid and bottom, where
                    // "inwards" is unambiguous); the outward normal is its negation.
                    glm::vec3 n = -patchNormal(t, p, u, v);
                    m.positions.push_back(toYUp(evalBezierPatch(t, p, u, v)));
                    m.normals.push_back(toYUp(n));
                    m.uvs.push_back({u, v});
                }
            const uint32_t row = uint32_t(level + 1);
            for (int i = 0; i < level; ++i)
                for (int j = 0; j < level; ++j) {
                    uint32_t a = base + i * row + j, b = base + (i + 1) * row + j;
                    uint32_t c = b + 1, d = a + 1;
                    // Counter-clockwise about the outward normal −(dP/du × dP/dv); toYUp
                    // is a rotation, so it keeps handedness.
                    m.indices.insert(m.indices.end(), {a, c, b, a, d, c});
                }
        }
        m.parts.push_back({pass == 0 ? "body" : "lid", firstTri,
                           uint32_t(m.triangleCount()) - firstTri});
    }
    m.source = {"teapot", "", {{"level", level}}};
    return m;
}

}  // namespace rg::ray
