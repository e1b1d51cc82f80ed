// The environment camera's lens calibration (envmap/fisheye_calibration.h, `penumbra
// calibrate-fisheye`) on real photographs: OpenCV's chessboard photos (opencv-doc's
// examples/data/left*.jpg, 640 × 480) seen again through a KNOWN fisheye lens. Each fisheye
// view is made by remapping a photo: every output pixel is undistorted through the known
// model (cv::fisheye's θ_d = θ (1 + k1 θ² + … + k4 θ⁸), inverted here by bisection) to a ray,
// the ray turned by the view's tilt into the photo camera's frame, and the photo sampled
// where its own pinhole calibration (scene::calibrateFromChessboards of the same photos)
// projects that ray; at 3 × 3 samples a pixel, averaged (INTER_AREA). Tilting the photo camera
// up to 62° from the fisheye's axis puts the board near the image's rim too, where the
// distortion terms matter. Then the calibration must give the known lens back, and the kiosk
// must take it, or refuse it when it does not see the hemisphere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "envmap/fisheye_calibration.h"
#include "envmap/fisheye_lens_file.h"
#include "kiosk/kiosk_config.h"
#include "tests/scratch_dir.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using envmap::FisheyeLens;

const fs::path kPhotos = "/usr/share/doc/opencv-doc/examples/data";
constexpr double kDeg = std::numbers::pi / 180;

std::vector<fs::path> chessboardPhotos() {
  std::vector<fs::path> photos;
  for (int i = 1; i <= 14; ++i) {
    const fs::path p = kPhotos / ((i < 10 ? "left0" : "left") + std::to_string(i) + ".jpg");
    if (fs::exists(p)) photos.push_back(p);
  }
  return photos;
}

double distortedAngle(const FisheyeLens& l, double t) {
  const double t2 = t * t;
  return t * (1 + t2 * (l.k[0] + t2 * (l.k[1] + t2 * (l.k[2] + t2 * l.k[3]))));
}

// The unit ray of image point (x, y) (FisheyeLens's convention: the image's corner at 0) by
// the model, or a zero vector beyond θ = 90°.
cv::Vec3d ray(const FisheyeLens& l, double x, double y) {
  const double a = (x - l.cx) / l.fx, b = (y - l.cy) / l.fy;
  const double d = std::hypot(a, b);
  if (d == 0) return {0, 0, 1};
  if (d > distortedAngle(l, std::numbers::pi / 2)) return {0, 0, 0};
  // Newton's method from θ = θ_d: θ_d increases on [0, π/2] for these lenses, and 12 steps
  // reach the double's precision.
  double t = std::min(d, std::numbers::pi / 2);
  for (int i = 0; i < 12; ++i) {
    const double t2 = t * t;
    const double slope =
        1 + t2 * (3 * l.k[0] + t2 * (5 * l.k[1] + t2 * (7 * l.k[2] + t2 * 9 * l.k[3])));
    t = std::clamp(t - (distortedAngle(l, t) - d) / slope, 0.0, std::numbers::pi / 2);
  }
  const double s = std::sin(t) / d;
  return {a * s, b * s, std::cos(t)};
}

// The photo camera's own calibration (pinhole + radial/tangential distortion).
struct PhotoCamera {
  cv::Matx33d k;
  cv::Mat dist;
  double xMin = 0, xMax = 0, yMin = 0, yMax = 0;  // the photo's extent in normalised coordinates
};

PhotoCamera photoCamera(const std::vector<fs::path>& photos) {
  const scene::ChessboardCalibration c = scene::calibrateFromChessboards(photos, {9, 6});
  const scene::Intrinsics& i = c.intrinsics;
  PhotoCamera p;
  p.k = {i.fx, 0, i.cx, 0, i.fy, i.cy, 0, 0, 1};
  p.dist = (cv::Mat_<double>(1, 5) << i.k1, i.k2, i.p1, i.p2, i.k3);
  // The border's pixels undistorted: beyond them a ray is not in the photo (and the distortion
  // polynomial, far outside, would fold back into it).
  std::vector<cv::Point2d> border, normal;
  for (int x = 0; x <= i.width; x += 16) {
    border.emplace_back(x, 0);
    border.emplace_back(x, i.height - 1);
  }
  for (int y = 0; y <= i.height; y += 16) {
    border.emplace_back(0, y);
    border.emplace_back(i.width - 1, y);
  }
  cv::undistortPoints(border, normal, p.k, p.dist);
  p.xMin = p.yMin = 1e9;
  p.xMax = p.yMax = -1e9;
  for (const cv::Point2d& n : normal) {
    p.xMin = std::min(p.xMin, n.x);
    p.xMax = std::max(p.xMax, n.x);
    p.yMin = std::min(p.yMin, n.y);
    p.yMax = std::max(p.yMax, n.y);
  }
  return p;
}

