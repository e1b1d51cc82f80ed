// `penumbra precompute`: a showroom description to a scene bundle (design §1, offline).
//
// Stages, each timed: patch mesh (Gibson 2003 §4), camera visibility and the source and
// receiver sets (§4), radiance transfers with ray-cast visibility (§5), the background
// "photograph" (the room as the transfers light it, through T()), and the products with
// their shadow proxies (§7.2). The shaft hierarchy is rebuilt from the bundle at load
// (milliseconds, deterministic), so it is not stored.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "scene/patch_mesh.h"
#include "scene/scene_file.h"
#include "shadow/scene_bundle.h"

namespace penumbra::lighting {

struct PrecomputeOptions {
  // §4: share of the emitted power the source set holds; 0 = the scene file's power_share.
  double powerShare = 0;
  int samplesPerSide = 4;  // visibility samples per source patch side (§5)
  unsigned threads = 2;
  uint64_t seed = 1;
  double patchSize = 0;  // metres; 0 = the scene file's patch_size
  // Emitters cut into patches of at most this size, metres; 0 = as the scene file cuts them.
  // Each emitter patch is a source, and each source one point of light in a pass, so a
  // small emitter drawn as one patch casts one edge where its penumbra integrates over its
  // area; cut finer, its passes sample that area (issue 17's scene models, docs/tuning.md).
  double emitterPatchSize = 0;
  // Measured light (lighting/light_probe.h, Gibson & Chalmers 2003 §4.2): one material per
  // patch of the mesh this scene and patchSize build, replacing the scene file's
  // materials. Empty: the scene file's. A count mismatch throws std::invalid_argument.
  std::vector<scene::Material> measuredMaterials;
  // Outgoing radiance per patch (e.g. ProbeProjection::radiance) for the irradiance volume.
  // Empty: solved from the materials with `radianceBounces` gathering steps.
  std::vector<glm::dvec3> measuredRadiance;
  // Measured camera response and photograph (lighting/capture.h): T() at the kiosk's live
  // exposure replaces the scene file's tone, and an RGBA8 photograph of width x height
  // replaces the rendered background (a size mismatch throws std::invalid_argument).
  std::optional<shadow::ToneCurve> tone;
  std::vector<uint8_t> background;
  int radianceBounces = 1;  // 1: direct light from the emitters; each more: one interreflection
  bool irradianceVolume = true;  // false: products keep the form-factor shading
  glm::uvec3 volumeDims{20, 10, 20};
  int volumeDirectionsPerSide = 12;
};

// Issue 17's volume scene models: PrecomputeOptions' default grid with each axis times
// `scale` (rounded, at least 1 cell). Throws std::invalid_argument unless scale is in (0, 8].
glm::uvec3 scaledVolumeDims(double scale);

struct StageTiming {
  std::string stage;
  double ms;
};

// Called at the start of each stage with its name, its index and the stage count.
using ProgressCallback = std::function<void(const std::string& stage, int index, int count)>;

// The patch mesh precompute builds for `scene` and `options` (patch size override
// included), before measured materials: build a light probe's ProbeProjection on this mesh
// so its per-patch materials and radiance line up with measuredMaterials/measuredRadiance.
scene::PatchMesh precomputePatchMesh(const scene::SceneDescription& scene,
                                     const PrecomputeOptions& options);

shadow::SceneBundle precomputeBundle(const scene::SceneDescription& scene,
                                     const PrecomputeOptions& options,
                                     std::vector<StageTiming>& timings,
                                     const ProgressCallback& progress = {});

}  // namespace penumbra::lighting
