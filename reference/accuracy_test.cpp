// measureAccuracy on the bundled showroom with the Penumbra stand-in as the reference (no
// ray tracer needed): the stand-in's own settings reproduce it exactly, fewer passes do not,
// the region written out is the one measured, and a reference of another size is refused.
#include "reference/accuracy.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "scene/image_io.h"
#include "tests/scratch_dir.h"
#include "tests/showroom_bundle.h"

namespace penumbra::reference {
namespace {

const shadow::SceneBundle& showroom() {
  return testing::showroomBundle();
}

AccuracyOptions standIn() {
  AccuracyOptions o;
  o.passes = {2, 1000};
  o.frames = 1;
  o.shadowMapSize = 256;
  o.penumbraReference = true;
  o.referenceMapSize = 256;  // the measured pipeline's own map: all passes must match
  o.referencePasses = 1000;
  return o;
}

TEST(Accuracy, AllPassesEqualTheStandInFewerDoNot) {
  const std::filesystem::path dir = test::scratchPath("accuracy");
  std::filesystem::create_directories(dir);
  AccuracyOptions o = standIn();
  o.maskOut = (dir / "mask.png").string();
  o.referenceOut = (dir / "reference.png").string();
  o.framesOut = (dir / "frame.png").string();
  std::vector<int> seen;
  const AccuracyReport r = measureAccuracy(
      showroom(), o, [&](const AccuracyRow& row) { seen.push_back(row.passesAsked); });
  EXPECT_EQ(seen, o.passes);
  ASSERT_EQ(r.rows.size(), 2u);
  EXPECT_EQ(r.reference["kind"], "penumbra");
  EXPECT_EQ(r.width, showroom().view.width);

  const AccuracyRow& few = r.rows[0];
  ASSERT_TRUE(few.comparison.masked.has_value());
  EXPECT_GT(few.comparison.masked->pixels, 0u) << "the product casts a shadow at the start pose";
  EXPECT_GT(few.comparison.masked->meanAbs, 0.0);
  EXPECT_LT(few.comparison.ssim, 1.0);
  EXPECT_LE(few.passes, 2u);
  EXPECT_GT(few.msPerFrame, 0.0);

  const AccuracyRow& all = r.rows[1];
  EXPECT_EQ(all.comparison.frame.maxAbs, 0u);
  EXPECT_EQ(all.comparison.masked->meanAbs, 0.0);
  EXPECT_EQ(all.contact.meanAbs, 0.0);

  // The region written out is the one the errors were measured over.
  const core::Image8 written = loadMask(o.maskOut);
  uint64_t inside = 0;
  for (uint8_t v : written.pixels) inside += v ? 1 : 0;
  EXPECT_EQ(inside, few.comparison.masked->pixels);

  // The frames written out are the ones measured: all passes is the stand-in, byte for byte.
  const core::Image8 reference = loadRgb8(o.referenceOut);
  const auto frameFile = [&](int n) {
    return (dir / ("frame-" + std::to_string(n) + ".png")).string();
  };
  EXPECT_EQ(loadRgb8(frameFile(o.passes[1])).pixels, reference.pixels);
  EXPECT_NE(loadRgb8(frameFile(o.passes[0])).pixels, reference.pixels);

  const nlohmann::json j = toJson("showroom.bundle", o, r);
  EXPECT_EQ(j["results"][1]["psnr"], nullptr) << "identical frames: PSNR is infinite";
  EXPECT_EQ(j["results"][0]["passes_asked"], 2);
  EXPECT_EQ(j["accumulation"], "linear");
  std::filesystem::remove_all(dir);
}

TEST(Accuracy, AReferenceOfAnotherSizeIsRefused) {
  const std::filesystem::path dir = test::scratchPath("accuracy");
  std::filesystem::create_directories(dir);
  AccuracyOptions o = standIn();
  o.referencePath = (dir / "small.png").string();
  scene::writePng(o.referencePath, 4, 4, std::vector<uint8_t>(4 * 4 * 4, 128));
  try {
    measureAccuracy(showroom(), o);
    ADD_FAILURE() << "no error";
  } catch (const MetricsError& e) {
    EXPECT_NE(std::string(e.what()).find("differs from the bundle's"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove_all(dir);
}

// A reference image read with its bounds: bounds of zero width measure what the image does;
// wider ones forgive what lies inside them; bounds that do not hold their own reference, or
// half of a pair, are refused by name.
TEST(Accuracy, AReferenceReadWithItsBounds) {
  const std::filesystem::path dir = test::scratchPath("accuracy-bounds");
  std::filesystem::create_directories(dir);
  AccuracyOptions o = standIn();
  o.passes = {2};
  o.referenceOut = (dir / "reference.png").string();
  o.maskOut = (dir / "mask.png").string();
  const AccuracyReport standInReport = measureAccuracy(showroom(), o);
  EXPECT_FALSE(standInReport.rows[0].beyondBounds) << "the stand-in has no bounds";

  AccuracyOptions read = standIn();
  read.passes = {2};
  read.penumbraReference = false;
  read.referencePath = o.referenceOut;
  read.maskPath = o.maskOut;
  read.referenceLowerPath = read.referenceUpperPath = o.referenceOut;
  const AccuracyReport same = measureAccuracy(showroom(), read);
  ASSERT_TRUE(same.rows[0].beyondBounds);
  EXPECT_EQ(same.rows[0].beyondBounds->meanAbs, same.rows[0].comparison.masked->meanAbs);
  EXPECT_GT(same.rows[0].beyondBounds->meanAbs, 0.0);
  EXPECT_EQ(same.reference["lower"], o.referenceOut);

  // Bounds 0..255 forgive everything.
  const auto writeUniform = [&](const char* name, uint8_t v) {
    const std::string path = (dir / name).string();
    scene::writePng(
        path, showroom().view.width, showroom().view.height,
        std::vector<uint8_t>(size_t(showroom().view.width) * showroom().view.height * 4, v));
    return path;
  };
  read.referenceLowerPath = writeUniform("black.png", 0);
  read.referenceUpperPath = writeUniform("white.png", 255);
  const AccuracyReport open = measureAccuracy(showroom(), read);
  EXPECT_EQ(open.rows[0].beyondBounds->maxAbs, 0u);
  const nlohmann::json j = toJson("showroom.bundle", read, open);
  EXPECT_EQ(j["results"][0]["mean_beyond_bounds_shadow"], 0.0);

  read.referenceUpperPath = read.referenceLowerPath;  // all black: the reference lies above
  try {
    measureAccuracy(showroom(), read);
    ADD_FAILURE() << "no error";
  } catch (const MetricsError& e) {
    EXPECT_NE(std::string(e.what()).find("outside its bounds"), std::string::npos) << e.what();
  }
  read.referenceUpperPath.clear();
  EXPECT_THROW(measureAccuracy(showroom(), read), MetricsError);
  std::filesystem::remove_all(dir);
}

// `--product` / `--pose` (issue 15 item 7): another product at another pose is measured
// there — its own shadow region, its own stand-in — and says so in the JSON; a product the
// bundle lacks is refused.
TEST(Accuracy, AnotherProductAtAnotherPose) {
  AccuracyOptions o = standIn();
  o.passes = {1000};
  const AccuracyReport start = measureAccuracy(showroom(), o);
  o.pose = shadow::ProductPose{2, 2.6f, 2.0f, 90.0f, 0.0f};  // the teapot, rotated
  const AccuracyReport teapot = measureAccuracy(showroom(), o);
  ASSERT_TRUE(teapot.rows[0].comparison.masked.has_value());
  EXPECT_GT(teapot.rows[0].comparison.masked->pixels, 0u);
  EXPECT_NE(teapot.rows[0].comparison.masked->pixels, start.rows[0].comparison.masked->pixels);
  EXPECT_EQ(teapot.rows[0].comparison.masked->meanAbs, 0.0) << "all passes equal the stand-in";
  const nlohmann::json j = toJson("showroom.bundle", o, teapot);
  EXPECT_EQ(j["pose"]["product"], 2);
  EXPECT_EQ(j["pose"]["yaw_deg"], 90.0);
  EXPECT_EQ(toJson("showroom.bundle", standIn(), start)["pose"], nullptr);
  o.pose->product = 3;
  EXPECT_THROW(measureAccuracy(showroom(), o), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::reference
