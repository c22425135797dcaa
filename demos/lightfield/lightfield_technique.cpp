// lightfield behind `retroglass compare` (reproduction.h's Technique): the first glass or
// mirror object of any scene as a radiance light field, drawn on sgi-octane-mxe by the
// Gortler reconstruction (§3, the main variant) and from its all-halved VQ codebook by the
// alpha-basis passes and by 4D textures (§5).
//
// Radiance, not the §4 geometry light field: compare's scenes are lit by their own lights
// and surroundings (teapot-in-room has a black environment), which an environment-map
// lookup of the exit ray cannot show; each sample ray carries the ray tracer's radiance
// (raycore Whitted, the whole scene, depth 8), as the Buddha light field of the colour
// plates carries captured radiance.
//
// A two-plane slab looks at the object from one side, so each view gets its own slab: the
// world is moved into a slab frame (object centre at the origin, scaled to the reproduction's
// bounding radius of 1.3, the camera on +z) where geometrySlab's planes apply (the eye points
// brought nearer when the camera is close), every sample ray is traced back in the world, and
// the slab-frame camera draws the light field: a rigid motion and a uniform scale leave the
// image as it is. The capture and the codebook are the technique's precompute, made at a
// view's first render.
#include <chrono>
#include <map>

#include "core/error.h"
#include "figures.h"
#include "gortler_renderer.h"
#include "lf_capture.h"
#include "lightfield_scene.h"
#include "raycore/accel.h"
#include "raycore/render.h"
#include "raycore/tracer_whitted.h"
#include "reproduce_lightfield.h"
#include "vq.h"

namespace rg::lightfield {

namespace {

using Clock = std::chrono::steady_clock;

constexpr float kRadius = 1.3f;  // the object's bounding radius in the slab frame (makeScene's)

int firstLensObject(const ray::Scene& scene) {
    for (size_t i = 0; i < scene.objects.size(); ++i) {
        const ray::MaterialType t = scene.materials.at(scene.objects[i].material).type;
        if (t == ray::MaterialType::Glass || t == ray::MaterialType::Mirror) return int(i);
    }
    return -1;
}

// One view's light field, its slab frame and what the routes need resident.
struct ViewField {
    glm::mat3 R{1.0f};  // world → slab rotation (rows: the slab's x, y, z)
    ray::Camera camera; // the view in the slab frame
    LightField lf;
    VqLightField vq;
};

class LightfieldTechnique final : public demos::Technique {
  public:
    LightfieldTechnique(const ray::Scene& scene, const demos::PrepareOptions& options)
        : full_(scene), options_(options), octane_(profile(ProfileId::SgiOctaneMxe)) {
        const int obj = firstLensObject(scene);
        if (obj < 0) throw Error("lightfield: scene '" + scene.name + "' has no glass or mirror object");
        const auto t0 = Clock::now();
        name_ = scene.objects[size_t(obj)].name;
        // Its bounds set the slab frame's origin and scale.
        mesh_ = scene.worldMesh(uint32_t(obj));
        const ray::Bounds b = ray::computeBounds(mesh_);
        centre_ = b.center();
        scale_ = kRadius / (0.5f * glm::length(b.hi - b.lo));
        accel_ = std::make_unique<ray::Accel>(full_);
        const bool paper = options.quality == demos::Quality::Paper;
        S_ = paper ? 32 : 16;
        U_ = paper ? 128 : 64;
        vqOptions_.codebookSize = paper ? 4096 : 256;
        vqOptions_.trainingBlocks = paper ? 131072 : 16384;
        vqOptions_.iterations = paper ? 4 : 4;
        vqOptions_.threads = options.threads;
        precomputeSeconds_ = std::chrono::duration<double>(Clock::now() - t0).count();
    }

    std::vector<std::string> variants() const override { return {"gortler", "vq_alpha_basis", "vq_4d"}; }
    std::string mainVariant() const override { return "gortler"; }
    std::string object() const override { return name_; }
    double precomputeSeconds() const override { return precomputeSeconds_; }
    uint64_t textureBytes(const std::string& variant) const override {
        const auto it = bytes_.find(variant);
        return it == bytes_.end() ? 0 : it->second;
    }

