#include "apps/calibrate_command.h"

#ifdef PENUMBRA_HAVE_CALIBRATION
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>

#include "scene/calibration_report.h"
#endif
#ifdef PENUMBRA_HAVE_FISHEYE_CALIBRATION
#include <filesystem>
#include <numbers>
#include <vector>

#include "core/cli.h"
#include "core/error.h"
#include "envmap/fisheye_calibration.h"
#endif

namespace penumbra::apps {

#ifdef PENUMBRA_HAVE_CALIBRATION
namespace {

struct CalibrateArgs {
  scene::CalibrationRequest request;
  std::string jsonOut;
};

void printIntrinsics(const scene::Intrinsics& k) {
  std::printf("image_size %d %d\n", k.width, k.height);
  std::printf("fx %.6f\nfy %.6f\ncx %.6f\ncy %.6f\n", k.fx, k.fy, k.cx, k.cy);
  std::printf("k1 %.8f\nk2 %.8f\np1 %.8f\np2 %.8f\nk3 %.8f\n", k.k1, k.k2, k.p1, k.p2, k.k3);
}

void printPose(const char* prefix, const scene::Pose& p) {
  const glm::dvec3 c = p.centre();
  std::printf("%scamera_position %.6f %.6f %.6f\n", prefix, c.x, c.y, c.z);
  for (int r = 0; r < 3; ++r) {
    std::printf("%srotation_row%d %.8f %.8f %.8f\n", prefix, r, p.rotation[0][r], p.rotation[1][r],
                p.rotation[2][r]);
  }
}

int runCalibrate(const CalibrateArgs& a) {
  const scene::CalibrationReport r = scene::calibrateCamera(a.request);
  if (r.chessboard) {
    const scene::ChessboardCalibration& c = *r.chessboard;
    for (const scene::ChessboardImage& im : c.images) {
      if (!im.used) std::cerr << "penumbra: warning: skipped " << im.problem << "\n";
    }
    std::printf("method chessboard\nimages_used %d of %zu\n", c.usedCount(), c.images.size());
    printIntrinsics(r.intrinsics);
    std::printf("reprojection_error_px %.6f\n", c.rmsPx);
  } else {
    const scene::VanishingCalibration& c = *r.vanishing;
    const char* axis[3] = {"x", "y", "z"};
    std::printf("method vanishing\n");
    for (int i = 0; i < 2; ++i) {
      std::printf("vanishing_point_%s %.4f %.4f\n", axis[c.markedAxes[i]], c.vanishingPoints[i].x,
                  c.vanishingPoints[i].y);
    }
    std::printf("derived_axis %s\n", axis[c.derivedAxis]);
    printIntrinsics(r.intrinsics);
    printPose("", c.pose);
    std::printf("reprojection_error_px %.6f\n", c.rmsPx);
  }
  if (r.corners) {
    printPose("corners_", r.corners->pose);
    std::printf("corners_reprojection_error_px %.6f\ncorners_max_error_px %.6f\n", r.corners->rmsPx,
                r.corners->maxPx);
  }
  if (!a.jsonOut.empty()) scene::writeJsonFile(a.jsonOut, r.json);
  return 0;
}

#ifdef PENUMBRA_HAVE_FISHEYE_CALIBRATION
struct CalibrateFisheyeArgs {
  std::vector<std::string> photos;
  std::string board, out;
  double square = 0;
};

int runCalibrateFisheye(const CalibrateFisheyeArgs& a) {
  scene::ChessboardSize board;
  try {
    board = scene::parseChessboardSize(a.board);
  } catch (const core::Error& e) {
    throw cli::UsageError(std::string("--board: ") + e.what());
  }
  // Every named photo must exist (a typo is not a photo without a board), and the output's
  // folder too, before the search for corners.
  for (const std::string& p : a.photos) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(p, ec)) {
      throw core::Error(p, "",
                        std::filesystem::exists(p, ec) ? "not a regular file" : "no such file");
    }
  }
  const std::filesystem::path outDir = std::filesystem::path(a.out).parent_path();
  if (!outDir.empty() && !std::filesystem::is_directory(outDir)) {
    throw core::Error(a.out, "", "no such folder: " + outDir.string());
  }
  const std::vector<std::filesystem::path> photos(a.photos.begin(), a.photos.end());
  const envmap::FisheyeCalibration c = envmap::calibrateFisheye(photos, board, a.square);
  int used = 0;
  for (const scene::ChessboardImage& im : c.images) {
    if (!im.used) std::cerr << "penumbra: warning: skipped " << im.problem << "\n";
    used += im.used ? 1 : 0;
  }
  const envmap::FisheyeLens& l = c.lens.lens;
  const double reachDeg = c.reach * 180 / std::numbers::pi;
  std::printf("method fisheye\nimages_used %d of %zu\n", used, c.images.size());
  std::printf("image_size %u %u\n", l.width, l.height);
  std::printf("fx %.6f\nfy %.6f\ncx %.6f\ncy %.6f\n", l.fx, l.fy, l.cx, l.cy);
  std::printf("k1 %.8f\nk2 %.8f\nk3 %.8f\nk4 %.8f\n", l.k[0], l.k[1], l.k[2], l.k[3]);
  std::printf("reprojection_error_px %.6f\nreach_deg %.3f\n", c.lens.rmsPx, reachDeg);
  if (!envmap::reachesHemisphere(c.reach)) {
    std::cerr << "penumbra: warning: " << a.out << ": the lens sees " << reachDeg
              << " deg from its axis towards the nearest image edge, less than the 90 deg of "
                 "the hemisphere: penumbra-kiosk will refuse it as an environment camera's lens\n";
  }
  envmap::writeFisheyeLensFile(a.out, c.lens);
  return 0;
}

