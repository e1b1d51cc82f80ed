// The last good bundle is replaced only by a bundle that has rendered (issue 18): a bundle
// that loads and then crashes the renderer must never become the fallback.
#include "kiosk/bundle_guard.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/scratch_dir.h"

namespace penumbra::kiosk {
namespace {

namespace fs = std::filesystem;

const fs::path kShowroom = fs::path(PENUMBRA_DATA_DIR) / "showroom" / "showroom.bundle";

std::string bytesOf(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class BundleGuard : public ::testing::Test {
 protected:
  void SetUp() override {
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    fs::copy_file(kShowroom, configured_);
    fs::copy_file(kShowroom, lastGood_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // Frames rendered without error.
  void render(GuardedBundle& g, uint32_t frames) {
    for (uint32_t i = 0; i < frames; ++i) noteFrameRendered(g, log_, 0);
  }

  const fs::path dir_ = test::scratchPath("bundle-guard");
  const fs::path configured_ = dir_ / "new.bundle";
  const fs::path lastGood_ = dir_ / "last-good.bundle";
  const fs::path trialMark_ = dir_ / "last-good.bundle.trial";
  KioskLog log_;
};

TEST_F(BundleGuard, ABundleBecomesLastGoodOnlyAfterItHasRendered) {
  std::ofstream(lastGood_, std::ios::binary | std::ios::trunc) << "the previous last good bundle";
  GuardedBundle g = loadBundleKeepingLastGood(configured_, lastGood_, log_, 0);
  EXPECT_FALSE(g.fellBack);
  EXPECT_EQ(g.loadedFrom, configured_);
  EXPECT_TRUE(fs::exists(trialMark_));
  render(g, kFramesBeforeLastGood - 1);
  EXPECT_EQ(bytesOf(lastGood_), "the previous last good bundle") << "replaced before it rendered";
  render(g, 1);
  EXPECT_EQ(bytesOf(lastGood_), bytesOf(configured_));
  EXPECT_FALSE(fs::exists(trialMark_));
  EXPECT_TRUE(log_.contains("kept as the last good bundle"));
  render(g, 100);  // kept once
}

TEST_F(BundleGuard, ABundleThatStoppedTheLastRunFallsBackWithOneLine) {
  {
    GuardedBundle crashed = loadBundleKeepingLastGood(configured_, lastGood_, log_, 0);
    render(crashed, kFramesBeforeLastGood - 1);  // ... and the program died here
  }
  const std::string lastGoodBytes = bytesOf(lastGood_);
  KioskLog log;
  const GuardedBundle g = loadBundleKeepingLastGood(configured_, lastGood_, log, 0);
  EXPECT_TRUE(g.fellBack);
  EXPECT_EQ(g.loadedFrom, lastGood_);
  EXPECT_NE(g.refusal.find("stopped before it had rendered"), std::string::npos) << g.refusal;
  ASSERT_EQ(log.lines().size(), 1u);
  EXPECT_NE(log.lines()[0].text.find("refused " + configured_.string()), std::string::npos)
      << log.lines()[0].text;
  EXPECT_NE(log.lines()[0].text.find("running on the last good bundle " + lastGood_.string()),
            std::string::npos)
      << log.lines()[0].text;
  EXPECT_EQ(bytesOf(lastGood_), lastGoodBytes);
}

TEST_F(BundleGuard, AReplacedBundleIsTriedAfresh) {
  { const GuardedBundle crashed = loadBundleKeepingLastGood(configured_, lastGood_, log_, 0); }
  // The technician copies a fixed bundle over the one that crashed.
  fs::remove(configured_);
  fs::copy_file(kShowroom, configured_);
  fs::last_write_time(configured_, fs::last_write_time(lastGood_) + std::chrono::hours(1));
  const GuardedBundle g = loadBundleKeepingLastGood(configured_, lastGood_, log_, 0);
  EXPECT_FALSE(g.fellBack) << g.refusal;
}

TEST_F(BundleGuard, ABundleThatFailsToLoadFallsBackWithOneLine) {
  std::ofstream(configured_, std::ios::binary | std::ios::trunc) << "not a bundle";
  KioskLog log;
  const GuardedBundle g = loadBundleKeepingLastGood(configured_, lastGood_, log, 0);
  EXPECT_TRUE(g.fellBack);
  ASSERT_EQ(log.lines().size(), 1u);
  EXPECT_NE(log.lines()[0].text.find("bad magic"), std::string::npos) << log.lines()[0].text;
  EXPECT_FALSE(fs::exists(trialMark_));
}

TEST_F(BundleGuard, ADeviceAsTheBundleIsRefusedWithoutReadingIt) {
  KioskLog log;
  const GuardedBundle g = loadBundleKeepingLastGood("/dev/zero", lastGood_, log, 0);
  EXPECT_TRUE(g.fellBack);
  EXPECT_NE(g.refusal.find("/dev/zero: is not a regular file"), std::string::npos) << g.refusal;
}

TEST_F(BundleGuard, TheLastGoodBundleItselfNeedsNoTrial) {
  GuardedBundle g = loadBundleKeepingLastGood(lastGood_, lastGood_, log_, 0);
  EXPECT_FALSE(g.fellBack);
  EXPECT_FALSE(fs::exists(trialMark_));
  render(g, kFramesBeforeLastGood);
  EXPECT_FALSE(g.kept);
}

}  // namespace
}  // namespace penumbra::kiosk
