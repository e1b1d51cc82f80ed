// The ray-traced ground truth Penumbra is measured against (design §4; issue 5 item 1):
// HDR differential rendering (Debevec 1998; Gibson 2003 §7 eq. 1) by Monte Carlo ray
// tracing of the same patch mesh, the same emitting patches and the same placed product.
//
// Per pixel, `samplesPerPixel` jittered camera rays. Where a ray hits the room at x
// (normal n, reflectance rho), the direct light from every emitting patch j (one-sided,
// emitting towards its normal, radiance E_j) is
//
//   L(x) = rho (*) sum_j E_j [ F_j(x) - integral over patch j of (1 - V(x, y)) k(x, y) dA_y ],
//   k(x, y) = cos_x cos_y / (pi r^2),
//
// F_j the closed-form point-to-polygon form factor (lighting/form_factor.h) and V the
// visibility. The blocked integral is estimated with `lightSamples` shadow rays per camera
// ray, spread over the emitters in proportion to lum(E_j) F_j(x) (systematic sampling of
// that distribution, then a uniform point on the chosen patch): an unbiased estimator whose
// variance is zero wherever every sample is visible, so unshadowed surfaces come out
// noise-free. The same samples, tested against the room only and against room + product,
// give L_noobj and L_obj; their difference comes only from samples the product blocks,
// hence is exactly 0 where the product casts no shadow (the "object far away equals the
// background" property of differential rendering).
//
// With `bounces` > 0 each surface point also gathers one cosine-distributed indirect ray
// per camera sample and bounce (path tracing with next-event estimation, Shirley &
// Marschner, FCG ch. 23): emitters are counted only through the direct term. The paths
// with and without the product share their random numbers until the product changes them.
//
// Determinism: every random number is a counter-based hash of (seed, pixel, camera sample,
// draw index) (core/random.h), every sum runs in a fixed order inside one pixel, and
// a pixel is written by one thread: the image is the same bytes for any thread count.
// Unlike the per-frame path, this offline renderer uses libm (form factors, sampling).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"
#include "raster/frame_trace.h"
#include "scene/patch_mesh.h"
#include "shadow/scene_bundle.h"

