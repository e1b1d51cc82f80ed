#include "envmap/fisheye_lens_file.h"

#include <cmath>
#include <fstream>
#include <numbers>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "tests/scratch_dir.h"

namespace penumbra::envmap {
namespace {

class LensError : public core::Error {
 public:
  using core::Error::Error;
};

FisheyeLensFile sample() {
  FisheyeLensFile f;
  f.lens = {480, 480, 145.90412345678901, 146.1, 239.7, 240.35, {0.01, -0.003, 1e-4, -2.5e-5}};
  f.rmsPx = 0.0512;
  f.views = 13;
  f.board = "9x6";
  f.square = 0.025;
  return f;
}

class FisheyeLensFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = test::scratchPath("lens");
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  // The error reading `text` as lens.json gives, or "no error".
  std::string errorOf(const std::string& text) {
    const std::filesystem::path p = dir_ / "lens.json";
    std::ofstream(p) << text;
    try {
      readFisheyeLensFile(p, core::throwAs<LensError>);
    } catch (const LensError& e) {
      const std::string m = e.what();
      // Relative to the folder: the messages name the file first.
      return m.rfind(dir_.string() + "/", 0) == 0 ? m.substr(dir_.string().size() + 1) : m;
    }
    return "no error";
  }
  // The sample file with `key` set to `value` (or removed, for a null value).
  std::string with(const std::string& key, const nlohmann::json& value) {
    nlohmann::json j = nlohmann::json::parse(fisheyeLensJson(sample()));
    if (value.is_null()) {
      j.erase(key);
    } else {
      j[key] = value;
    }
    return j.dump();
  }
  std::filesystem::path dir_;
};

TEST_F(FisheyeLensFileTest, RoundTripsBitForBit) {
  const FisheyeLensFile f = sample();
  writeFisheyeLensFile(dir_ / "lens.json", f);
  const FisheyeLensFile g = readFisheyeLensFile(dir_ / "lens.json", core::throwAs<LensError>);
  EXPECT_EQ(g.lens.width, 480u);
  EXPECT_EQ(g.lens.height, 480u);
  EXPECT_EQ(g.lens.fx, f.lens.fx);
  EXPECT_EQ(g.lens.fy, f.lens.fy);
  EXPECT_EQ(g.lens.cx, f.lens.cx);
  EXPECT_EQ(g.lens.cy, f.lens.cy);
  EXPECT_EQ(g.lens.k, f.lens.k);
  EXPECT_EQ(g.rmsPx, f.rmsPx);
  EXPECT_EQ(g.views, 13);
  EXPECT_EQ(g.board, "9x6");
  EXPECT_EQ(g.square, 0.025);
  // The optional fields may be left out.
  FisheyeLensFile bare = sample();
  bare.board.clear();
  bare.square = 0;
  EXPECT_EQ(fisheyeLensJson(bare).find("board"), std::string::npos);
  writeFisheyeLensFile(dir_ / "bare.json", bare);
  EXPECT_EQ(readFisheyeLensFile(dir_ / "bare.json", core::throwAs<LensError>).board, "");
}

TEST_F(FisheyeLensFileTest, EveryBadFieldIsNamed) {
  EXPECT_EQ(errorOf(fisheyeLensJson(sample())), "no error");
  EXPECT_EQ(errorOf("{"),
            "lens.json: line 1: syntax error while parsing object key - unexpected "
            "end of input; expected string literal");
  EXPECT_EQ(
      errorOf(with("format", "penumbra-camera-response")),
      R"(lens.json: format: expected "penumbra-fisheye-lens", got "penumbra-camera-response")");
  EXPECT_EQ(errorOf(with("version", 2)),
            "lens.json: version: 2: written by a newer Penumbra (this one reads "
            "penumbra-fisheye-lens version 1 to 1)");
  EXPECT_EQ(errorOf(with("fx", nullptr)), "lens.json: fx: missing");
  EXPECT_EQ(errorOf(with("focal", 3)), "lens.json: focal: unknown field");
  EXPECT_EQ(errorOf(with("image_size", {480})),
            "lens.json: image_size: expected an array of 2 to 2 elements, got 1");
  EXPECT_EQ(errorOf(with("image_size", {480, 1})),
            "lens.json: image_size[1]: 1 is not in [2, 4096]");
  EXPECT_EQ(errorOf(with("image_size", {480.5, 480})),
            "lens.json: image_size[0]: expected an integer, got 480.5");
  EXPECT_EQ(errorOf(with("fx", 0)), "lens.json: fx: 0: must be positive");
  EXPECT_EQ(errorOf(with("fy", -146)), "lens.json: fy: -146: must be positive");
  EXPECT_EQ(errorOf(with("fx", 2e6)), "lens.json: fx: 2e+06 is over 1e+06");
  EXPECT_EQ(errorOf(with("fx", "146")), "lens.json: fx: expected a number, got a string");
  EXPECT_EQ(errorOf(R"({"fx": 1e400})"),
            "lens.json: fx: expected a number within double's range, got 1e400");
  EXPECT_EQ(errorOf(with("cx", 480)), "lens.json: cx: 480 is outside the image (0 < cx < 480)");
  EXPECT_EQ(errorOf(with("cy", -1)), "lens.json: cy: -1 is outside the image (0 < cy < 480)");
  EXPECT_EQ(errorOf(with("k", {0, 0, 0})),
            "lens.json: k: expected an array of 4 to 4 elements, got 3");
  EXPECT_EQ(errorOf(with("k", {0, 0, 101, 0})), "lens.json: k[2]: 101 is not in [-100, 100]");
  EXPECT_EQ(errorOf(with("rms_px", 5.5)), "lens.json: rms_px: 5.5 is not in [0, 5]");
  EXPECT_EQ(errorOf(with("rms_px", -0.1)), "lens.json: rms_px: -0.1 is not in [0, 5]");
  EXPECT_EQ(errorOf(with("views", 2)), "lens.json: views: 2 is not in [3, 100000]");
  EXPECT_EQ(errorOf(with("board", "")),
            "lens.json: board: expected a non-empty string, got a string");
  EXPECT_EQ(errorOf(with("square", 0)), "lens.json: square: 0: must be positive");
  EXPECT_EQ(errorOf("[]"), "lens.json: expected an object, got an array of 0");
}

TEST(NearestEdgeReach, TheIdealLensReachesTheHorizon) {
  for (uint32_t size : {480u, 481u, 1024u}) {
    const double reach = nearestEdgeReach(FisheyeLens::equidistant180(size));
    EXPECT_NEAR(reach, std::numbers::pi / 2, 1e-12) << size;
    EXPECT_TRUE(reachesHemisphere(reach)) << size;
  }
  // A wide image: the shorter side decides.
  EXPECT_NEAR(nearestEdgeReach(FisheyeLens::equidistant180(640, 480)), std::numbers::pi / 2, 1e-12);
}

TEST(NearestEdgeReach, NearestEdgeAlongTheWorstAxis) {
  // Equidistant (k = 0): θ = the edge distance / f.
  FisheyeLens lens{480, 480, 146, 146, 240, 240, {}};
  EXPECT_NEAR(nearestEdgeReach(lens), 240.0 / 146, 1e-12);  // 94.2°
  lens.cx = 200;                                            // nearer the left edge
  EXPECT_NEAR(nearestEdgeReach(lens), 200.0 / 146, 1e-12);
  lens.cx = 240;
  lens.fy = 170;  // the vertical squeezed less: top and bottom are nearer in angle
  EXPECT_NEAR(nearestEdgeReach(lens), 240.0 / 170, 1e-12);
  EXPECT_FALSE(reachesHemisphere(nearestEdgeReach({480, 480, 165, 165, 240, 240, {}})));  // 83.3°
  // With distortion: f · θ_d(reach) is the edge distance.
  lens = {480, 480, 146, 146, 240, 240, {0.02, -0.01, 0.003, -0.0004}};
  const double t = nearestEdgeReach(lens);
  const double t2 = t * t;
  const double d =
      t * (1 + 0.02 * t2 - 0.01 * t2 * t2 + 0.003 * t2 * t2 * t2 - 0.0004 * t2 * t2 * t2 * t2);
  EXPECT_NEAR(146 * d, 240, 1e-9);
}

TEST(NearestEdgeReach, AFoldingModelEndsWhereItTurns) {
  // θ_d = θ (1 − 0.3 θ²) peaks at θ = 1/√0.9 = 1.054 rad (60.4°), where θ_d = 0.7027: the
  // edge at 240 / 146 = 1.64 is never reached.
  const FisheyeLens lens{480, 480, 146, 146, 240, 240, {-0.3, 0, 0, 0}};
  EXPECT_NEAR(nearestEdgeReach(lens), 1 / std::sqrt(0.9), 1.0 / 1024);
  EXPECT_EQ(nearestEdgeReach({480, 480, 0, 146, 240, 240, {}}), 0);
}

}  // namespace
}  // namespace penumbra::envmap
