// Small frame traces built in code, for tests that must not depend on bundled data.
#pragma once

#include <cstdint>

#include "raster/frame_trace.h"

namespace penumbra::testing {

struct TestSceneOptions {
  uint32_t width = 160, height = 120;
  int floorCells = 12;  // floor grid cells per side (2 triangles each), plus a back wall
  int passes = 6;
  bool pcf2x2 = false;
  bool objectVisible = true;
  float objectOffsetX = 0.0f;  // moves the object (and its occluder proxy)
  uint64_t seed = 1;
};

// A floor and a back wall seen by a perspective camera, a box object standing on the floor
// that is also the occluder proxy, passes lit from point sources above, S pseudo-random.
raster::FrameTrace makeTestScene(const TestSceneOptions& options);

}  // namespace penumbra::testing
