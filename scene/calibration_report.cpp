#include "scene/calibration_report.h"

#include <stdexcept>

#include "core/replace_file.h"

namespace penumbra::scene {

using nlohmann::json;

json toJson(const Intrinsics& k) {
  return {{"width", k.width}, {"height", k.height}, {"fx", k.fx}, {"fy", k.fy},
          {"cx", k.cx},       {"cy", k.cy},         {"k1", k.k1}, {"k2", k.k2},
          {"p1", k.p1},       {"p2", k.p2},         {"k3", k.k3}};
}

json toJson(const Pose& p) {
  json rot = json::array();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) rot.push_back(p.rotation[c][r]);  // row-major
  }
  const glm::dvec3 centre = p.centre();
  return {{"rotation_world_to_camera", rot},
          {"translation", {p.translation.x, p.translation.y, p.translation.z}},
          {"camera_position", {centre.x, centre.y, centre.z}}};
}

void writeJsonFile(const std::filesystem::path& path, const json& doc) {
  core::writeFileReplacing(path, doc.dump(2) + "\n");
}

CalibrationReport calibrateCamera(const CalibrationRequest& a) {
  if (a.chessboard.empty() == a.vanishing.empty()) {
    throw std::invalid_argument("calibrate: give exactly one of --chessboard or --vanishing");
  }
  CalibrationReport r;
  if (!a.chessboard.empty()) {
    if (a.images.empty()) throw std::invalid_argument("calibrate --chessboard: no IMAGE given");
    const ChessboardSize board = parseChessboardSize(a.chessboard);
    const std::vector<std::filesystem::path> photos(a.images.begin(), a.images.end());
    const ChessboardCalibration& c =
        r.chessboard.emplace(calibrateFromChessboards(photos, board, a.square));
    r.intrinsics = c.intrinsics;
    json images = json::array();
    for (const ChessboardImage& im : c.images) {
      json j = {{"file", im.file}, {"used", im.used}};
      if (im.used) {
        j["reprojection_error_px"] = im.rmsPx;
      } else {
        j["problem"] = im.problem;
      }
      images.push_back(j);
    }
    r.json = {{"method", "chessboard"},
              {"board", a.chessboard},
              {"intrinsics", toJson(r.intrinsics)},
              {"reprojection_error_px", c.rmsPx},
              {"images", images}};
  } else {
    const VanishingCalibration& c =
        r.vanishing.emplace(calibrateFromVanishingPoints(loadVanishingMarks(a.vanishing)));
    r.intrinsics = c.intrinsics;
    r.json = {{"method", "vanishing"},
              {"marks", a.vanishing},
              {"intrinsics", toJson(r.intrinsics)},
              {"pose", toJson(c.pose)},
              {"reprojection_error_px", c.rmsPx}};
  }
  if (!a.corners.empty()) {
    const PoseFit& fit =
        r.corners.emplace(fitPose(r.intrinsics, loadCornerMarks(a.corners),
                                  std::filesystem::path(a.corners).filename().string()));
    r.json["corners_pose"] = toJson(fit.pose);
    r.json["corners_reprojection_error_px"] = fit.rmsPx;
  }
  return r;
}

}  // namespace penumbra::scene
