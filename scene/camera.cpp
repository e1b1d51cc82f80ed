#include "scene/camera.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace penumbra::scene {

glm::dmat4 lookAt(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up) {
  const glm::dvec3 fwd = target - eye;
  if (!(glm::length(fwd) > 0)) throw std::invalid_argument("lookAt: eye equals target");
  const glm::dvec3 f = glm::normalize(fwd);
  const glm::dvec3 side = glm::cross(f, up);
  if (!(glm::length(side) > 1e-12)) throw std::invalid_argument("lookAt: up parallel to view");
  const glm::dvec3 s = glm::normalize(side);
  const glm::dvec3 u = glm::cross(s, f);
  glm::dmat4 m(1.0);  // columns: m[c][r]
  // One matrix row per line reads as the math.
  // clang-format off
  m[0][0] = s.x;  m[1][0] = s.y;  m[2][0] = s.z;  m[3][0] = -glm::dot(s, eye);
  m[0][1] = u.x;  m[1][1] = u.y;  m[2][1] = u.z;  m[3][1] = -glm::dot(u, eye);
  m[0][2] = -f.x; m[1][2] = -f.y; m[2][2] = -f.z; m[3][2] = glm::dot(f, eye);
  // clang-format on
  return m;
}

glm::dmat4 perspective(double fovYRadians, double aspect, double zNear, double zFar) {
  if (!(fovYRadians > 0 && fovYRadians < std::numbers::pi) || !(aspect > 0) ||
      !(zNear > 0 && zNear < zFar)) {
    throw std::invalid_argument("perspective: bad field of view, aspect or depth range");
  }
  return perspectiveFromTanHalf(std::tan(0.5 * fovYRadians), aspect, zNear, zFar);
}

glm::dmat4 perspectiveFromTanHalf(double tanHalfFovY, double aspect, double zNear, double zFar) {
  if (!(tanHalfFovY > 0 && std::isfinite(tanHalfFovY)) || !(aspect > 0) ||
      !(zNear > 0 && zNear < zFar)) {
    throw std::invalid_argument("perspective: bad field of view, aspect or depth range");
  }
  const double f = 1.0 / tanHalfFovY;
  glm::dmat4 m(0.0);
  m[0][0] = f / aspect;
  m[1][1] = f;
  m[2][2] = (zFar + zNear) / (zNear - zFar);
  m[3][2] = 2.0 * zFar * zNear / (zNear - zFar);
  m[2][3] = -1.0;
  return m;
}

core::Mat4 toRasterMat4(const glm::dmat4& m) {
  core::Mat4 out;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) out.m[4 * r + c] = static_cast<float>(m[c][r]);
  }
  return out;
}

glm::dmat4 fromRasterMat4(const core::Mat4& m) {
  glm::dmat4 out;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) out[c][r] = m.m[4 * size_t(r) + size_t(c)];
  }
  return out;
}

glm::dmat4 Camera::projection() const {
  glm::dmat4 m = perspective(fovYDegrees * std::numbers::pi / 180.0, aspect, zNear, zFar);
  // x_ndc += principalNdc.x (w_clip = -z_eye); only when set, so symmetric cameras keep
  // exactly the matrices (and golden frames) they had.
  if (principalNdc.x != 0) m[2][0] = -principalNdc.x;
  if (principalNdc.y != 0) m[2][1] = -principalNdc.y;
  return m;
}

glm::dvec3 Camera::rayDirection(double xw, double yw, double width, double height) const {
  // Window -> NDC as the inverse of the viewport of spec §2 (y flips), then through the
  // same basis lookAt() builds.
  const double nx = xw / (0.5 * width) - 1.0 - principalNdc.x;
  const double ny = 1.0 - yw / (0.5 * height) - principalNdc.y;
  const double tanHalf = std::tan(0.5 * fovYDegrees * std::numbers::pi / 180.0);
  const glm::dvec3 f = glm::normalize(target - eye);
  const glm::dvec3 s = glm::normalize(glm::cross(f, up));
  const glm::dvec3 u = glm::cross(s, f);
  return glm::normalize(f + (nx * tanHalf * aspect) * s + (ny * tanHalf) * u);
}

}  // namespace penumbra::scene
