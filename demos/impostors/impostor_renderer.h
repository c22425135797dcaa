// The frame of Dancsik & Minarik on the emulated geforce8800:
//
//   once         refractor distance maps, one cube per mesh (the six piece kinds and the
//                sphere: 002 §4.2), normal + distance from the mesh's centre (RGBA16F)
//   light maps   §7's shadow maps of the two lights (Depth32F), resolved into the board's
//                texture space: one light map for the static pieces, one for the mover
//   impostors    §5.1: every glass object's environment distance impostor (RGBA16F cube,
//                radiance + distance from its centre): board and sky, then DEPTH times the
//                surrounding objects through their own impostors, in place (Gauss–Seidel,
//                scene order), six 90° passes per cube
//   frame        board and sky, then the glass objects (002 §3), nearest first
//
// Modes (§8): Static — nothing moves, the impostors are built once; Classical — every
// impostor holds the whole scene and all are rebuilt every frame; Separated (§5.2) — the
// static objects' impostors hold the static scene only and are built once, the mover's is
// rebuilt every frame and the static objects search the mover's refractor map from
// outside; RefractorMapsOnly (§4.2, "mode A") — no environment impostors: rays search the
// first occupied board square's refractor map, then the board and the sky.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>

#include "core/path.h"
#include "impostor_height_search.h"
#include "impostor_programs.h"
#include "impostor_scene.h"
#include "rasterizer/programmable_device.h"
#include "raycore/image.h"
#include "texunit/texture.h"

namespace rg::impostors {

enum class Mode { Static, Classical, Separated, RefractorMapsOnly };
const char* modeName(Mode m);
Mode modeByName(const std::string& name);  // rg::Error listing the names otherwise

// Where a glass object's refracted ray finds its exit: the refractor distance map from the
// object's centre (002 §3, Figure 3) or the refractor height map over its plane of symmetry
// on a billboard (§6). Mirrors have no exit; mode A (§4.2) searches distance maps only.
enum class Exit { DistanceMap, HeightMap };
const char* exitName(Exit e);
Exit exitByName(const std::string& name);  // rg::Error listing the names otherwise

struct ImpostorSettings {
    int width = 600, height = 600;  // §8
    int envSize = 256;              // §8: environment maps 256 × 256 (and 512 × 512)
    int refractorSize = 256;        // refractor distance maps (§4.2: "can be higher")
    int depth = 2;                  // §5.1's DEPTH
    int iterations = 8;             // secant steps after the first guesses p and l
    float epsilon = 0.03f;          // §4.1's validity distance, × the object's bounding radius
    Mode mode = Mode::Separated;
    float moverU = 0.0f;            // the mover's place on its path, 0–1
    bool diagnostics = false;       // targets 1–3 of the glass programs (readDiagnostics)
    int lightMapSize = 512;         // §7's light maps over the board
    int shadowMapSize = 1024;
    Exit exit = Exit::DistanceMap;  // the refracted ray's exit (§3 or §6)
    int heightMapSize = 512;        // §8: "refractor height maps were made in a 512 × 512 resolution"
    int heightSteps = 8;            // binary-search steps per segment (§6 gives none; [D] 8)
    // §7's caustics (impostor_caustics.h): photon maps per glass piece and light, splatted
    // into two caustic light maps (static pieces once, the mover per frame) that the board
    // adds to its lighting. Off by default: raycore's Whitted reference has no caustics, so
    // the figures compared with it leave them out.
    bool caustics = false;
    int photonMapSize = 32;         // photons per piece and light: N × N (the paper gives none; [D] 32²)
    float causticSigma = 1.5f;      // the splats' Gaussian σ, light-map texels (radius 3σ)
};
constexpr int kMaxDepth = 8;
constexpr int kMaxIterations = 32;
// rg::Error naming the value and the limit: DEPTH outside 1–kMaxDepth, iterations outside
// 0–kMaxIterations, sizes the profile cannot hold (its largest texture and viewport), a
// mover position outside [0, 1], a negative ε.
void validate(const ImpostorSettings& s);

// The view and projection that render cube face `face` about `centre` so that the texel the
// rasterizer writes at (x, y) is the one tex::selectCubeFace gives for the direction through
// its centre (x right along increasing s, y down along increasing t, 90°, D3D depth 0–1).
glm::mat4 cubeFaceView(int face, const glm::vec3& centre);
glm::mat4 cubeFaceProjection(float near, float far);

struct PassTiming {
    std::string name;
    double ms = 0;
    raster::ProgramCounters counters;
};
struct ImpostorFrame {
    std::vector<PassTiming> passes;
    double totalMs = 0;
    double mapsMs = 0;               // building impostors and light maps this frame
    int64_t glassFragments = 0;      // glass-program invocations of the frame pass
    double fetchesPerGlassFragment = 0;
    int impostorsRebuilt = 0;        // environment impostors (re)built this frame
    int64_t impostorTexels = 0;      // their texels rendered (6 faces × size² × passes)
};

class ImpostorRenderer {
  public:
    ImpostorRenderer(const ImpostorScene& scene, int threads = 0, Path path = Path::Fast);
    ~ImpostorRenderer();

