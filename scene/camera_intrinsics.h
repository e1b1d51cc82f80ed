// A calibrated pinhole camera in the convention of the calibration literature (and of
// OpenCV): camera coordinates x right, y down, z forward (into the scene); image position
// (u, v) in pixels with the centre of the top-left pixel at (0, 0). The renderer puts
// pixel centres at +0.5 (scene/camera.h), so its window position is (u + 0.5, v + 0.5);
// `toCamera` takes care of that shift.
//
// Brown–Conrady lens distortion with k1, k2, k3 (radial) and p1, p2 (tangential), the
// model OpenCV's calibrateCamera estimates. These are offline types: nothing here runs in
// the per-frame path, so libm is fine.
#pragma once

#include <stdexcept>
#include <string>

#include <glm/glm.hpp>

#include "core/error.h"
#include "scene/camera.h"

namespace penumbra::scene {

class CalibrationError : public core::Error {
 public:
  using core::Error::Error;
};

struct Intrinsics {
  int width = 0, height = 0;  // image size in pixels
  double fx = 0, fy = 0;      // focal lengths in pixels
  double cx = 0, cy = 0;      // principal point in pixels
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;

  // Image position of a point given in camera coordinates (z > 0), with distortion.
  glm::dvec2 project(const glm::dvec3& cameraPoint) const;
  bool hasDistortion() const { return k1 != 0 || k2 != 0 || p1 != 0 || p2 != 0 || k3 != 0; }
};

// World -> camera: x_cam = rotation * x_world + translation (a proper rotation).
struct Pose {
  glm::dmat3 rotation{1.0};
  glm::dvec3 translation{0.0};

  glm::dvec3 toCamera(const glm::dvec3& world) const { return rotation * world + translation; }
  // The camera centre in world coordinates: -R^T t.
  glm::dvec3 centre() const { return -(glm::transpose(rotation) * translation); }
};

// Image position of world point `world` seen by a camera with these intrinsics and pose.
inline glm::dvec2 projectPoint(const Intrinsics& k, const Pose& pose, const glm::dvec3& world) {
  return k.project(pose.toCamera(world));
}

// The renderer's camera (scene/camera.h, OpenGL conventions) for a calibrated camera.
// scene::Camera is a symmetric frustum without distortion, so it keeps fx, fy and the
// pose exactly but assumes the principal point at the image centre; the pixel offset this
// causes is returned in `principalOffsetPx` (|c - image centre|) so callers can report it.
// Throws CalibrationError for non-positive focal lengths or image sizes.
Camera toCamera(const Intrinsics& k, const Pose& pose, double zNear, double zFar,
                double* principalOffsetPx = nullptr);

}  // namespace penumbra::scene
