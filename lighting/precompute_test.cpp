// `penumbra precompute` refuses what `render` would refuse (issue 18): a scene whose camera
// sees no surface of the room, and a patch size override that cuts the room into more
// patches than precompute handles, or a shadow-boundary refinement that does.
#include "lighting/precompute.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <tuple>

#include "tests/test_data.h"

namespace penumbra::lighting {
namespace {

const scene::SceneDescription& showroom() {
  static const scene::SceneDescription s =
      scene::loadSceneFile(testing::dataDir() / "showroom" / "showroom.json");
  return s;
}

std::string refusal(const scene::SceneDescription& s, const PrecomputeOptions& options) {
  std::vector<StageTiming> timings;
  try {
    precomputeBundle(s, options, timings);
  } catch (const scene::SceneFileError& e) {
    return e.what();
  }
  return "accepted";
}

// It printed "receivers 0" and exited 0; `render` then segfaulted on the bundle.
TEST(Precompute, CameraSeeingNoReceiverIsRefused) {
  scene::SceneDescription s = showroom();
  s.camera.eye = glm::dvec3(-5, 1.6, 2);  // outside the room, looking away from it
  s.camera.target = glm::dvec3(-10, 1.6, 2);
  EXPECT_EQ(refusal(s, {}),
            s.source.string() +
                ": camera: sees no surface of the room (0 receivers): aim camera.target at the "
                "room");
}

TEST(Precompute, PatchSizeOverrideIsBounded) {
  PrecomputeOptions options;
  options.patchSize = 0.02;
  const std::string why = refusal(showroom(), options);
  EXPECT_EQ(why.rfind(showroom().source.string() + ": patch size 0.02: cuts the room into ", 0), 0u)
      << why;
  EXPECT_NE(why.find(" patches, more than the 20000 precompute handles"), std::string::npos) << why;
}

// The grid count is checked before the mesh is built; shadow-boundary refinement grows it
// afterwards, by as much as the lights' shadow edges need, so it is bounded while it cuts.
TEST(Precompute, ShadowBoundaryRefinementIsBounded) {
  scene::SceneDescription s = showroom();
  s.room.shadowBoundaryPatchSize = 0.02;
  PrecomputeOptions options;
  options.patchSize = 0.13;  // 8,285 grid patches; the desk's shadow edges add the rest
  EXPECT_EQ(refusal(s, options),
            s.source.string() +
                ": shadow_boundary_patch_size: 0.02 m refines the room into more than the 20000 "
                "patches precompute handles: use a larger shadow_boundary_patch_size");
}

// Issue 17's scene models: the spotlight showroom's 0.2 m spot is one patch, so one source;
// cut at 5 cm it is 16 sources that emit the same power, the rest of the room unchanged
// but for the grid lines the finer strips run across the ceiling.
TEST(Precompute, EmitterPatchSizeCutsOnlyTheEmittersFiner) {
  const scene::SceneDescription spot =
      scene::loadSceneFile(testing::dataDir() / "showroom" / "spotlight.json");
  auto emitters = [&](double size) {
    PrecomputeOptions options;
    options.emitterPatchSize = size;
    const scene::PatchMesh mesh = precomputePatchMesh(spot, options);
    size_t count = 0;
    glm::dvec3 power(0.0);
    double largest = 0;
    for (const scene::Patch& p : mesh.patches) {
      if (!p.emits()) continue;
      ++count;
      power += p.emission * p.area;
      largest = std::max(largest, p.area);
    }
    return std::tuple{count, power, largest};
  };
  const auto [whole, wholePower, wholeArea] = emitters(0);
  const auto [cut, cutPower, cutArea] = emitters(0.05);
  EXPECT_EQ(whole, 1u);
  EXPECT_EQ(cut, 16u);
  EXPECT_NEAR(wholeArea, 0.04, 1e-12);
  EXPECT_NEAR(cutArea, 0.0025, 1e-12);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(cutPower[c], wholePower[c], 1e-9 * wholePower[c]);
  // A size finer than the scene's own is not coarsened back.
  EXPECT_EQ(std::get<0>(emitters(0.3)), 1u);
  std::vector<StageTiming> timings;
  PrecomputeOptions options;
  options.emitterPatchSize = 0.05;
  EXPECT_EQ(precomputeBundle(spot, options, timings).sets.sources.size(), 16u);
  options.emitterPatchSize = 0.01;
  EXPECT_EQ(refusal(spot, options),
            spot.source.string() + ": emitter patch size 0.01: is not in [0.02, 10] metres");
}

}  // namespace
}  // namespace penumbra::lighting
