// The hardware light-field reconstruction of Gortler et al. as Heidrich et al. 1999 §3
// describe it, on the emulated SGI device: "for each eye point on the (s, t)-plane ... draws
// the grid cells surrounding the eye point ... The alpha values of the polygon vertices are
// set to 1 at the eye point and to 0 everywhere else ... each rendered polygon is textured
// with the (u, v)-slice corresponding to the eye point ... weighted by the alpha values ...
// alpha blending and texture mapping with bi-linear interpolation yields the desired
// reconstruction."
//
// Per eye point (i, j) the triangles of the (s, t) grid that have it as a vertex, drawn on
// the (s, t) plane in world space; at each vertex the texture coordinate is where the line
// from the camera through the vertex meets the (u, v) plane (affine on the plane, so
// perspective-correct interpolation is exact); the weight rides in the vertex colour
// (w, w, w, w) with w = 255 at the eye point, 0 elsewhere, GL MODULATE, blending ONE/ONE
// into a cleared buffer (so RGBA data keeps its alpha, and an RGB light field's alpha
// becomes the summed weight: 255 where the eye points cover the ray).
//
// The weights sum to one only if every eye point uses the same triangulation of the grid
// (Triangulation::FixedDiagonal: each cell split along the diagonal (a, b)–(a+1, b+1), the
// hexagon of 6 triangles around an interior eye point). PerEyePointDiagonals — each eye
// point splitting its own 4 cells along diagonals through itself — is what a reading of
// "the grid cells surrounding the eye point" can lead to; its weights do not sum to one
// (kept for the test that shows it and the report's figure).
#pragma once

#include <array>
#include <memory>
#include <vector>

#include <glm/glm.hpp>

#include "light_slab.h"
#include "rasterizer/device.h"
#include "texunit/texture.h"

namespace rg::lightfield {

enum class Triangulation { FixedDiagonal, PerEyePointDiagonals };

struct StTriangle {
    std::array<glm::ivec2, 3> v;  // eye-point grid vertices (i, j)
};
// The triangles drawn for eye point (i, j).
std::vector<StTriangle> eyePointTriangles(const LightSlab& slab, int i, int j, Triangulation tri);
// The weight eye point (i, j) gives the (s, t) point `st` (world): its barycentric
// coordinate in the triangle of its set that contains `st`, 0 outside them. The analytic
// twin of what the blending sums (tests: Σ over eye points = 1).
double hatWeight(const LightSlab& slab, int i, int j, glm::vec2 st, Triangulation tri);

// View and projection for the device that match ray::primaryRay pixel for pixel (D3D clip
// volume 0 ≤ z ≤ w, the camera's vertical field of view).
glm::mat4 viewMatrix(const ray::Camera& c);
glm::mat4 projectionMatrix(const ray::Camera& c, int width, int height);

// A light field's (u, v) slices as 2D textures of one profile's texture memory. When they
// all fit beside what the memory already holds they are uploaded once (resident);
// otherwise each is uploaded for its eye point in every frame (swapped: §5's "these need to
// be swapped in and out for every frame"), which the memory's upload counter shows.
// Swapped slices go through 2·kGroup slots of the memory, two halves: given the frame's
// order of eye points (beginSequence), a second thread uploads the next group of kGroup
// slices into one half while the polygons of the current group are drawn from the other.
// That changes no byte and no count: each slice is uploaded once, into a slot nothing reads
// meanwhile, and settle() waits for the last upload before the frame's counter is read.
class SliceTextures {
  public:
    static constexpr int kGroup = 16;

    SliceTextures(std::shared_ptr<tex::TextureMemory> memory, const LightField& lf);
    ~SliceTextures();
    SliceTextures(const SliceTextures&) = delete;
    SliceTextures& operator=(const SliceTextures&) = delete;
    bool resident() const { return resident_; }
    // The slices the next slice() calls will ask for, in order ((i, j) pairs); with
    // `overlap`, uploads run a group ahead on another thread. A slice() off the sequence
    // ends it (everything after is uploaded when asked for).
    void beginSequence(std::vector<glm::ivec2> order, bool overlap);
    // The texture holding slice (i, j), uploaded by now when swapping.
    std::shared_ptr<const tex::Texture> slice(int i, int j);
    // Waits for an upload in flight and ends the sequence.
    void settle();
    uint64_t sliceBytes() const;

  private:
    void uploadGroup(size_t group, bool async);  // the sequence's group into its half
    void upload(int slot, const glm::ivec2& ij);

    std::shared_ptr<tex::TextureMemory> memory_;
    const LightField* lf_;
    bool resident_ = false;
    std::vector<std::shared_ptr<tex::Texture>> slices_;
    // Swapping: the slots; eye point e of the sequence is in slot (e / kGroup mod 2)·kGroup
    // + e mod kGroup.
    std::vector<std::shared_ptr<tex::Texture>> stream_;
    int next_ = 0;  // the slot an upload off the sequence goes to next
    std::vector<glm::ivec2> order_;
    size_t cursor_ = 0;
    size_t groupsUploaded_ = 0;  // of the sequence: uploaded or in flight
    bool overlap_ = false;
    struct Pending;
    std::unique_ptr<Pending> pending_;  // a group's upload in flight
};

struct GortlerOptions {
    Triangulation triangulation = Triangulation::FixedDiagonal;
    tex::FilterMode filter = tex::FilterMode::Linear;  // (u, v) filtering of the slices
    bool clear = true;                                 // clear colour to 0 first
};

struct GortlerStats {
    int eyePoints = 0;          // eye points drawn
    int triangles = 0;
    uint64_t uploadBytes = 0;   // slice uploads this frame (0 when resident)
};

// The texture coordinates (u, v) of the ray from `eye` through the world point p on the
// (s, t) plane: where it meets the window, as window fractions.
glm::vec2 windowCoords(const LightSlab& slab, const glm::vec3& eye, const glm::vec3& p);

// Draws the reconstruction into `device` (which must be of the memory's profile) as seen by
// `camera` over the whole framebuffer. Between beginPass calls the caller's frame.
GortlerStats renderGortler(raster::Device& device, SliceTextures& slices, const LightField& lf,
                           const ray::Camera& camera, const GortlerOptions& options = {});

// The weighting state every Gortler-style pass shares: no depth, no culling, ONE/ONE.
raster::PipelineState additiveState();

}  // namespace rg::lightfield
