#include "apps/calibrate_command.h"

#ifdef PENUMBRA_HAVE_CALIBRATION
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "scene/camera_calibration.h"
#include "scene/room_pose.h"
#include "scene/vanishing_points.h"
#endif

namespace penumbra::apps {

#ifdef PENUMBRA_HAVE_CALIBRATION
namespace {

using nlohmann::json;

struct CalibrateArgs {
  std::string chessboard, vanishing, corners, jsonOut;
  double square = 1.0;
  std::vector<std::string> images;
};

void printIntrinsics(const scene::Intrinsics& k) {
  std::printf("image_size %d %d\n", k.width, k.height);
  std::printf("fx %.6f\nfy %.6f\ncx %.6f\ncy %.6f\n", k.fx, k.fy, k.cx, k.cy);
  std::printf("k1 %.8f\nk2 %.8f\np1 %.8f\np2 %.8f\nk3 %.8f\n", k.k1, k.k2, k.p1, k.p2, k.k3);
}

json intrinsicsJson(const scene::Intrinsics& k) {
  return {{"width", k.width}, {"height", k.height}, {"fx", k.fx}, {"fy", k.fy},
          {"cx", k.cx},       {"cy", k.cy},         {"k1", k.k1}, {"k2", k.k2},
          {"p1", k.p1},       {"p2", k.p2},         {"k3", k.k3}};
}

json poseJson(const scene::Pose& p) {
  json rot = json::array();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) rot.push_back(p.rotation[c][r]);  // row-major
  }
  const glm::dvec3 centre = p.centre();
  return {{"rotation_world_to_camera", rot},
          {"translation", {p.translation.x, p.translation.y, p.translation.z}},
          {"camera_position", {centre.x, centre.y, centre.z}}};
}

void printPose(const char* prefix, const scene::Pose& p) {
  const glm::dvec3 c = p.centre();
  std::printf("%scamera_position %.6f %.6f %.6f\n", prefix, c.x, c.y, c.z);
  for (int r = 0; r < 3; ++r) {
    std::printf("%srotation_row%d %.8f %.8f %.8f\n", prefix, r, p.rotation[0][r], p.rotation[1][r],
                p.rotation[2][r]);
  }
}

// Writes through a temporary file so an interrupted run leaves no half-written result.
void writeJson(const std::string& path, const json& doc) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    if (!out) throw std::runtime_error(path + ": cannot write");
    out << doc.dump(2) << "\n";
    if (!out) throw std::runtime_error(path + ": write failed");
  }
  std::filesystem::rename(tmp, path);
}

int runCalibrate(const CalibrateArgs& a) {
  if (a.chessboard.empty() == a.vanishing.empty()) {
    throw std::runtime_error("calibrate: give exactly one of --chessboard or --vanishing");
  }
  json doc;
  scene::Intrinsics k;
  if (!a.chessboard.empty()) {
    if (a.images.empty()) throw std::runtime_error("calibrate --chessboard: no IMAGE given");
    const scene::ChessboardSize board = scene::parseChessboardSize(a.chessboard);
    std::vector<std::filesystem::path> photos(a.images.begin(), a.images.end());
    const scene::ChessboardCalibration c = scene::calibrateFromChessboards(photos, board, a.square);
    for (const scene::ChessboardImage& im : c.images) {
      if (!im.used) std::cerr << "penumbra: warning: skipped " << im.problem << "\n";
    }
    k = c.intrinsics;
    std::printf("method chessboard\nimages_used %d of %zu\n", c.usedCount(), c.images.size());
    printIntrinsics(k);
    std::printf("reprojection_error_px %.6f\n", c.rmsPx);
    json images = json::array();
    for (const scene::ChessboardImage& im : c.images) {
      json j = {{"file", im.file}, {"used", im.used}};
      if (im.used)
        j["reprojection_error_px"] = im.rmsPx;
      else
        j["problem"] = im.problem;
      images.push_back(j);
    }
    doc = {{"method", "chessboard"},
           {"board", a.chessboard},
           {"intrinsics", intrinsicsJson(k)},
           {"reprojection_error_px", c.rmsPx},
           {"images", images}};
  } else {
    const scene::VanishingCalibration c =
        scene::calibrateFromVanishingPoints(scene::loadVanishingMarks(a.vanishing));
    k = c.intrinsics;
    const char* axis[3] = {"x", "y", "z"};
    std::printf("method vanishing\n");
    for (int i = 0; i < 2; ++i) {
      std::printf("vanishing_point_%s %.4f %.4f\n", axis[c.markedAxes[i]], c.vanishingPoints[i].x,
                  c.vanishingPoints[i].y);
    }
    std::printf("derived_axis %s\n", axis[c.derivedAxis]);
    printIntrinsics(k);
    printPose("", c.pose);
    std::printf("reprojection_error_px %.6f\n", c.rmsPx);
    doc = {{"method", "vanishing"},
           {"marks", a.vanishing},
           {"intrinsics", intrinsicsJson(k)},
           {"pose", poseJson(c.pose)},
           {"reprojection_error_px", c.rmsPx}};
  }
  if (!a.corners.empty()) {
    const scene::PoseFit fit = scene::fitPose(k, scene::loadCornerMarks(a.corners),
                                              std::filesystem::path(a.corners).filename().string());
    printPose("corners_", fit.pose);
    std::printf("corners_reprojection_error_px %.6f\ncorners_max_error_px %.6f\n", fit.rmsPx,
                fit.maxPx);
    doc["corners_pose"] = poseJson(fit.pose);
    doc["corners_reprojection_error_px"] = fit.rmsPx;
  }
  if (!a.jsonOut.empty()) writeJson(a.jsonOut, doc);
  return 0;
}

}  // namespace

std::vector<Command> addCalibrateCommands(CLI::App& app) {
  auto args = std::make_shared<CalibrateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate", "Camera intrinsics (and pose) from chessboard photos or vanishing-point marks");
  cmd->add_option("--chessboard", args->chessboard, "inner corners COLSxROWS, e.g. 9x6");
  cmd->add_option("--square", args->square, "chessboard square size (unit of the poses)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--vanishing", args->vanishing, "vanishing-point marks (docs/calibration.md)");
  cmd->add_option("--corners", args->corners,
                  "also fit the pose to marked room corners (docs/calibration.md)");
  cmd->add_option("--json", args->jsonOut, "write the result as JSON");
  cmd->add_option("IMAGE", args->images, "chessboard photos");
  return {Command{cmd, [args] { return runCalibrate(*args); }}};
}

#else

std::vector<Command> addCalibrateCommands(CLI::App&) {
  return {};
}

#endif

}  // namespace penumbra::apps
