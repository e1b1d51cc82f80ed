// A 640x480 view through a 60° (vertical) perspective camera, for the tests that project
// points by hand: the focal length is kFocalPx pixels.
#pragma once

#include <cmath>
#include <numbers>

#include <glm/glm.hpp>

#include "raster/frame_trace.h"
#include "scene/camera.h"

namespace penumbra::testing {

inline const double kFocalPx = 240.0 / std::tan(std::numbers::pi / 6.0);

inline raster::StaticView cameraView(const glm::dvec3& eye, const glm::dvec3& target,
                                     const glm::dvec3& up) {
  raster::StaticView v;
  v.width = 640;
  v.height = 480;
  v.cameraViewProj =
      scene::toRasterMat4(scene::perspective(std::numbers::pi / 3.0, 640.0 / 480.0, 0.05, 20.0) *
                          scene::lookAt(eye, target, up));
  return v;
}

}  // namespace penumbra::testing
