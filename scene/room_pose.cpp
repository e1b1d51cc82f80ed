#include "scene/room_pose.h"

#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>

#include "core/json_reader.h"

namespace penumbra::scene {
namespace {

bool finite(const glm::dvec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace

PoseFit fitPose(const Intrinsics& k, const std::vector<CornerMark>& marks,
                const std::string& source) {
  if (!(k.fx > 0 && k.fy > 0) || !std::isfinite(k.cx) || !std::isfinite(k.cy)) {
    throw CalibrationError(source, "",
                           "intrinsics need positive focal lengths and a finite principal point");
  }
  if (marks.size() < 4) {
    throw CalibrationError(source, "",
                           std::to_string(marks.size()) + " corner mark(s), need at least 4");
  }
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (size_t i = 0; i < marks.size(); ++i) {
    const CornerMark& m = marks[i];
    const std::string name = m.name.empty() ? "corners[" + std::to_string(i) + "]" : m.name;
    if (!finite(m.world) || !std::isfinite(m.image.x) || !std::isfinite(m.image.y)) {
      throw CalibrationError(source, name, "not a finite number");
    }
    object.emplace_back(m.world.x, m.world.y, m.world.z);
    image.emplace_back(m.image.x, m.image.y);
  }
  // The world points must span at least a plane: the largest triangle they form must not
  // be a sliver relative to their extent.
  double extent = 0, bestArea = 0;
  for (size_t i = 1; i < marks.size(); ++i) {
    extent = std::max(extent, glm::length(marks[i].world - marks[0].world));
    for (size_t j = i + 1; j < marks.size(); ++j) {
      const double area =
          glm::length(glm::cross(marks[i].world - marks[0].world, marks[j].world - marks[0].world));
      bestArea = std::max(bestArea, area);
    }
  }
  if (!(extent > 0) || !(bestArea > 1e-6 * extent * extent)) {
    throw CalibrationError(source, "",
                           "the marked room points are coincident or collinear: no pose");
  }
  const cv::Matx33d camera(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
  const cv::Matx<double, 5, 1> dist(k.k1, k.k2, k.p1, k.p2, k.k3);
  cv::Mat rvec, tvec;
  bool ok = false;
  try {
    // EPnP gives a start without a guess (and handles planar sets); the iterative method
    // and LM refinement then minimise the reprojection error.
    ok = cv::solvePnP(object, image, camera, dist, rvec, tvec, false,
                      marks.size() >= 6 ? cv::SOLVEPNP_EPNP : cv::SOLVEPNP_SQPNP);
    if (ok) {
      ok = cv::solvePnP(object, image, camera, dist, rvec, tvec, true, cv::SOLVEPNP_ITERATIVE);
    }
    if (ok) cv::solvePnPRefineLM(object, image, camera, dist, rvec, tvec);
  } catch (const cv::Exception& e) {
    throw CalibrationError(source, "", std::string("solvePnP failed: ") + e.what());
  }
  if (!ok) throw CalibrationError(source, "", "solvePnP found no pose");
  cv::Mat r;
  cv::Rodrigues(rvec, r);
  PoseFit fit;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) fit.pose.rotation[j][i] = r.at<double>(i, j);  // glm [col][row]
    fit.pose.translation[i] = tvec.at<double>(i);
  }
  double sum = 0;
  for (size_t i = 0; i < marks.size(); ++i) {
    const glm::dvec3 pc = fit.pose.toCamera(marks[i].world);
    if (!(pc.z > 0)) {
      throw CalibrationError(
          source, marks[i].name.empty() ? "corners[" + std::to_string(i) + "]" : marks[i].name,
          "behind the fitted camera (the marks do not match the room points)");
    }
    const double e = glm::length(k.project(pc) - marks[i].image);
    fit.residualsPx.push_back(e);
    sum += e * e;
    fit.maxPx = std::max(fit.maxPx, e);
  }
  fit.rmsPx = std::sqrt(sum / double(marks.size()));
  return fit;
}

std::vector<CornerMark> loadCornerMarks(const std::filesystem::path& path) {
  const core::JsonDocument doc(path, core::throwAs<CalibrationError>);
  const core::JsonValue root = doc.root().object({"corners", "comment"});
  std::vector<CornerMark> marks;
  for (const core::JsonValue& c : root["corners"].array()) {
    c.object({"name", "world", "image"});
    CornerMark m;
    m.name = c.stringOr("name", "");
    const std::vector<double> w = c["world"].numbers(3);
    const std::vector<double> im = c["image"].numbers(2);
    m.world = {w[0], w[1], w[2]};
    m.image = {im[0], im[1]};
    marks.push_back(m);
  }
  return marks;
}

}  // namespace penumbra::scene