    demos::RenderedView render(const std::string& variant, const ray::Camera& camera) override {
        const ViewField& vf = field(camera);
        const int w = options_.width, h = options_.height;
        raster::Device dev(octane_, w, h, raster::DepthFormat::None, raster::DeviceOptions{Path::Fast, options_.threads});
        auto mem = std::make_shared<tex::TextureMemory>(octane_);
        dev.textureUnits().setTextureMemory(mem);
        demos::RenderedView v;
        const auto t0 = Clock::now();
        dev.beginFrame();
        // Passes as the paper counts them: the Gortler frame is one (every eye point's
        // polygons blended); a VQ frame its basis and colour passes and the final alpha fill.
        if (variant == "gortler") {
            SliceTextures slices(mem, vf.lf);
            renderGortler(dev, slices, vf.lf, vf.camera);
            bytes_[variant] = slices.resident() ? mem->residentBytes() : vf.lf.bytes();
            v.passes = 1;
        } else if (variant == "vq_alpha_basis") {
            const VqTextures tx(mem, vf.vq);
            const VqStats st = renderVq(dev, tx, vf.vq, vf.camera);
            bytes_[variant] = mem->residentBytes();
            v.passes = st.basisPasses + st.colorPasses + 1;
        } else if (variant == "vq_4d") {
            const VqTextures4D tx(mem, vf.vq);
            const VqStats st = renderVq4D(dev, tx, vf.vq, vf.camera);
            bytes_[variant] = mem->residentBytes();
            v.passes = st.basisPasses + st.colorPasses + 1;
        } else {
            throw Error("lightfield: unknown variant '" + variant + "'");
        }
        dev.endFrame();
        v.frameMs = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
        v.image = demos::framebufferImage(dev.framebuffer());
        // Where the eye points cover the ray (the Gortler weights' alpha): the VQ passes set
        // alpha to one over the whole frame, so every variant is measured on this mask.
        v.drawn = drawn(vf);
        v.counters = {{"fragments", dev.counters().fragmentsGenerated}};
        return v;
    }

    demos::GroundTruth groundTruth(const ray::Camera& camera) override {
        const ray::Accel& accel = *accel_;
        ray::RenderOptions ro;
        ro.width = options_.width;
        ro.height = options_.height;
        ro.maxDepth = 8;
        ro.threads = options_.threads;
        demos::GroundTruth g;
        g.image = ray::renderWhitted(accel, camera, ro);
        g.coverage = ray::Image(ro.width, ro.height, 1);
        const int obj = firstLensObject(full_);
        for (int y = 0; y < ro.height; ++y)
            for (int x = 0; x < ro.width; ++x) {
                const ray::Hit hit = accel.intersect(ray::primaryRay(camera, ro.width, ro.height, float(x) + 0.5f, float(y) + 0.5f));
                g.coverage.at(x, y, 0) = hit.valid() && int(hit.object) == obj ? 1.0f : 0.0f;
            }
        g.tracer = "raycore Whitted, depth 8, 1 sample at the pixel centre (the whole scene)";
        return g;
    }