    ImpostorFrame render(const ray::Camera& camera, const ImpostorSettings& settings);

    // After render(): the frame (RGB, bytes / 255) and, with diagnostics, per pixel the
    // searches (0 where no glass was drawn) and the mover flags (1 the reflected ray met
    // the mover, 2 the exiting ray, 3 both), and the rays of Figure 9's class map.
    ray::Image frame() const;
    const tex::Texture& frameTexture() const { return *frame_; }
    const tex::Texture& frameDepthTexture() const { return *frameDepth_; }  // Depth24 (dataR)
    struct Diagnostics {
        ray::Image searches, flags;
        ray::Image reflDir, reflD, exitOrigin, exitD, exitDir;  // world space; d: along the ray
    };
    Diagnostics readDiagnostics() const;
    // Figure 3/6-style views of the maps: an impostor's faces as a cross (radiance; or its
    // distance / maxDistance as grey), a refractor map's normals ½ + ½n.
    ray::Image impostorImage(int glassIndex, bool distance, float maxDistance = 8.0f) const;
    ray::Image refractorImage(int map) const;
    // Figure 6: a refractor height map (after a height-map frame), normals ½ + ½n on the left,
    // the height / hMax as grey on the right; empty texels black.
    ray::Image heightMapImage(int map) const;
    const HeightFrame& heightFrame(int map) const { return refractors_.at(size_t(map)).heightFrame; }
    const tex::Texture& heightTexture(int map) const { return *refractors_.at(size_t(map)).height; }
    ray::Image lightMapImage() const;
    // §7's caustics (after a frame with settings.caustics): the caustic light maps (RGBA32F,
    // rgb the caustic irradiance on the board, a the splat weights' sum), the static pieces'
    // or the mover's; the last photon map drawn (target 0: u, v, hit; target 1: power).
    // nullptr before any caustics were built.
    const tex::Texture* causticTexture(bool mover) const;
    const tex::Texture* photonHitTexture() const;
    const tex::Texture* photonPowerTexture() const;
    // Both caustic light maps summed, rgb (black where none were built).
    ray::Image causticImage() const;
    // The board's plane, extent and texture space as the light maps use them (after a
    // frame; GridConstants' board fields).
    const GridConstants& board() const { return grid_; }
    int refractorMaps() const { return int(refractors_.size()); }
    // A refractor distance map (after a frame), the map of glass object i, the map's mesh.
    const tex::Texture& refractorTexture(int map) const { return *refractors_.at(size_t(map)).cube; }
    int refractorOf(int glassIndex) const { return glass_.at(size_t(glassIndex)).refractor; }
    uint32_t refractorMesh(int map) const { return refractors_.at(size_t(map)).mesh; }
    // An environment impostor (after a frame): object i's, or the mover's own in separated mode.
    const tex::Texture& impostorTexture(int glassIndex) const;
    int moverIndex() const { return moverGlass_; }

    // Objects the renderer draws through impostors (ImpostorScene::glass order) and their
    // frames as the programs see them at the mover's current place.
    const std::vector<ObjectFrame>& frames() const { return frames_; }
    const GlassConstants& lastConstants() const { return lastConstants_; }
    // The last frame's glass pass as it was drawn (the bench's impostor peers,
    // bench/impostor_peers_workload.h): the glass objects drawn, in order (nearest first, the
    // ones in view), the view-projection they were drawn with, and each object's world mesh.
    const std::vector<int>& lastGlassOrder() const { return lastGlassOrder_; }
    const glm::mat4& lastViewProj() const { return lastViewProj_; }
    std::span<const ImpostorVertex> glassVertices(int i) const { return glass_.at(size_t(i)).world.vertices; }
    std::span<const uint32_t> glassIndices(int i) const { return glass_.at(size_t(i)).world.indices; }
    raster::ProgrammableDevice& device() { return device_; }
    uint64_t textureBytes() const;
    void setPath(Path path) { device_.setPath(path); }
    void setThreads(int threads) { device_.setThreads(threads); }
    // Forget every impostor and light map (the next frame builds them again).
    void invalidate();

