// The mask of real things in front of the product (kiosk/foreground_mask.h) on synthetic
// frames: a dark figure over an exposure-drifted room is found whole and nothing else is;
// sensor noise leaves no speckle; the hysteresis holds a pixel between release and
// threshold; applyTo takes the camera's pixels exactly there.
#include "kiosk/foreground_mask.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <utility>
#include <vector>

namespace penumbra::kiosk {
namespace {

constexpr uint32_t kW = 96, kH = 64;

// An empty room: a smooth gradient of mid-grey colours.
std::vector<uint8_t> room() {
  std::vector<uint8_t> img(size_t{kW} * kH * 4);
  for (uint32_t y = 0; y < kH; ++y) {
    for (uint32_t x = 0; x < kW; ++x) {
      uint8_t* p = &img[4 * (size_t{y} * kW + x)];
      p[0] = static_cast<uint8_t>(90 + x);
      p[1] = static_cast<uint8_t>(80 + y + x / 2);
      p[2] = static_cast<uint8_t>(120 + y);
      p[3] = 255;
    }
  }
  return img;
}

// The room at `gainPermille`, with a dark figure over [x0, x1) x [y0, y1) and noise of
// +-`noise` levels.
std::vector<uint8_t> filmed(const std::vector<uint8_t>& empty, int gainPermille, uint32_t x0,
                            uint32_t x1, uint32_t y0, uint32_t y1, int noise, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> jitter(-noise, noise);
  std::vector<uint8_t> img = empty;
  for (uint32_t y = 0; y < kH; ++y) {
    for (uint32_t x = 0; x < kW; ++x) {
      uint8_t* p = &img[4 * (size_t{y} * kW + x)];
      const bool figure = x >= x0 && x < x1 && y >= y0 && y < y1;
      for (int c = 0; c < 3; ++c) {
        const int v = figure ? 30 + 5 * c : p[c] * gainPermille / 1000 + jitter(rng);
        p[c] = static_cast<uint8_t>(std::clamp(v, 0, 255));
      }
    }
  }
  return img;
}

TEST(ForegroundMask, FindsTheFigureWholeUnderDriftAndNoise) {
  const std::vector<uint8_t> empty = room();
  ForegroundMask mask(empty, kW, kH);
  for (int gain : {940, 1000, 1060}) {
    const auto frame = filmed(empty, gain, 30, 50, 10, 60, 6, uint32_t(gain));
    mask.update(frame);
    EXPECT_NEAR(int(mask.gain256()), gain * 256 / 1000, 3) << gain;
    for (uint32_t y = 0; y < kH; ++y) {
      for (uint32_t x = 0; x < kW; ++x) {
        const bool figure = x >= 30 && x < 50 && y >= 10 && y < 60;
        // Grown by 2 pixels around the figure; nothing further away.
        const bool near = x + 2 >= 30 && x < 52 && y + 2 >= 10 && y < 62;
        const uint8_t m = mask.mask()[size_t{y} * kW + x];
        if (figure) {
          EXPECT_EQ(m, 1) << x << "," << y << " gain " << gain;
        }
        if (!near) {
          EXPECT_EQ(m, 0) << x << "," << y << " gain " << gain;
        }
      }
    }
  }
  // applyTo: the camera's pixel where the mask is set, the rendered one elsewhere.
  const auto frame = filmed(empty, 1000, 30, 50, 10, 60, 0, 1);
  mask.update(frame);
  std::vector<uint8_t> rendered(frame.size(), 7);
  mask.applyTo(rendered, frame);
  for (size_t i = 0; i < mask.mask().size(); ++i) {
    for (size_t c = 0; c < 4; ++c) {
      EXPECT_EQ(rendered[4 * i + c], mask.mask()[i] ? frame[4 * i + c] : 7) << i;
    }
  }
}

TEST(ForegroundMask, NoiseAloneLeavesNothingAndTheRoomAloneIsEmpty) {
  const std::vector<uint8_t> empty = room();
  ForegroundMask mask(empty, kW, kH);
  EXPECT_EQ(mask.update(empty), 0u);
  for (uint32_t seed = 1; seed <= 5; ++seed) {
    EXPECT_EQ(mask.update(filmed(empty, 1030, 0, 0, 0, 0, 20, seed)), 0u) << seed;
  }
}

// A pixel whose difference lies between release and threshold stays as it was: a figure
// fading into a matching background does not blink at its edges.
TEST(ForegroundMask, HysteresisHoldsBetweenReleaseAndThreshold) {
  const std::vector<uint8_t> empty = room();
  ForegroundMask mask(empty, kW, kH, {40, 24, 0});
  auto offset = [&](int by) {
    std::vector<uint8_t> img = empty;
    for (uint32_t y = 20; y < 40; ++y) {
      for (uint32_t x = 40; x < 60; ++x) {
        for (int c = 0; c < 3; ++c) {
          uint8_t& v = img[4 * (size_t{y} * kW + x) + size_t(c)];
          v = static_cast<uint8_t>(std::clamp(int(v) - by, 0, 255));
        }
      }
    }
    return img;
  };
  EXPECT_EQ(mask.update(offset(30)), 0u) << "30 levels: under the threshold, off";
  // The 20 x 20 square less its 4 corners, which have 4 of 9 neighbours inside (no growth
  // here to put them back).
  EXPECT_EQ(mask.update(offset(50)), 396u) << "50: on";
  EXPECT_EQ(mask.update(offset(30)), 396u) << "30 again: held";
  EXPECT_EQ(mask.update(offset(20)), 0u) << "20: released";
}

// The header's algorithm written pixel by pixel, as plainly as it reads: the vectorized
// loops of foreground_mask.cpp must give the same mask, bit for bit, frame after frame.
class PlainForegroundMask {
 public:
  PlainForegroundMask(std::vector<uint8_t> empty, ForegroundOptions o)
      : empty_(std::move(empty)), o_(o), last_(size_t{kW} * kH, 0) {}
  std::vector<uint8_t> update(const std::vector<uint8_t>& frame, uint32_t gain256) {
    auto at = [](const std::vector<uint8_t>& plane, int x, int y) -> int {
      return x < 0 || y < 0 || x >= int(kW) || y >= int(kH) ? 0 : plane[size_t(y) * kW + x];
    };
    std::vector<uint8_t> flags(size_t{kW} * kH), filtered(flags.size()), grown(flags.size());
    for (size_t i = 0; i < flags.size(); ++i) {
      int d = 0;
      for (size_t c = 0; c < 3; ++c) {
        const int expected = std::min((empty_[4 * i + c] * int(gain256) + 128) >> 8, 255);
        d = std::max(d, std::abs(frame[4 * i + c] - expected));
      }
      flags[i] = d > (last_[i] ? o_.release : o_.threshold);
    }
    for (int y = 0; y < int(kH); ++y) {
      for (int x = 0; x < int(kW); ++x) {
        int n = 0;
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) n += at(flags, x + dx, y + dy);
        }
        filtered[size_t(y) * kW + x] = n >= 5;
      }
    }
    for (int y = 0; y < int(kH); ++y) {
      for (int x = 0; x < int(kW); ++x) {
        int any = 0;
        for (int dy = -o_.grow; dy <= o_.grow; ++dy) {
          for (int dx = -o_.grow; dx <= o_.grow; ++dx) any |= at(filtered, x + dx, y + dy);
        }
        grown[size_t(y) * kW + x] = static_cast<uint8_t>(any);
      }
    }
    last_ = filtered;
    return grown;
  }