// `photo` seen through `lens` with the photo camera tilted by `tilt` towards azimuth `azimuth`.
cv::Mat fisheyeView(const cv::Mat& photo, const PhotoCamera& cam, const FisheyeLens& lens,
                    double tilt, double azimuth) {
  constexpr int kSuper = 3;
  const int w = int(lens.width) * kSuper, h = int(lens.height) * kSuper;
  cv::Matx33d turn;
  cv::Rodrigues(cv::Vec3d(-std::sin(azimuth) * tilt, std::cos(azimuth) * tilt, 0), turn);
  std::vector<cv::Point3d> rays;
  std::vector<int> where;
  rays.reserve(size_t(w) * size_t(h));
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const cv::Vec3d d = ray(lens, (u + 0.5) / kSuper, (v + 0.5) / kSuper);
      const cv::Vec3d p = turn * d;
      if (!(p[2] > 0.05)) continue;
      const double x = p[0] / p[2], y = p[1] / p[2];
      const double mx = 0.05 * (cam.xMax - cam.xMin), my = 0.05 * (cam.yMax - cam.yMin);
      if (x < cam.xMin - mx || x > cam.xMax + mx || y < cam.yMin - my || y > cam.yMax + my)
        continue;
      rays.emplace_back(x, y, 1.0);
      where.push_back(v * w + u);
    }
  }
  std::vector<cv::Point2d> image;
  cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cam.k, cam.dist, image);
  cv::Mat mapX(h, w, CV_32F, cv::Scalar(-1000)), mapY(h, w, CV_32F, cv::Scalar(-1000));
  for (size_t i = 0; i < image.size(); ++i) {
    mapX.at<float>(where[i]) = float(image[i].x);
    mapY.at<float>(where[i]) = float(image[i].y);
  }
  cv::Mat big, out;
  cv::remap(photo, big, mapX, mapY, cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(128));
  cv::resize(big, out, cv::Size(int(lens.width), int(lens.height)), 0, 0, cv::INTER_AREA);
  return out;
}

// The views of every photo through `lens` (photo i tilted by kTilts[i % 4] towards the golden
// angle times i), written as PNGs into `dir`; `lensOf(i)` may give some views another lens.
template <class LensOf>
std::vector<fs::path> writeViews(const fs::path& dir, LensOf lensOf) {
  static constexpr double kTilts[] = {0, 35, 62, 50};
  const std::vector<fs::path> photos = chessboardPhotos();
  const PhotoCamera cam = photoCamera(photos);
  std::vector<fs::path> views;
  for (size_t i = 0; i < photos.size(); ++i) {
    const cv::Mat photo = cv::imread(photos[i].string(), cv::IMREAD_GRAYSCALE);
    const cv::Mat view =
        fisheyeView(photo, cam, lensOf(i), kTilts[i % 4] * kDeg, double(i) * 137.5 * kDeg);
    const fs::path p = dir / ("fisheye_" + photos[i].stem().string() + ".png");
    EXPECT_TRUE(cv::imwrite(p.string(), view));
    views.push_back(p);
  }
  return views;
}

// The largest angle between the rays of `a` and `b` over `a`'s image circle (θ ≤ 90°, inside
// the image), every 4th pixel.
double maxDirectionErrorDeg(const FisheyeLens& a, const FisheyeLens& b) {
  double worst = 0;
  for (uint32_t y = 2; y < a.height; y += 4) {
    for (uint32_t x = 2; x < a.width; x += 4) {
      const cv::Vec3d da = ray(a, x + 0.5, y + 0.5), db = ray(b, x + 0.5, y + 0.5);
      if (cv::norm(da) == 0 || cv::norm(db) == 0) continue;
      worst = std::max(worst, std::acos(std::min(1.0, da.dot(db))) / kDeg);
    }
  }
  return worst;
}

