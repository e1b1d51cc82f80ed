// Camera matrices with OpenGL conventions: clip = P * V * world, visible when
// -w <= x, y, z <= w (docs/trace-format.md, docs/pipeline-spec.md §2). Everything is
// computed in double and rounded to the trace's float matrix once, at the end, so the
// trace does not inherit float error from the composition.
#pragma once

#include <glm/glm.hpp>

#include "core/geometry.h"

namespace penumbra::scene {

// Right-handed view matrix: the eye at the origin looking down -z, `up` projected to +y.
// Throws std::invalid_argument when eye == target or `up` is parallel to the view.
glm::dmat4 lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up);

// GL perspective: view-space depth -zNear maps to z/w = -1 and -zFar to +1.
// Throws std::invalid_argument unless 0 < fovY < pi, aspect > 0, 0 < zNear < zFar.
glm::dmat4 perspective(double fovYRadians, double aspect, double zNear, double zFar);

// The same from tan(fovY / 2) directly: no libm, for the per-frame light frusta.
glm::dmat4 perspectiveFromTanHalf(double tanHalfFovY, double aspect, double zNear, double zFar);

// GLM stores columns (m[c][r]); the trace stores rows (element (r, c) at m[4r + c]).
core::Mat4 toRasterMat4(const glm::dmat4& m);
// And back, widened to double exactly (the trace's camera as GLM multiplies it).
glm::dmat4 fromRasterMat4(const core::Mat4& m);

struct Camera {
  glm::dvec3 eye{0.0}, target{0, 0, -1}, up{0, 1, 0};
  double fovYDegrees = 60;
  double aspect = 4.0 / 3.0;
  double zNear = 0.05, zFar = 20;
  // Off-axis frustum (a calibrated camera whose principal point is not at the image centre,
  // lighting/capture.h): the principal point's NDC position. Zero: the symmetric frustum.
  glm::dvec2 principalNdc{0.0};

  glm::dmat4 view() const { return lookAt(eye, target, up); }
  glm::dmat4 projection() const;
  glm::dmat4 viewProj() const { return projection() * view(); }
  core::Mat4 rasterViewProj() const { return toRasterMat4(viewProj()); }
  // Unit world-space direction through window position (xw, yw) of a width x height
  // image (row 0 at the top; pixel centres at +0.5), consistent with viewProj().
  glm::dvec3 rayDirection(double xw, double yw, double width, double height) const;
};

}  // namespace penumbra::scene