  private:
    struct Batch {
        std::vector<ImpostorVertex> vertices;
        std::vector<uint32_t> indices;
        glm::vec3 lo{0.0f}, hi{0.0f};  // world bounds
    };
    struct Refractor {  // one refractor distance map
        uint32_t mesh = 0;
        int object = -1;  // ≥ 0: its own (a transform that is not a rotation), world space
        glm::vec3 centre{0.0f}, lo{0.0f}, hi{0.0f};
        Batch model;
        std::shared_ptr<tex::Texture> cube;
        int size = 0;
        std::shared_ptr<tex::Texture> height;  // §6's refractor height map (RGBA32F 2D)
        HeightFrame heightFrame;
        int heightSize = 0;
    };
    struct Glass {
        uint32_t object = 0;
        int refractor = 0;
        Batch world;
    };
    enum class Content { None, Full, StaticOnly };
    struct View {
        glm::mat4 viewProj{1.0f};
        glm::vec3 eye{0.0f};
        SkyFP sky;
        raster::CullMode backFaces = raster::CullMode::CW;
        glm::vec4 planes[6]{};  // frustum culling (normals inward)
        bool cube = false;
    };
    View cameraView(const ray::Camera& c, int width, int height) const;
    View faceView(int face, const glm::vec3& centre, int size) const;
    bool visible(const View& v, const Batch& b) const;
    void placeMover(float u);
    void ensureStatic(const ImpostorSettings& s);
    void buildRefractors(int size);
    void buildHeightMaps(int size, int steps);
    void buildLightMaps(const ImpostorSettings& s, bool staticMap, bool moverMap, bool moverInStatic);
    // §7's caustics into the static pieces' and/or the mover's caustic light map
    // (impostor_caustics.cpp).
    void buildCaustics(const ImpostorSettings& s, bool staticMap, bool moverMap, bool moverInStatic);
    // The board's top face with the caustic maps (impostor_caustics.cpp); false when
    // caustics are off (DiffuseFP draws it).
    bool drawCausticBoard(const WorldVP& vp, const DiffuseFP& fp, size_t diffuse, bool moverShadow);
    void buildImpostors(const ImpostorSettings& s, Content content, ImpostorFrame& f);
    void buildMoverImpostor(const ImpostorSettings& s, ImpostorFrame& f);
    void renderImpostor(const ImpostorSettings& s, int i, const std::shared_ptr<tex::Texture>& target, bool withMover,
                        bool moverShadow);
    void drawSurroundings(const View& v, bool writeDistance, bool moverShadow);
    void drawGlass(const View& v, const ImpostorSettings& s, int i, const std::shared_ptr<tex::Texture>& env,
                   bool searchMover, bool diagnostics, bool writeDistance);
    ObjectFrame frameOf(const Glass& g, const ImpostorSettings& s) const;
    void drawGrid(const View& v, const ImpostorSettings& s, int i);
    void buildGridTexture();
    bool boardSetup();  // false: the scene has no board (no light-map footprints, no mode A)
    std::shared_ptr<tex::Texture> cubeTarget(int size) ;

    const ImpostorScene& scene_;
    tex::TextureMemory memory_;
    raster::ProgrammableDevice device_;
    std::vector<Batch> diffuse_;              // the board (and any diffuse object)
    std::vector<ray::Material> diffuseMaterials_;
    std::vector<std::shared_ptr<tex::Texture>> diffuseTextures_;
    std::vector<Glass> glass_;
    std::vector<Refractor> refractors_;
    std::vector<ObjectFrame> frames_;
    int moverGlass_ = -1;                     // index into glass_
    float moverU_ = -1.0f;
    std::shared_ptr<tex::Texture> world_, white_, shadowStatic_[2], shadowMover_[2];
    std::shared_ptr<tex::Texture> lightStatic_, lightMover_, lightDepth_;
    std::array<glm::mat4, 2> lightViewProj_{};
    std::vector<std::shared_ptr<tex::Texture>> impostors_;
    std::shared_ptr<tex::Texture> moverImpostor_, cubeDepth_;
    std::shared_ptr<tex::Texture> frame_, frameDepth_, diag_[3];
    std::shared_ptr<tex::Texture> gridCells_;  // mode A: the board's squares' occupants (R32F 8×8)
    GridConstants grid_;                       // mode A: the constants every object shares
    int board_ = -1;                           // diffuse_ index of the board (its top face)
    bool boardMissing_ = false;
    int frameW_ = 0, frameH_ = 0, envSize_ = 0, lightSize_ = 0, shadowSize_ = 0;
    Content content_ = Content::None;
    std::string impostorKey_, lightKey_;
    bool frameDiagnostics_ = false;
    GlassConstants lastConstants_;
    std::vector<int> lastGlassOrder_;
    glm::mat4 lastViewProj_{1.0f};
    struct Caustics;  // impostor_caustics.cpp
    std::shared_ptr<Caustics> caustics_;  // made by the first buildCaustics
    std::string causticKey_;
    bool causticsOn_ = false;
};

}  // namespace rg::impostors