int run(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

class FisheyeCalibrationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (chessboardPhotos().size() < 13)
      GTEST_SKIP() << "opencv-doc's left*.jpg not installed (.ci/install-deps.sh installs them)";
    dir_ = test::scratchPath("fisheye-calibration");
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    if (!dir_.empty()) fs::remove_all(dir_);
  }
  // `penumbra calibrate-fisheye VIEWS --board 9x6 --square 0.025 -o OUT`: its exit status;
  // stdout and stderr in dir_/out.txt, dir_/err.txt.
  int calibrateCli(const std::vector<fs::path>& views, const fs::path& out) {
    std::string command = std::string("'") + PENUMBRA_CLI + "' calibrate-fisheye";
    for (const fs::path& v : views) command += " '" + v.string() + "'";
    command += " --board 9x6 --square 0.025 -o '" + out.string() + "' > '" +
               (dir_ / "out.txt").string() + "' 2> '" + (dir_ / "err.txt").string() + "'";
    return run(command);
  }
  std::string text(const std::string& name) {
    std::ifstream in(dir_ / name);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }
  // A kiosk configuration whose environment camera has `lens`; the refusal, or "accepted".
  std::string kioskVerdict(const std::string& lens, double* reach = nullptr) {
    const fs::path config = dir_ / "kiosk.json";
    std::ofstream(config) << R"({"bundle": "b", "environment": {"device": "/dev/video2",
        "width": 480, "height": 480, "lens": ")"
                          << lens << R"("}})";
    try {
      const kiosk::KioskConfig c = kiosk::loadKioskConfig(config);
      if (reach) *reach = c.environment->lensReach;
    } catch (const kiosk::ConfigError& e) {
      return e.what();
    }
    return "accepted";
  }
  fs::path dir_;
};

// A known lens: equidistant at f = 146 (a 480-pixel image sees 94° from the axis at k = 0)
// with small distortion terms.
const FisheyeLens kLens146{480, 480, 146, 146, 240, 240, {0.015, -0.004, 0.0006, -0.00005}};

TEST_F(FisheyeCalibrationTest, RecoversAKnownLensFromRealPhotos) {
  const std::vector<fs::path> views = writeViews(dir_, [](size_t) { return kLens146; });
  const envmap::FisheyeCalibration c = envmap::calibrateFisheye(views, {9, 6}, 0.025);
  const FisheyeLens& l = c.lens.lens;
  const double direction = maxDirectionErrorDeg(kLens146, l);
  const double knownReach = envmap::nearestEdgeReach(kLens146);
  std::printf(
      "recovered: %lld of %zu views, rms %.4f px, fx %.3f fy %.3f cx %.3f cy %.3f k %.5f %.5f "
      "%.5f %.6f, reach %.3f deg (known %.3f), max direction error %.3f deg\n",
      static_cast<long long>(c.lens.views), views.size(), c.lens.rmsPx, l.fx, l.fy, l.cx, l.cy,
      l.k[0], l.k[1], l.k[2], l.k[3], c.reach / kDeg, knownReach / kDeg, direction);
  EXPECT_EQ(c.lens.views, int64_t(views.size()));
  EXPECT_LT(c.lens.rmsPx, 0.3);  // measured 0.18 px
  // The recovered lens sends every pixel of the image circle within 0.8° of the known lens's
  // direction (measured 0.58°, at the rim). Focal length and k trade against each other over
  // the angles the boards cover, so they are checked loosely one by one and tightly together:
  // the ideal equidistant180 lens (f 152.8) is 1.2° off at r = 200 px, f = 149 is 2°.
  EXPECT_NEAR(l.fx, 146, 1.5);  // measured 146.57
  EXPECT_NEAR(l.fy, 146, 1.5);
  EXPECT_NEAR(l.cx, 240, 2.0);  // measured 240.03 and 238.72
  EXPECT_NEAR(l.cy, 240, 2.0);
  EXPECT_LT(direction, 0.8);
  EXPECT_NEAR(c.reach / kDeg, knownReach / kDeg, 1.0);  // measured 92.03 of 92.32
  EXPECT_TRUE(envmap::reachesHemisphere(c.reach));

  // The command gives the same lens, as a file the kiosk takes.
  ASSERT_EQ(calibrateCli(views, dir_ / "lens.json"), 0) << text("err.txt");
  const envmap::FisheyeLensFile f =
      envmap::readFisheyeLensFile(dir_ / "lens.json", core::throwAs<core::Error>);
  EXPECT_EQ(f.lens.fx, l.fx);
  EXPECT_EQ(f.lens.cy, l.cy);
  EXPECT_EQ(f.lens.k, l.k);
  EXPECT_EQ(f.rmsPx, c.lens.rmsPx);
  EXPECT_EQ(f.board, "9x6");
  EXPECT_NE(text("out.txt").find("reach_deg "), std::string::npos);
  double reach = 0;
  EXPECT_EQ(kioskVerdict("lens.json", &reach), "accepted");
  EXPECT_EQ(reach, c.reach);
}

