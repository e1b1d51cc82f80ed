// Exposure bracketing (kiosk/exposure_control.h) against a sensor model with the
// pipeline delay real sensors have: a control change takes effect `delay` frames after it
// was requested. No camera exists on the build machines, so this is the camera's stand-in;
// the libcamera backend implements the same ControllableCamera interface.
#include "kiosk/exposure_control.h"

#include <gtest/gtest.h>

#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "core/clock.h"
#include "tests/scratch_dir.h"

namespace penumbra::kiosk {
namespace {

class VirtualTimebase final : public Timebase {
 public:
  int64_t nowNanoseconds() override { return clock_.nowNanoseconds(); }
  void sleepUntil(int64_t ns) override {
    if (ns > clock_.nowNanoseconds()) clock_.advance(ns - clock_.nowNanoseconds());
  }

 private:
  core::VirtualClock clock_;
};

// A 30 fps sensor whose grey level is exposure / 100 µs (clipped), applying controls
// `delay` frames late, optionally reporting the applied exposure as metadata.
class DelayedSensor final : public ControllableCamera {
 public:
  DelayedSensor(uint32_t delay, bool metadata) : delay_(delay), metadata_(metadata) {}
  GrabStatus grab(int64_t nowNs, CameraFrame& out) override {
    if (disconnectAfter_ && sequence_ >= disconnectAfter_) return GrabStatus::kDisconnected;
    const uint64_t due = static_cast<uint64_t>(nowNs / 33'333'333);
    if (due <= sequence_) return GrabStatus::kNoFrame;
    sequence_ = due;
    int32_t applied = initial_;
    for (const auto& [from, us] : changes_) {
      if (sequence_ >= from) applied = us;
    }
    out.width = 8, out.height = 2, out.stride = 32, out.format = PixelFormat::kXrgb8888;
    out.sequence = sequence_;
    out.exposureUs = metadata_ ? applied : 0;
    out.data.assign(64, static_cast<uint8_t>(std::min(255, applied / 100)));
    return GrabStatus::kFrame;
  }
  bool reopen(int64_t) override { return false; }
  std::string describe() const override { return "delayed sensor"; }
  void applyControls(const CameraControls& c) override {
    changes_.emplace_back(sequence_ + 1 + delay_, c.exposureUs);
    last_ = c;
  }
  CameraControls last_;
  uint64_t disconnectAfter_ = 0;

 private:
  uint32_t delay_;
  bool metadata_;
  int32_t initial_ = 10'000;
  uint64_t sequence_ = 0;
  std::vector<std::pair<uint64_t, int32_t>> changes_;
};

BracketOptions options(std::vector<int32_t> exposures) {
  BracketOptions o;
  o.exposuresUs = std::move(exposures);
  o.base.exposureUs = 10'000;
  o.base.analogueGain = 2.0f;
  o.width = 8, o.height = 2;
  return o;
}

TEST(ExposureBracket, EachShotIsFilmedWithItsOwnExposure) {
  for (const bool metadata : {true, false}) {
    // Without metadata the settle delay (3) must cover the pipeline delay (2); with it, a
    // longer pipeline (5) is caught by the metadata check.
    DelayedSensor sensor(metadata ? 5 : 2, metadata);
    VirtualTimebase time;
    KioskLog log;
    const auto shots = captureBracket(sensor, time, options({2000, 4000, 8000, 16000}), log);
    ASSERT_EQ(shots.size(), 4u);
    for (size_t i = 0; i < shots.size(); ++i) {
      const int32_t us = 2000 << i;
      EXPECT_EQ(shots[i].askedUs, us);
      EXPECT_EQ(shots[i].appliedUs, us);
      EXPECT_EQ(shots[i].rgba[0], us / 100) << "shot " << i << " has another exposure's pixels";
      if (i > 0) {
        EXPECT_GT(shots[i].sequence, shots[i - 1].sequence);
      }
    }
    EXPECT_EQ(sensor.last_.exposureUs, 10'000) << "the live exposure is restored";
    EXPECT_EQ(sensor.last_.analogueGain, 2.0f);
    EXPECT_TRUE(log.contains("bracket: exposure 16000 us: frame"));
  }
}

TEST(ExposureBracket, CameraFaultsNameTheExposure) {
  VirtualTimebase time;
  KioskLog log;
  DelayedSensor gone(2, true);
  gone.disconnectAfter_ = 6;
  try {
    captureBracket(gone, time, options({2000, 4000}), log);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("exposure 4000 us: camera disconnected"),
              std::string::npos)
        << e.what();
  }
  // Metadata that never reaches the asked exposure (the sensor ignores it): a timeout.
  DelayedSensor stuck(1'000'000, true);
  BracketOptions o = options({2000, 4000});
  o.timeoutNs = 500'000'000;
  try {
    captureBracket(stuck, time, o, log);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("exposure 2000 us: no settled frame within 500 ms"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(captureBracket(stuck, time, options({2000}), log), std::invalid_argument);
  EXPECT_THROW(captureBracket(stuck, time, options({0, 2000}), log), std::invalid_argument);
}

TEST(ExposureBracket, WritesPhotographsAndTheManifestList) {
  DelayedSensor sensor(2, true);
  VirtualTimebase time;
  KioskLog log;
  const auto shots = captureBracket(sensor, time, options(exposureLadder(8000, 3)), log);
  const std::filesystem::path dir = test::scratchPath("bracket");
  writeBracket(shots, 8, 2, dir);
  std::ifstream in(dir / "exposures.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  ASSERT_EQ(j["exposures"].size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(j["exposures"][i]["image"], "bracket-" + std::to_string(i) + ".png");
    EXPECT_DOUBLE_EQ(j["exposures"][i]["seconds"].get<double>(), (4000 << i) * 1e-6);
    std::ifstream png(dir / j["exposures"][i]["image"].get<std::string>(), std::ios::binary);
    char signature[8] = {};
    png.read(signature, 8);
    EXPECT_EQ(std::string(signature + 1, 3), "PNG");
  }
  std::filesystem::remove_all(dir);
}

TEST(ExposureBracket, LadderIsOneStopApartAroundTheCentre) {
  EXPECT_EQ(exposureLadder(8000, 5), (std::vector<int32_t>{2000, 4000, 8000, 16000, 32000}));
  EXPECT_EQ(exposureLadder(8000, 2), (std::vector<int32_t>{4000, 8000}));
  EXPECT_EQ(checkControls(CameraControls{}), "");
  CameraControls c;
  c.redGain = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NE(checkControls(c).find("colour_gains[0] must be in"), std::string::npos);
}

}  // namespace
}  // namespace penumbra::kiosk