 private:
  std::vector<uint8_t> empty_;
  ForegroundOptions o_;
  std::vector<uint8_t> last_;
};

TEST(ForegroundMask, EqualsThePlainAlgorithmBitForBit) {
  const std::vector<uint8_t> empty = room();
  for (const ForegroundOptions o :
       {ForegroundOptions{}, ForegroundOptions{40, 24, 0}, ForegroundOptions{12, 4, 5}}) {
    ForegroundMask mask(empty, kW, kH, o);
    PlainForegroundMask plain(empty, o);
    // A figure walking through, under drifting exposure and noise strong enough to flicker
    // around the threshold: the hysteresis and the majority filter both decide pixels.
    for (uint32_t f = 0; f < 12; ++f) {
      const auto frame = filmed(empty, 900 + 20 * int(f), 5 + 6 * f, 25 + 6 * f, 8, 50, 14, f);
      const size_t count = mask.update(frame);
      const std::vector<uint8_t> expected = plain.update(frame, mask.gain256());
      ASSERT_EQ(std::vector<uint8_t>(mask.mask().begin(), mask.mask().end()), expected)
          << "options " << o.threshold << "/" << o.release << "/" << o.grow << ", frame " << f;
      size_t ones = 0;
      for (uint8_t m : expected) ones += m;
      EXPECT_EQ(count, ones);
      EXPECT_GT(ones, 0u);
    }
  }
}

TEST(ForegroundMask, RefusesWrongSizesAndOptions) {
  const std::vector<uint8_t> empty = room();
  EXPECT_THROW(ForegroundMask(empty, kW + 1, kH), std::invalid_argument);
  EXPECT_THROW(ForegroundMask(empty, kW, kH, {20, 30, 2}), std::invalid_argument);
  EXPECT_THROW(ForegroundMask(empty, kW, kH, {40, 24, 17}), std::invalid_argument);
  ForegroundMask mask(empty, kW, kH);
  EXPECT_THROW(mask.update(std::vector<uint8_t>(16)), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::kiosk