TEST_F(FisheyeCalibrationTest, ANarrowLensIsRecoveredAndRefusedByTheKiosk) {
  // f = 165 on 480 pixels: the nearest edge is 240 / 165 rad = 83.3° from the axis.
  const FisheyeLens narrow{480, 480, 165, 165, 240, 240, {}};
  const std::vector<fs::path> views = writeViews(dir_, [&](size_t) { return narrow; });
  ASSERT_EQ(calibrateCli(views, dir_ / "narrow.json"), 0) << text("err.txt");
  EXPECT_NE(text("err.txt").find("penumbra-kiosk will refuse it"), std::string::npos)
      << text("err.txt");
  const envmap::FisheyeLensFile f =
      envmap::readFisheyeLensFile(dir_ / "narrow.json", core::throwAs<core::Error>);
  const double reach = envmap::nearestEdgeReach(f.lens) / kDeg;
  std::printf("narrow: %lld views, rms %.4f px, fx %.3f fy %.3f, reach %.3f deg (known %.3f)\n",
              static_cast<long long>(f.views), f.rmsPx, f.lens.fx, f.lens.fy, reach,
              240.0 / 165 / kDeg);
  EXPECT_GE(f.views, 10);                       // measured 12 of 13: one board leaves the image
  EXPECT_NEAR(f.lens.fx, 165, 2.0);             // measured 166.04
  EXPECT_NEAR(reach, 240.0 / 165 / kDeg, 1.0);  // measured 83.06 of 83.34
  EXPECT_LT(reach, 90);
  const std::string verdict = kioskVerdict("narrow.json");
  EXPECT_NE(verdict.find("environment.lens: " + (dir_ / "narrow.json").string() + " sees 8"),
            std::string::npos)
      << verdict;
  EXPECT_NE(verdict.find("deg from its axis towards the nearest image edge: the hemisphere map "
                         "needs 90 deg"),
            std::string::npos)
      << verdict;
}

TEST_F(FisheyeCalibrationTest, AFitOfTwoLensesIsRefused) {
  // Every other photo through a rectilinear lens (a pinhole: r = f tan θ, whose series
  // θ + θ³/3 + 2θ⁵/15 + 17θ⁷/315 + 62θ⁹/2835 is cv::fisheye's model with these k) centred 40 px
  // away: no one lens gives both, and the fit must say so instead of writing one.
  const FisheyeLens other{
      480, 480, 146, 146, 280, 220, {1.0 / 3, 2.0 / 15, 17.0 / 315, 62.0 / 2835}};
  const std::vector<fs::path> views =
      writeViews(dir_, [&](size_t i) { return i % 2 ? other : kLens146; });
  try {
    envmap::calibrateFisheye(views, {9, 6}, 0.025);
    ADD_FAILURE() << "a fit over two lenses was accepted";
  } catch (const envmap::FisheyeError& e) {
    std::printf("two lenses: %s\n", e.what());
    // Measured: Levenberg–Marquardt ends at rms 175.7 px with negative focal lengths.
    EXPECT_NE(std::string(e.what()).find("fisheye calibration: OpenCV's fit did not converge"),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(calibrateCli(views, dir_ / "mixed.json"), 1);
  EXPECT_FALSE(fs::exists(dir_ / "mixed.json"));
  EXPECT_NE(text("err.txt").find("penumbra: error: fisheye calibration: "), std::string::npos)
      << text("err.txt");
}

TEST_F(FisheyeCalibrationTest, AFitOverFivePixelsIsRefused) {
  // The corners of the f = 146 views as found, then each moved 6 px along x and y, one way on
  // the board's white-diagonal corners and the other way on the rest: detections that no lens
  // and pose explain (a mislabelled or smeared set), which Levenberg–Marquardt still fits to
  // finite, positive focal lengths.
  const std::vector<fs::path> views = writeViews(dir_, [](size_t) { return kLens146; });
  const scene::ChessboardViews found =
      scene::findChessboards(views, {9, 6}, {scene::CornerSearch::Detector::kSectorBased});
  EXPECT_LT(envmap::fitFisheyeLens(found, {9, 6}, 0.025).lens.rmsPx, 0.3);  // as found: 0.18
  scene::ChessboardViews moved = found;
  for (std::vector<glm::dvec2>& view : moved.corners) {
    for (size_t i = 0; i < view.size(); ++i) {
      const double s = (i % 9 + i / 9) % 2 ? 6.0 : -6.0;
      view[i] += glm::dvec2(s, s);
    }
  }
  try {
    const envmap::FisheyeCalibration c = envmap::fitFisheyeLens(moved, {9, 6}, 0.025);
    ADD_FAILURE() << "accepted corners 6 px off, rms " << c.lens.rmsPx;
  } catch (const envmap::FisheyeError& e) {
    std::printf("moved corners: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("px, more than 5 px: not a calibration of this lens"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("the worst photo is fisheye_left"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace penumbra
