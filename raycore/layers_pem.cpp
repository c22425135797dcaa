// 001 §3–4: the ray tracer's segmented layers per object.
#include "raycore/layers_pem.h"

#include <algorithm>

#include "core/error.h"
#include "raycore/fresnel.h"
#include "raycore/tracer_whitted.h"

namespace rg::ray {

Segment findSegment(const Scene& scene, const std::string& name) {
    std::string obj = name, part;
    if (auto slash = name.find('/'); slash != std::string::npos) {
        obj = name.substr(0, slash);
        part = name.substr(slash + 1);
    }
    int o = scene.findObject(obj);
    if (o < 0) throw Error("no object named '" + obj + "' in scene '" + scene.name + "'");
    Segment s{uint32_t(o), -1};
    if (!part.empty()) {
        s.part = scene.meshes[scene.objects[size_t(o)].mesh].findPart(part);
        if (s.part < 0)
            throw Error("object '" + obj + "' has no part named '" + part + "'");
    }
    return s;
}

std::string segmentName(const Scene& scene, const Segment& s) {
    const Object& o = scene.objects.at(s.object);
    if (s.part < 0) return o.name;
    return o.name + "/" + scene.meshes[o.mesh].parts.at(size_t(s.part)).name;
}

Image PemLayers::composite() const {
    Image out(diffuse.width, diffuse.height, 3);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            float cov = coverage.at(x, y, 0), a = localAlpha.at(x, y, 0);
            glm::vec3 spec = a * localColor.rgb(x, y) + (1.0f - a) * distant.rgb(x, y);
            out.setRgb(x, y, diffuse.rgb(x, y) + cov * fresnel.rgb(x, y) * spec);
        }
    return out;
}

namespace {

struct Accum {
    int count = 0, localCount = 0;
    glm::vec3 diffuse{0.0f}, fresnel{0.0f}, local{0.0f}, distant{0.0f};
};

}  // namespace

