// The frame of Davis & Wyman 2007 on the emulated geforce8800 (004 §3, Figure 2):
//
//   pass 1  back faces of the refractor  → back map   (RGBA16F: eye normal, linear depth)
//   pass 2  front faces                   → front map  (RGBA16F)
//   pass 3  nearby geometry               → nearby map (RGBA16F: colour, linear depth)
//   pass 4  nearby geometry at full size, then the refractor's front faces through the
//           search (TirFP) or the Wyman 2005 baseline → the RGBA8 frame
//
// Passes 1–3 render at mapScale × the frame's size (Figure 7); the maps are read point
// sampled, so a smaller map is the same search on coarser texels.
#pragma once

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "core/path.h"
#include "raycore/image.h"
#include "rasterizer/programmable_device.h"
#include "texunit/texture.h"
#include "tir_programs.h"
#include "tir_scene.h"

namespace rg::tir {

enum class Method { Ours, Wyman05 };
const char* methodName(Method m);

struct TirSettings {
    int width = 512, height = 512;
    float mapScale = 1.0f;        // intermediate maps' size / the frame's (Figure 7)
    int bounces = 3;              // segments searched inside the refractor (Table 1: 1–4)
    int itersFirst = 8, itersLater = 5, itersNearby = 8;
    bool frontAndBack = false;    // Table 1 and §4: back faces only
    bool searchNearby = true;
    Method method = Method::Ours;
    float epsilon = 1e-3f;        // start offset, × the refractor's bounding radius
    float missDegrees = 10.0f;    // candidates further off the ray miss
    int envSize = 128;            // the environment cube map's face size
};
// rg::Error naming the value: bounces outside 0–kMaxBounces, iterations outside
// 1–log₂ of the larger map side + 4, sizes the profile cannot hold, a map scale ≤ 0 or > 1.
constexpr int kMaxBounces = 8;
void validate(const TirSettings& s);

struct PassTiming {
    std::string name;
    double ms = 0;
    raster::ProgramCounters counters;
};
struct TirFrame {
    std::vector<PassTiming> passes;  // the four passes of Figure 2
    double totalMs = 0;
    int64_t refractiveFragments = 0;  // fragment invocations of the final pass's search
    double fetchesPerRefractiveFragment = 0;
};

class TirRenderer {
  public:
    // textureSize: the baked albedo textures' side (each object's texture over its uvs).
    TirRenderer(const TirScene& scene, int threads = 0, Path path = Path::Fast, int textureSize = 512);
    ~TirRenderer();

    TirFrame render(const ray::Camera& camera, const TirSettings& settings);

    // After render(): the frame (RGB, bytes / 255) and the intermediate maps as images
    // for Figure 2 (normals as colours ½ + ½n, linear depth as grey, nearby colour).
    ray::Image frame() const;
    ray::Image backNormals() const, backDepth() const, frontNormals() const, frontDepth() const;
    ray::Image nearbyColor() const, nearbyDepth() const;
    const tex::Texture& frameTexture() const { return *frame_; }
    const tex::Texture& backMap() const { return *backMap_; }
    const tex::Texture& frontMap() const { return *frontMap_; }
    const tex::Texture& nearbyMap() const { return *nearbyMap_; }
    raster::ProgrammableDevice& device() { return device_; }
    // The search constants of the last frame (tests replay the search on them).
    const SearchConstants& constants() const { return constants_; }
    // The last frame's vertex program (the camera's view and projection), the refractor's
    // world-space mesh and the environment cube map (RGBA16F, envSize² faces): with the
    // maps and constants(), everything pass 4's TirFP reads, so a benchmark or a peer can
    // replay the final pass alone (bench/tir_final_pass_workload.h).
    const EyeVP& eyeVP() const { return eyeVP_; }
    std::span<const TirVertex> refractorVertices() const { return refractor_.vertices; }
    std::span<const uint32_t> refractorIndices() const { return refractor_.indices; }
    const tex::Texture& environmentMap() const { return *env_; }
    // Bytes of texture memory resident after the last frame.
    uint64_t textureBytes() const;
    void setPath(Path path) { device_.setPath(path); }
    void setThreads(int threads) { device_.setThreads(threads); }

  private:
    struct Batch {
        std::vector<TirVertex> vertices;
        std::vector<uint32_t> indices;
        glm::vec3 albedo{1.0f};
        std::shared_ptr<tex::Texture> texture;  // albedo texture (white 1×1 when plain)
    };
    // One view's vertex program, search constants and lights (in its eye space).
    struct View {
        EyeVP vp;
        SearchConstants k;
        NearbyFP lighting;
    };
    View makeView(const glm::mat4& view, float px, float py, float near, float far) const;
    float farthestFrom(glm::vec3 eye) const;
    void ensureTargets(const TirSettings& s);
    void bakeSurroundings(int size);
    void passNormalDepth(const EyeVP& vp, float invFar, const std::shared_ptr<tex::Texture>& map,
                         const std::shared_ptr<tex::Texture>& depth, raster::CullMode cull);
    void drawNearby(const View& v, bool depthInAlpha);
    void drawEnvironment(const View& v, int width, int height);
    ray::Image mapImage(const tex::Texture& map, int which) const;

    const TirScene& scene_;
    tex::TextureMemory memory_;
    raster::ProgrammableDevice device_;
    Batch refractor_;
    std::vector<Batch> nearby_;
    std::shared_ptr<tex::Texture> world_, env_, white_;
    std::shared_ptr<tex::Texture> backMap_, frontMap_, nearbyMap_, mapDepth_, frame_, frameDepth_;
    int mapW_ = 0, mapH_ = 0, frameW_ = 0, frameH_ = 0, envSize_ = 0;
    float radius_ = 1.0f;
    glm::vec3 centre_{0.0f};  // of the refractor's bounds: where the surroundings are seen from
    SearchConstants constants_;
    EyeVP eyeVP_;
    int64_t refractiveFragments_ = 0, refractiveFetches_ = 0;
};

}  // namespace rg::tir
