// Camera calibration from marked vanishing points (Gibson & Chalmers 2003 §3): the user
// marks, in one photograph, two pairs of image lines along each of two orthogonal room
// directions (e.g. floor edges along x and along z). Each pair meets in a vanishing point
// v, v'. With the principal point c at the image centre and square pixels,
//   f^2 = -((v - c) . (v' - c))                      (tutorial §3, eq. 1)
// because the rays (v - c, f) and (v' - c, f) are orthogonal. Those rays are the two room
// axes in camera coordinates; the third is their cross product. The translation comes from
// a marked origin (the world origin lies on its ray) and marked points at known distances
// along the axes, which also fix each axis' sign. docs/calibration.md documents the marks
// file; data/calibration/vanishing-marks.json is an example.
//
// Pure math on GLM (no OpenCV): part of penumbra_scene. Offline only.
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "scene/camera_intrinsics.h"

namespace penumbra::scene {

struct ImageLine {
  glm::dvec2 a{0.0}, b{0.0};
};

// A marked point at `distance` (world units, > 0) from the origin along +axis.
struct AxisPoint {
  glm::dvec2 image{0.0};
  double distance = 1;
};

struct VanishingMarks {
  std::string source = "marks";  // the file name, for errors
  int width = 0, height = 0;
  // Two lines per direction (index 0 = x, 1 = y, 2 = z) for exactly two directions.
  std::array<std::optional<std::array<ImageLine, 2>>, 3> lines;
  glm::dvec2 origin{0.0};  // image of the world origin
  // Required for both line-marked axes (they fix the axis signs), optional for the third.
  std::array<std::optional<AxisPoint>, 3> axisPoints;
};

// Reads a marks file (docs/calibration.md). Throws CalibrationError naming the file and
// the field for unreadable files, malformed JSON, missing or unknown fields, non-finite
// numbers and wrong counts.
VanishingMarks loadVanishingMarks(const std::filesystem::path& path);

struct VanishingCalibration {
  Intrinsics intrinsics;  // fx = fy = f, principal point at the image centre, no distortion
  Pose pose;              // world -> camera
  std::array<int, 2> markedAxes{0, 0};          // the two line-marked axes (0 = x, 1 = y, 2 = z)
  int derivedAxis = 0;                          // the third, from the cross product
  std::array<glm::dvec2, 2> vanishingPoints{};  // of markedAxes, in pixels
  // Reprojection of the origin and every axis point (residual per point, in the order
  // origin, then axis points x, y, z that are present) and their RMS.
  std::vector<double> residualsPx;
  double rmsPx = 0;
};

// Throws CalibrationError naming marks.source and the mark for degenerate input: a line
// of zero length, a pair of parallel lines (vanishing point at infinity), f^2 <= 0 (the
// two directions are not orthogonal as seen), an axis point on the origin or pointing
// neither towards nor away from its vanishing point, an origin behind the camera.
VanishingCalibration calibrateFromVanishingPoints(const VanishingMarks& marks);

// The vanishing point of two image lines (homogeneous intersection). Throws
// CalibrationError("<what>: ...") when a line has zero length or the lines are parallel.
glm::dvec2 vanishingPoint(const ImageLine& l0, const ImageLine& l1, const std::string& what);

}  // namespace penumbra::scene