PemLayerImages renderPemLayers(const Accel& accel, const Camera& camera, const RenderOptions& o,
                               const std::vector<Segment>& segments,
                               const PemLayerOptions& lo) {
    PemLayerImages out;
    out.segmentId = Image(o.width, o.height, 1, -1.0f);
    out.background = Image(o.width, o.height, 3);
    for (const Segment& sg : segments) {
        PemLayers l;
        l.segment = sg;
        l.coverage = Image(o.width, o.height, 1);
        l.diffuse = Image(o.width, o.height, 3);
        l.fresnel = Image(o.width, o.height, 3);
        l.localColor = Image(o.width, o.height, 3);
        l.localAlpha = Image(o.width, o.height, 1);
        l.distant = Image(o.width, o.height, 3);
        out.segments.push_back(std::move(l));
    }
    const int n = std::max(1, o.spp);
    const float inv = 1.0f / float(n * n);
    auto segmentOf = [&](const SurfacePoint& s) {
        for (size_t k = 0; k < segments.size(); ++k)
            if (segments[k].object == s.object &&
                (segments[k].part < 0 || segments[k].part == int(s.part)))
                return int(k);
        return -1;
    };
    parallelRows(o, [&](int y, RayCounts& counts) {
        // The row's camera rays traced ahead, a chunk of pixels at a time (CameraRowRays).
        CameraRowRays row(accel, camera, o, y);
        std::vector<Accum> acc(segments.size());
        for (int x = 0; x < o.width; ++x) {
            std::fill(acc.begin(), acc.end(), Accum{});
            glm::vec3 background(0.0f);
            int centreSegment = -1;
            const CameraRowRays::Samples px = row.pixel(x);
            for (int sy = 0; sy < n; ++sy)
                for (int sx = 0; sx < n; ++sx) {
                    const size_t i = size_t(sy * n + sx);
                    const Ray& ray = px.rays[i];
                    const Hit& hit = px.hits[i];
                    const SurfacePoint& s = px.points[i];
                    counts.add(RayKind::Primary);
                    int k = hit.valid() ? segmentOf(s) : -1;
                    if (sx == n / 2 && sy == n / 2) centreSegment = k;
                    if (k < 0) {
                        background += whittedShade(accel, ray, hit, s, 0, o.maxDepth, counts);
                        continue;
                    }
                    Accum& a = acc[size_t(k)];
                    ++a.count;
                    const Material& m = *s.material;
                    if (m.type == MaterialType::Diffuse || o.maxDepth <= 0) {
                        // Not a reflector: its whole shading is "diffuse", F = 0.
                        a.diffuse += whittedShade(accel, ray, hit, s, 0, o.maxDepth, counts);
                        continue;
                    }
                    a.diffuse += diffuseLighting(accel, s, ray.dir, counts);
                    const glm::vec3 nrm = s.frontFace ? s.ns : -s.ns;
                    const float cosI = std::max(0.0f, -glm::dot(ray.dir, nrm));
                    glm::vec3 F;
                    if (m.type == MaterialType::Mirror) {
                        F = mirrorReflectance(m, cosI);
                    } else {
                        // Glass: 001 has no refraction; the transmitted share (1 − F̂_R)·T
                        // is view-dependent residue that we fold into the diffuse layer so
                        // the layers still recombine to the reference image.
                        const float etaI = s.frontFace ? 1.0f : m.ior;
                        const float etaT = s.frontFace ? m.ior : 1.0f;
                        float FR = FresnelDielectric(cosI, etaI, etaT);
                        glm::vec3 t;
                        if (!refractDir(ray.dir, nrm, etaI / etaT, &t)) FR = 1.0f;
                        if (FR < 1.0f) {
                            Ray tr;
                            tr.dir = t;
                            tr.origin = accel.offsetOrigin(s, t);
                            counts.add(RayKind::Refraction);
                            a.diffuse += (1.0f - FR) *
                                         whittedRadiance(accel, tr, 1, o.maxDepth, counts);
                        }
                        F = glm::vec3(FR);
                    }
                    a.fresnel += F;
                    // The first reflected ray: local if it strikes the reflector again.
                    Ray r;
                    r.dir = mirrorDirection(s, ray.dir);
                    r.origin = accel.offsetOrigin(s, r.dir);
                    counts.add(RayKind::Reflection);
                    Hit h2 = accel.intersect(r);
                    auto onReflector = [&](const Hit& h) {
                        if (!h.valid() || h.object != s.object) return false;
                        if (lo.localScope == LocalScope::Object) return true;
                        return accel.surface(r, h).part == s.part;
                    };
                    if (onReflector(h2)) {
                        ++a.localCount;
                        a.local += whittedShade(accel, r, h2, 1, o.maxDepth, counts);
                        // Distant: continue through the reflector (001 §4) past every hit
                        // on it, so the distant layer is defined everywhere.
                        Ray c = r;
                        Hit hc = h2;
                        for (int i = 0; i < lo.maxContinuation && onReflector(hc); ++i) {
                            c.tnear = hc.t * (1.0f + 1e-6f) + accel.epsilon();
                            counts.add(RayKind::Continuation);
                            hc = accel.intersect(c);
                        }
                        if (onReflector(hc)) hc = Hit{};  // gave up: treat as escaped
                        // Shade the continued hit as seen along the same reflected ray.
                        a.distant += whittedShade(accel, c, hc, 1, o.maxDepth, counts);
                    } else {
                        a.distant += whittedShade(accel, r, h2, 1, o.maxDepth, counts);
                    }
                }
            out.segmentId.at(x, y, 0) = float(centreSegment);
            out.background.setRgb(x, y, background * inv);
            for (size_t k = 0; k < acc.size(); ++k) {
                const Accum& a = acc[k];
                if (a.count == 0) continue;
                PemLayers& l = out.segments[k];
                const float invCount = 1.0f / float(a.count);
                l.coverage.at(x, y, 0) = float(a.count) * inv;
                l.diffuse.setRgb(x, y, a.diffuse * inv);
                l.fresnel.setRgb(x, y, a.fresnel * invCount);
                l.localAlpha.at(x, y, 0) = float(a.localCount) * invCount;
                if (a.localCount > 0) l.localColor.setRgb(x, y, a.local / float(a.localCount));
                l.distant.setRgb(x, y, a.distant * invCount);
            }
        }
    });
    return out;
}

}  // namespace rg::ray
