// `penumbra precompute` refuses what `render` would refuse (issue 18): a scene whose camera
// sees no surface of the room, and a patch size override that cuts the room into more
// patches than precompute handles, or a shadow-boundary refinement that does.
#include "lighting/precompute.h"

#include <gtest/gtest.h>

#include <string>

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

}  // namespace
}  // namespace penumbra::lighting