namespace penumbra::reference {

// The synthetic object, placed in world space (shadow::placeMesh), diffuse. Shaded as the
// per-frame path shades it (shadow/product_shading.h): at a hit, the normal is its triangle's
// vertex normals interpolated barycentrically and normalized, and the reflectance its vertex
// reflectances interpolated; the geometric normal (towards the ray) only offsets the shadow
// and bounce rays off the surface. Without normals: the flat face normal.
struct ReferenceObject {
  core::Mesh mesh;
  glm::dvec3 reflectance{0.5};             // every vertex's, when `reflectances` is empty
  std::vector<glm::dvec3> normals{};       // empty, or one per vertex (any positive length)
  std::vector<glm::dvec3> reflectances{};  // empty, or one per vertex
};

struct ReferenceScene {
  scene::PatchMesh room;  // patches carry reflectance and emission
  // World -> GL clip space. Pixel (px, py) (row 0 at the top) sample (jx, jy) in [0, 1)^2
  // casts the segment from the unprojected near-plane point of NDC
  // ((px + jx) / (width / 2) - 1, 1 - (py + jy) / (height / 2)) to the far-plane point,
  // the camera rays of lighting::patchesVisibleFromCamera with jitter.
  glm::dmat4 viewProj{1.0};
  uint32_t width = 0, height = 0;
  // Another camera model (e.g. the mirrored-ball probe of the synthetic showroom): maps
  // the window position (px + jx, py + jy) to a ray origin + t dir, t in [0, tMax]; returns
  // false where the image shows nothing (black). Must be a pure function. When set,
  // viewProj is not used.
  std::function<bool(double xw, double yw, glm::dvec3& origin, glm::dvec3& dir, double& tMax)>
      cameraRay;
  std::optional<ReferenceObject> object;
};

struct ReferenceOptions {
  int samplesPerPixel = 4;  // jittered camera rays per pixel
  // Every camera ray through the pixel's centre (the samples then only average the light):
  // the quantity Penumbra's rasterizer computes, which samples coverage and attributes at
  // pixel centres and has no anti-aliasing. Off: jittered over the pixel (anti-aliased),
  // which also counts a point-sampled image's aliasing at silhouettes and contact lines.
  bool pixelCentres = false;
  int lightSamples = 32;  // shadow rays per surface point, over all emitters
  // Every shadow ray aimed at its emitter's centre: each emitting patch is then blocked or
  // not as a whole, as seen from its centre, while its unblocked light stays the polygon's
  // closed form. That is the light of Penumbra's passes, each cast from a point; the
  // difference to the default (rays spread over each patch) is what the point sources cost
  // (docs/accuracy.md: where the remaining error comes from).
  bool pointLights = false;
  int bounces = 0;  // indirect bounces (0: direct light only)
  // Only what differential rendering reads (reference/differential.h): roomDelta, the
  // product's radiance and coverage. With direct light only, a room point whose every
  // emitter lies outside the cone of the product's bounding sphere (seen from the point) can
  // lose no light to the product: its delta is exactly 0 and its light is not gathered, so
  // noObject and withObject hold only its emission there, and noObject nothing behind the
  // product. roomDelta, objectRadiance and objectCoverage are the same bytes as without (the
  // skipped samples' deltas were 0, and every sample draws from its own stream). With
  // bounces it changes nothing: the product can take indirect light from anywhere.
  bool differenceOnly = false;
  unsigned threads = 0;  // 0 = hardware concurrency; the bytes do not depend on it
  uint64_t seed = 1;
  double normalOffset = 1e-4;  // metres: shadow and bounce rays start this far off a surface
  // Only the pixels x in [x0, x1), y in [y0, y1) are rendered; the others are left as pixels
  // no sample reached (composeDifferential shows the background there). Empty: the whole
  // image. What a test needs around one product's contact band, at a fraction of the cost.
  struct Window {
    uint32_t x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  };
  std::optional<Window> window;
};

// Per pixel, means over the camera samples (row 0 at the top, width * height entries).
struct ReferenceImage {
  uint32_t width = 0, height = 0;
  std::vector<glm::vec3> noObject;    // L_noobj: the room without the product
  std::vector<glm::vec3> withObject;  // L_obj: with it (its own radiance where it is seen)
  // Over the samples that hit the room: mean of L_noobj - L_obj (the light the product
  // takes away, Gibson 2003 eq. 1); 0 when no sample hit the room.
  std::vector<glm::vec3> roomDelta;
  // Over the samples that hit the product: mean of its radiance; 0 when none did.
  std::vector<glm::vec3> objectRadiance;
  std::vector<float> objectCoverage;  // share of the camera samples that hit the product
};

// The bundle's room, view and (when `pose` is given) its product placed by
// shadow::placeMesh, exactly where `penumbra render` draws it. Throws std::invalid_argument
// for a product index out of range or a non-finite pose.
ReferenceScene referenceSceneOf(const shadow::SceneBundle& bundle,
                                const std::optional<shadow::ProductPose>& pose);

// Per-pixel radiance as the HDR image type the EXR writer takes (lighting/exr_io.h).
core::ImageF hdrImageOf(uint32_t width, uint32_t height, const std::vector<glm::vec3>& radiance);

// Called after each finished image row with (rows done, rows); from worker threads, one
// call at a time.
using ReferenceProgress = std::function<void(uint32_t done, uint32_t total)>;

// Throws std::invalid_argument for a zero or oversized image (raster::kMaxImageSide), a
// singular viewProj, samplesPerPixel or lightSamples outside 1..65536, bounces outside
// 0..16, an inconsistent mesh or non-finite geometry.
ReferenceImage renderReference(const ReferenceScene& scene, const ReferenceOptions& options,
                               const ReferenceProgress& progress = {});

}  // namespace penumbra::reference
