#include "scene/camera_intrinsics.h"

#include <cmath>
#include <numbers>

namespace penumbra::scene {

glm::dvec2 Intrinsics::project(const glm::dvec3& c) const {
  const double x = c.x / c.z, y = c.y / c.z;
  // Brown–Conrady: radial factor 1 + k1 r^2 + k2 r^4 + k3 r^6 and the tangential terms,
  // in the order OpenCV's projectPoints documents, so both agree to rounding.
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const double xd = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x);
  const double yd = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y;
  return {fx * xd + cx, fy * yd + cy};
}

Camera toCamera(const Intrinsics& k, const Pose& pose, double zNear, double zFar,
                double* principalOffsetPx) {
  if (!(k.fx > 0 && k.fy > 0) || k.width <= 0 || k.height <= 0) {
    throw CalibrationError("camera intrinsics: focal lengths and image size must be positive");
  }
  // Camera axes in world coordinates: the rows of R (world -> camera).
  const glm::dmat3 rt = glm::transpose(pose.rotation);
  const glm::dvec3 forward = rt * glm::dvec3(0, 0, 1);
  const glm::dvec3 down = rt * glm::dvec3(0, 1, 0);
  Camera cam;
  cam.eye = pose.centre();
  cam.target = cam.eye + forward;
  cam.up = -down;
  // tan(fovY / 2) = (h / 2) / fy; aspect = tan(fovX / 2) / tan(fovY / 2) = (w fy) / (h fx).
  cam.fovYDegrees = 2.0 * std::atan(0.5 * k.height / k.fy) * 180.0 / std::numbers::pi;
  cam.aspect = (double(k.width) * k.fy) / (double(k.height) * k.fx);
  cam.zNear = zNear;
  cam.zFar = zFar;
  if (principalOffsetPx != nullptr) {
    // The symmetric frustum's axis passes through window (w/2, h/2), i.e. (u, v) =
    // (w/2 - 0.5, h/2 - 0.5) in the calibration convention.
    const double dx = k.cx - (0.5 * k.width - 0.5), dy = k.cy - (0.5 * k.height - 0.5);
    *principalOffsetPx = std::sqrt(dx * dx + dy * dy);
  }
  return cam;
}

}  // namespace penumbra::scene