Command addCalibrateFisheyeCommand(CLI::App& app) {
  auto args = std::make_shared<CalibrateFisheyeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate-fisheye",
      "The environment camera's fisheye lens (cv::fisheye) from chessboard photos, as a lens "
      "file for kiosk.json's environment.lens");
  cmd->add_option("PHOTO", args->photos, "chessboard photos taken through the lens")->required();
  cmd->add_option("--board", args->board, "inner corners COLSxROWS, e.g. 9x6")->required();
  cmd->add_option("--square", args->square, "the board's square size (any unit)")
      ->required()
      ->check(cli::NumberRange(1e-6, 1e6));
  cmd->add_option("-o,--output", args->out, "the lens file to write (docs/calibration.md)")
      ->required();
  return Command{cmd, [args] { return runCalibrateFisheye(*args); }};
}
#endif

}  // namespace

std::vector<Command> addCalibrateCommands(CLI::App& app) {
  auto args = std::make_shared<CalibrateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate", "Camera intrinsics (and pose) from chessboard photos or vanishing-point marks");
  cmd->add_option("--chessboard", args->request.chessboard, "inner corners COLSxROWS, e.g. 9x6");
  cmd->add_option("--square", args->request.square, "chessboard square size (unit of the poses)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--vanishing", args->request.vanishing,
                  "vanishing-point marks (docs/calibration.md)");
  cmd->add_option("--corners", args->request.corners,
                  "also fit the pose to marked room corners (docs/calibration.md)");
  cmd->add_option("--json", args->jsonOut, "write the result as JSON");
  cmd->add_option("IMAGE", args->request.images, "chessboard photos");
  std::vector<Command> commands{Command{cmd, [args] { return runCalibrate(*args); }}};
#ifdef PENUMBRA_HAVE_FISHEYE_CALIBRATION
  commands.push_back(addCalibrateFisheyeCommand(app));
#endif
  return commands;
}

#else

std::vector<Command> addCalibrateCommands(CLI::App&) {
  return {};
}

#endif

}  // namespace penumbra::apps
