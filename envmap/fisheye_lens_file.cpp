#include "envmap/fisheye_lens_file.h"

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/json_reader.h"
#include "core/replace_file.h"

namespace penumbra::envmap {

namespace {

using core::JsonValue;

// θ_d(θ) of cv::fisheye (OpenCV's fisheye module documentation), in Horner form.
double distortedAngle(const FisheyeLens& lens, double theta) {
  const double t2 = theta * theta;
  return theta * (1 + t2 * (lens.k[0] + t2 * (lens.k[1] + t2 * (lens.k[2] + t2 * lens.k[3]))));
}

// A value that must be a number > 0 and at most `hi`.
double positive(const JsonValue& v, double hi) {
  const double x = v.number();
  if (!(x > 0)) v.fail(core::formatNumber(x) + ": must be positive");
  if (!(x <= hi)) v.fail(core::formatNumber(x) + " is over " + core::formatNumber(hi));
  return x;
}

}  // namespace

FisheyeLensFile readFisheyeLensFile(const std::filesystem::path& path, core::ErrorThrower raise) {
  const core::JsonDocument doc(path, raise);
  const JsonValue j = doc.root().object({"format", "version", "image_size", "fx", "fy", "cx", "cy",
                                         "k", "rms_px", "views", "board", "square"});
  core::requireFileFormat(j, kFisheyeLensFormat, kFisheyeLensVersion);
  FisheyeLensFile f;
  const std::vector<JsonValue> size = j["image_size"].array(2, 2);
  f.lens.width = static_cast<uint32_t>(size[0].integer(2, kMostFisheyeImageSide));
  f.lens.height = static_cast<uint32_t>(size[1].integer(2, kMostFisheyeImageSide));
  // 1e6 px: far beyond any lens on a 4096-pixel sensor, and keeps f·θ_d finite in any product.
  f.lens.fx = positive(j["fx"], 1e6);
  f.lens.fy = positive(j["fy"], 1e6);
  // The principal point inside the image (its edges excluded): a centre outside leaves the
  // optical axis, the map's zenith, unseen.
  const auto inside = [](const JsonValue& v, uint32_t side, const char* axis) {
    const double x = v.number();
    if (!(x > 0 && x < side)) {
      v.fail(core::formatNumber(x) + " is outside the image (0 < " + axis + " < " +
             std::to_string(side) + ")");
    }
    return x;
  };
  f.lens.cx = inside(j["cx"], f.lens.width, "cx");
  f.lens.cy = inside(j["cy"], f.lens.height, "cy");
  const std::vector<JsonValue> k = j["k"].array(4, 4);
  for (size_t i = 0; i < 4; ++i) f.lens.k[i] = k[i].number(-100, 100);
  f.rmsPx = j["rms_px"].number(0, kMostFisheyeRmsPx);
  f.views = j["views"].integer(3, 100000);
  if (const auto b = j.find("board")) f.board = b->nonEmptyString();
  if (const auto s = j.find("square")) f.square = positive(*s, 1e6);
  return f;
}

std::string fisheyeLensJson(const FisheyeLensFile& f) {
  nlohmann::ordered_json j = {{"format", kFisheyeLensFormat},
                              {"version", kFisheyeLensVersion},
                              {"image_size", {f.lens.width, f.lens.height}},
                              {"fx", f.lens.fx},
                              {"fy", f.lens.fy},
                              {"cx", f.lens.cx},
                              {"cy", f.lens.cy},
                              {"k", f.lens.k},
                              {"rms_px", f.rmsPx},
                              {"views", f.views}};
  if (!f.board.empty()) j["board"] = f.board;
  if (f.square > 0) j["square"] = f.square;
  return j.dump(2) + "\n";
}

void writeFisheyeLensFile(const std::filesystem::path& path, const FisheyeLensFile& f) {
  core::writeFileReplacing(path, fisheyeLensJson(f));
}

double nearestEdgeReach(const FisheyeLens& lens) {
  if (!(lens.fx > 0) || !(lens.fy > 0)) return 0;
  const double edge = std::min({lens.cx / lens.fx, (lens.width - lens.cx) / lens.fx,
                                lens.cy / lens.fy, (lens.height - lens.cy) / lens.fy});
  if (!(edge > 0)) return 0;
  // Walk θ up in steps of 1/1024 rad (0.056°) until θ_d passes the edge or folds, then
  // bisect that step: θ_d is a polynomial, smooth between the steps.
  constexpr double kStep = 1.0 / 1024;
  double lo = 0, previous = 0;
  for (int i = 1;; ++i) {
    const double theta = std::min(i * kStep, std::numbers::pi);
    const double d = distortedAngle(lens, theta);
    if (!(d > previous)) return lo;  // folded (or not finite): the reach ends where it turns
    if (d >= edge) break;
    if (theta >= std::numbers::pi) return std::numbers::pi;
    lo = theta;
    previous = d;
  }
  double hi = std::min(lo + kStep, std::numbers::pi);
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (distortedAngle(lens, mid) < edge ? lo : hi) = mid;
  }
  return lo;
}

bool reachesHemisphere(double reach) {
  return reach >= std::numbers::pi / 2 - 1e-9;
}

}  // namespace penumbra::envmap
