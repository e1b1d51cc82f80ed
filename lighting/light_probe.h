// Light probe → patch mesh (Gibson & Chalmers 2003 §4.2): an HDR probe image taken at a known
// pose in the room is projected outwards onto every patch; a patch's radiance is the probe
// radiance averaged over the patch, and its diffuse reflectance is that radiance divided by
// the irradiance it gathers from the other patches (lighting/patch_radiosity.h). Patches the
// probe cannot see get a default reflectance (0.5) and radiance by gathering. The result is
// a scene::Material per patch that precompute takes instead of the scene file's materials
// (PrecomputeOptions::measuredMaterials), so a captured room flows through the same path.
//
// Emitters vs reflectors (our rule, the tutorial treats every surface as diffuse): with G the
// gathered irradiance over pi, a seen patch whose radiance luminance exceeds G's (implied
// reflectance > 1: it sends more light than anything could make it reflect) is an emitter:
// reflectance = the default, emission = max(0, L - default (*) G) per channel. Other seen
// patches get reflectance L / G per channel, clamped to [0, 1]; where G is 0 (no light
// reaches the patch) a bright patch is an emitter with emission L, a black one keeps the
// default reflectance.
//
// Offline only: libm is used freely (atan2, acos), results are deterministic for any thread
// count (each patch on one thread, fixed-order sums, counter-based sample jitter).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/image.h"
#include "lighting/embree_scene.h"
#include "lighting/hdr_image.h"
#include "scene/patch_mesh.h"

namespace penumbra::lighting {

enum class ProbeMapping {
  // Equirectangular: column = azimuth, row = polar angle from +y (row 0 looks up). Azimuth
  // 0 (the image centre column) looks along -z, increasing towards +x.
  LatLong,
  // A photograph of a mirrored sphere filling the square image, camera looking along -z of
  // the probe frame (Debevec's light-probe format): direction d reflects in the ball point
  // whose normal is normalize(d + (0, 0, 1)).
  MirrorBall,
  // Equidistant fisheye looking along -z, image up = +y: radius proportional to the angle
  // from the axis, fisheyeFovDegrees across the inscribed circle.
  Fisheye,
};

struct LightProbe {
  core::ImageF image;  // the radiance image (lighting/exr_io.h reads one from an EXR file)
  ProbeMapping mapping = ProbeMapping::LatLong;
  glm::dvec3 position{0.0};  // probe centre in the room frame (metres)
  glm::dmat3 rotation{1.0};  // probe frame → room frame (columns: probe axes in the room)
  double fisheyeFovDegrees = 180;

  // Radiance seen along room-frame direction `d` (any length): the nearest pixel, or
  // nothing (returns false) outside a fisheye's circle. Throws std::invalid_argument for an
  // empty or mis-sized image.
  bool radiance(const glm::dvec3& d, glm::dvec3& out) const;
  // The room-frame unit direction of pixel centre (x + 0.5, y + 0.5); false where the
  // pixel lies outside the mapping's disc (mirror ball, fisheye).
  bool direction(uint32_t x, uint32_t y, glm::dvec3& out) const;
};

struct ProbeSanitizeReport {
  size_t nonFinite = 0;  // NaN or infinite channel values, set to 0
  size_t negative = 0;   // negative values (lossy compression), set to 0
  size_t saturated = 0;  // pixels with a channel >= saturationLevel, kept at their value
  float mostNegative = 0;
};

// Clamps the image in place and counts what it did. saturationLevel <= 0 disables the count.
ProbeSanitizeReport sanitizeProbe(core::ImageF& image, float saturationLevel);

struct ProbeProjectionOptions {
  int samplesPerSide = 4;  // jittered samples per patch side (inset from its edges)
  double inset = 0.1;      // fraction of each side kept clear of neighbouring patches' pixels
  glm::dvec3 defaultReflectance{0.5};
  int unseenIterations = 10;  // gathering steps for the unseen patches' radiance
  // Channel values at or above this are counted as saturated (the camera clipped; the
  // true radiance is higher). <= 0: no check.
  float saturationLevel = 0;
  unsigned threads = 2;
  uint64_t seed = 0x50524F4245ull;  // "PROBE"
};

struct ProbeProjection {
  std::vector<glm::dvec3> radiance;        // per patch: measured or gathered
  std::vector<glm::dvec3> gathered;        // per patch: irradiance over pi, G
  std::vector<scene::Material> materials;  // per patch
  std::vector<uint8_t> seen;               // per patch: 1 when the probe saw it
  size_t seenPatches = 0, emitters = 0, clampedReflectances = 0;
  ProbeSanitizeReport sanitize;
  std::vector<std::string> warnings;  // what was clamped or guessed, for the user
};

// Projects `probe` (sanitized copy) onto `mesh`. Throws std::invalid_argument for a bad
// image, samplesPerSide < 1 or a probe outside every patch's view (nothing seen).
ProbeProjection projectProbe(const LightProbe& probe, const scene::PatchMesh& mesh,
                             const EmbreeScene& rays, const ProbeProjectionOptions& options = {});

// Ray-casts a probe image of a room whose per-patch radiance is known (synthetic tests and
// the capture generator, lighting/capture_synth.h): every pixel of `probe.image` (already
// sized) inside the mapping's disc shows the radiance of the patch its ray from
// probe.position hits first, black where it hits nothing. The inverse of projectProbe.
void renderProbe(LightProbe& probe, const scene::PatchMesh& mesh, const EmbreeScene& rays,
                 const std::vector<glm::dvec3>& patchRadiance);

}  // namespace penumbra::lighting
