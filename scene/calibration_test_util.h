// Shared by the calibration tests: a camera pose that looks from `eye` at `target`, in the
// calibration convention (x right, y down, z forward) with world +y up.
#pragma once

#include <glm/glm.hpp>

#include "scene/camera_intrinsics.h"

namespace penumbra::scene::testutil {

inline Pose lookFrom(const glm::dvec3& eye, const glm::dvec3& target,
                     const glm::dvec3& up = {0, 1, 0}) {
  const glm::dvec3 z = glm::normalize(target - eye);
  const glm::dvec3 x = glm::normalize(glm::cross(z, up));
  const glm::dvec3 y = glm::cross(z, x);
  Pose p;
  // Rows of R are the camera axes in world coordinates (glm: m[col][row]).
  for (int c = 0; c < 3; ++c) {
    p.rotation[c][0] = x[c];
    p.rotation[c][1] = y[c];
    p.rotation[c][2] = z[c];
  }
  p.translation = -(p.rotation * eye);
  return p;
}

}  // namespace penumbra::scene::testutil