  private:
    // The view's slab frame, light field and codebook, made at its first render.
    const ViewField& field(const ray::Camera& camera) {
        for (const auto& [c, f] : fields_)
            if (c == camera) return *f;
        const auto t0 = Clock::now();
        auto f = std::make_unique<ViewField>();
        // ---- the slab frame: the camera on +z, the object at the origin ------------------------
        const glm::vec3 z = glm::normalize(camera.eye - centre_);
        glm::vec3 x = glm::cross(camera.up, z);
        if (glm::length(x) < 1e-4f) x = glm::cross(glm::vec3(1, 0, 0), z);
        x = glm::normalize(x);
        const glm::vec3 y = glm::cross(z, x);
        f->R = glm::transpose(glm::mat3(x, y, z));  // rows x, y, z
        auto toSlab = [&](glm::vec3 p) { return scale_ * (f->R * (p - centre_)); };
        f->camera = camera;
        f->camera.eye = toSlab(camera.eye);
        f->camera.target = toSlab(camera.target);
        f->camera.up = f->R * camera.up;
        // ---- the slab: geometrySlab's planes, fitted to the object and the camera ------------
        // The object's bounds in the slab frame (its vertices' box), the eye points 3/4 of
        // the way from its front to the camera (at most geometrySlab's z = 6), their grid
        // ±stZ/6 as geometrySlab's; the window holds the box's shadow from every corner eye
        // point (validateSlab's condition), so every ray through the object is stored.
        ray::Bounds box{glm::vec3(1e30f), glm::vec3(-1e30f)};
        for (const glm::vec3& p : mesh_.positions) {
            const glm::vec3 q = toSlab(p);
            box.lo = glm::min(box.lo, q);
            box.hi = glm::max(box.hi, q);
        }
        const float d = f->camera.eye.z;
        if (d < box.hi.z + 0.2f * kRadius)
            throw Error("lightfield: view '" + camera.name + "' is too close to '" + name_ + "' for a two-plane slab in front of it");
        LightSlab slab = geometrySlab(S_, U_);
        slab.stZ = std::min(6.0f, box.hi.z + 0.75f * (d - box.hi.z));
        slab.stMin = glm::vec2(-slab.stZ / 6.0f);
        slab.stMax = glm::vec2(slab.stZ / 6.0f);
        float half = 0.0f;
        for (int c = 0; c < 4; ++c) {
            const glm::vec3 e(c & 1 ? slab.stMax.x : slab.stMin.x, c & 2 ? slab.stMax.y : slab.stMin.y, slab.stZ);
            for (int k = 0; k < 8; ++k) {
                const glm::vec3 b(k & 1 ? box.hi.x : box.lo.x, k & 2 ? box.hi.y : box.lo.y, k & 4 ? box.hi.z : box.lo.z);
                const glm::vec3 p = e + (b - e) * (e.z / (e.z - b.z));
                half = std::max({half, std::abs(p.x), std::abs(p.y)});
            }
        }
        slab.uvMin = glm::vec2(-1.02f * half);
        slab.uvMax = glm::vec2(1.02f * half);
        validateSlab(slab, box, "lightfield: the slab of view '" + camera.name + "'");
        // ---- the radiance light field, traced in the world ----------------------------------
        const glm::mat3 Rt = glm::transpose(f->R);
        f->lf = captureRadianceField(slab, [&](const ray::Ray& r) {
            ray::Ray world;
            world.origin = centre_ + Rt * r.origin / scale_;
            world.dir = glm::normalize(Rt * r.dir);
            ray::RayCounts counts;
            return ray::whittedRadiance(*accel_, world, 0, 8, counts);
        }, options_.threads);
        f->vq = quantize(f->lf, {2, 2, 2, 2}, vqOptions_);
        // The coverage of the eye points: a Gortler frame's alpha.
        {
            raster::Device dev(octane_, options_.width, options_.height, raster::DepthFormat::None,
                               raster::DeviceOptions{Path::Fast, options_.threads});
            auto mem = std::make_shared<tex::TextureMemory>(octane_);
            dev.textureUnits().setTextureMemory(mem);
            SliceTextures slices(mem, f->lf);
            dev.beginFrame();
            renderGortler(dev, slices, f->lf, f->camera);
            dev.endFrame();
            ray::Image d;
            (void)demos::framebufferImage(dev.framebuffer(), &d);
            drawn_.emplace(f.get(), std::move(d));
        }
        precomputeSeconds_ += std::chrono::duration<double>(Clock::now() - t0).count();
        fields_.emplace_back(camera, std::move(f));
        return *fields_.back().second;
    }
    const ray::Image& drawn(const ViewField& f) const { return drawn_.at(&f); }

    ray::Scene full_;
    ray::Mesh mesh_;  // the object in world coordinates
    demos::PrepareOptions options_;
    const Profile& octane_;
    std::string name_;
    glm::vec3 centre_{0.0f};
    float scale_ = 1.0f;
    std::unique_ptr<ray::Accel> accel_;
    int S_ = 16, U_ = 64;
    VqOptions vqOptions_;
    std::vector<std::pair<ray::Camera, std::unique_ptr<ViewField>>> fields_;
    std::map<const ViewField*, ray::Image> drawn_;
    std::map<std::string, uint64_t> bytes_;
    double precomputeSeconds_ = 0;
};

}  // namespace

std::string LightfieldReproduction::appliesTo(const ray::Scene& scene) const {
    const int obj = firstLensObject(scene);
    return obj < 0 ? std::string() : scene.objects[size_t(obj)].name;
}

std::unique_ptr<demos::Technique> LightfieldReproduction::prepare(const ray::Scene& scene, const std::vector<ray::Camera>&,
                                                                  const demos::PrepareOptions& options) const {
    return std::make_unique<LightfieldTechnique>(scene, options);
}

}  // namespace rg::lightfield
