// Reading and writing frame traces: round trip, and a clear error for every malformed file.
#include <gtest/gtest.h>
#include <algorithm>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "raster/frame_trace.h"
#include "tests/test_scenes.h"

namespace penumbra {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class TraceFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("penumbra-trace-" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(dir_);
    trace_ = testing::makeTestScene({});
    raster::saveTrace(trace_, dir_ / "scene.json");
    std::ifstream in(dir_ / "scene.json");
    doc_ = json::parse(in);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes `doc` as bad.json beside the good sidecar; returns the loader's error.
  std::string errorFor(const json& doc) {
    std::ofstream(dir_ / "bad.json") << doc.dump();
    try {
      raster::loadTrace(dir_ / "bad.json");
    } catch (const raster::TraceError& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
  raster::FrameTrace trace_;
  json doc_;
};

TEST_F(TraceFiles, RoundTripIsExact) {
  EXPECT_EQ(raster::loadTrace(dir_ / "scene.json"), trace_);
  // cull_back_faces is written only when set, and read back.
  EXPECT_FALSE(doc_["passes"][0].contains("cull_back_faces"));
  raster::FrameTrace culled = trace_;
  culled.frame.passes[1].cullBackFaces = true;
  raster::saveTrace(culled, dir_ / "culled.json");
  EXPECT_EQ(raster::loadTrace(dir_ / "culled.json"), culled);
}

// Area-light penumbrae (spec §7): written only when set, read back to the bit; a scale that
// is negative, not finite or not a number, or a scale on a pass without 2x2 PCF or with a
// map over 512 texels is named.
TEST_F(TraceFiles, AreaPenumbraFieldsRoundTripAndAreValidated) {
  EXPECT_FALSE(doc_["passes"][0].contains("penumbra_scale"));
  raster::FrameTrace soft = trace_;
  soft.frame.passes[1].pcf2x2 = true;
  soft.frame.passes[1].penumbraScale = 37.123456f;
  raster::saveTrace(soft, dir_ / "soft.json");
  EXPECT_EQ(raster::loadTrace(dir_ / "soft.json"), soft);
  auto fieldOf = [&](const raster::FrameTrace& t) {
    try {
      raster::validateTrace(t, "t.json");
    } catch (const raster::TraceError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  raster::FrameTrace bad = soft;
  bad.frame.passes[1].penumbraScale = -1.0f;
  EXPECT_NE(fieldOf(bad).find("passes[1].penumbra_scale"), std::string::npos);
  bad.frame.passes[1].penumbraScale = std::numeric_limits<float>::infinity();
  EXPECT_NE(fieldOf(bad).find("passes[1].penumbra_scale"), std::string::npos);
  bad = soft;
  bad.frame.passes[1].pcf2x2 = false;
  EXPECT_NE(fieldOf(bad).find("needs pcf2x2"), std::string::npos);
  bad = soft;
  bad.frame.passes[1].shadowMapSize = 1024;
  EXPECT_NE(fieldOf(bad).find("at most 512"), std::string::npos);
  json d = doc_;
  d["passes"][0]["penumbra_scale"] = "wide";
  EXPECT_NE(errorFor(d).find("penumbra_scale"), std::string::npos);
}

TEST_F(TraceFiles, MissingFieldsAreNamed) {
  for (const char* field : {"width", "camera_view_proj", "static_mesh", "background", "passes"}) {
    json d = doc_;
    d.erase(field);
    const std::string e = errorFor(d);
    EXPECT_NE(e.find("bad.json"), std::string::npos) << e;
    EXPECT_NE(e.find(field), std::string::npos) << e;
  }
  json d = doc_;
  d["passes"][0].erase("light_view_proj");
  EXPECT_NE(errorFor(d).find("passes[0].light_view_proj"), std::string::npos);
}

TEST_F(TraceFiles, WrongSizesAndIndicesAreNamed) {
  json d = doc_;
  d["width"] = 161;
  EXPECT_NE(errorFor(d).find("background"), std::string::npos);
  d = doc_;
  d["passes"][1]["shadow_map_size"] = 100;
  EXPECT_NE(errorFor(d).find("passes[1].shadow_map_size"), std::string::npos);
  d = doc_;
  d["passes"][0]["occluder"] = 5;
  EXPECT_NE(errorFor(d).find("passes[0].occluder"), std::string::npos);
  d = doc_;
  d["static_mesh"]["indices"]["count"] = d["static_mesh"]["indices"]["count"].get<int>() - 1;
  EXPECT_NE(errorFor(d).find("static_mesh.indices"), std::string::npos);
  d = doc_;
  d["version"] = 3;
  EXPECT_NE(errorFor(d).find("version"), std::string::npos);
  d = doc_;
  d["passes"][0]["receiver_s"]["count"] = 1;
  EXPECT_NE(errorFor(d).find("receiver_s"), std::string::npos);
}

TEST_F(TraceFiles, OutOfRangeIndexIsNamed) {
  raster::FrameTrace bad = trace_;
  bad.frame.occluders[0].indices[4] = 999;
  EXPECT_THROW(raster::validateTrace(bad, "x"), raster::TraceError);
  try {
    raster::validateTrace(bad, "x.json");
  } catch (const raster::TraceError& e) {
    EXPECT_NE(std::string(e.what()).find("occluders[0].indices"), std::string::npos) << e.what();
  }
}

TEST_F(TraceFiles, ObjectReceiversAreValidated) {
  ASSERT_FALSE(trace_.frame.passes[0].objectTriangles.empty());
  raster::FrameTrace bad = trace_;
  bad.frame.passes[0].objectTriangles[0] = 12;  // the box has 12 triangles: 0..11
  EXPECT_THROW(raster::validateTrace(bad, "x"), raster::TraceError);
  // Both ways the validation takes: increasing lists (one comparison each), any other order
  // (a bitmap). The last of an increasing list out of range; a valid list reversed.
  bad = trace_;
  bad.frame.passes[0].objectTriangles.back() = 12;
  EXPECT_THROW(raster::validateTrace(bad, "x"), raster::TraceError);
  raster::FrameTrace reversed = trace_;
  auto& list = reversed.frame.passes[0].objectTriangles;
  ASSERT_GE(list.size(), 2u);
  ASSERT_TRUE(std::is_sorted(list.begin(), list.end()));
  std::reverse(list.begin(), list.end());
  auto& sList = reversed.frame.passes[0].objectS;
  for (size_t i = 0, j = list.size() - 1; i < j; ++i, --j) {
    std::swap_ranges(sList.begin() + std::ptrdiff_t(3 * i),
                     sList.begin() + std::ptrdiff_t(3 * i + 3),
                     sList.begin() + std::ptrdiff_t(3 * j));
  }
  EXPECT_NO_THROW(raster::validateTrace(reversed, "x"));
  bad = trace_;
  bad.frame.passes[1].objectS.pop_back();
  EXPECT_THROW(raster::validateTrace(bad, "x"), raster::TraceError);
  bad = trace_;
  bad.frame.passes[0].objectTriangles[1] = bad.frame.passes[0].objectTriangles[0];
  try {
    raster::validateTrace(bad, "x.json");
    FAIL() << "a triangle listed twice was accepted";
  } catch (const raster::TraceError& e) {
    EXPECT_NE(std::string(e.what()).find("passes[0].object_triangles"), std::string::npos);
  }
}

TEST_F(TraceFiles, TruncatedBufferIsRefused) {
  fs::resize_file(dir_ / "scene.bin", fs::file_size(dir_ / "scene.bin") / 2);
  try {
    raster::loadTrace(dir_ / "scene.json");
    FAIL() << "a truncated buffer was accepted";
  } catch (const raster::TraceError& e) {
    EXPECT_NE(std::string(e.what()).find("runs past the end"), std::string::npos) << e.what();
  }
}

// Views may overlap, so a small sidecar can feed views of any total size: that total has its
// own bound (kMaxSidecarBytes, 1 GiB; here a smaller one, so the test needs no gigabyte).
// Every view moved to offset 0 and the sidecar cut to the largest view: each view fits, the
// sidecar is within the bound, and only the views' sum is not.
TEST_F(TraceFiles, ViewsTogetherAreBoundedEvenWhenTheyOverlap) {
  std::vector<json*> views;
  std::vector<uint64_t> offsets;
  const auto collect = [&](auto&& self, json& j) -> void {
    if (j.is_object() && j.contains("offset") && j.contains("count")) {
      views.push_back(&j);
      offsets.push_back(j["offset"].get<uint64_t>());
      return;
    }
    if (j.is_object() || j.is_array()) {
      for (json& child : j) self(self, child);
    }
  };
  json d = doc_;
  collect(collect, d);
  ASSERT_GT(views.size(), 3u);
  // The saver lays views out one after another: a view's bytes are at most the gap to the
  // next offset.
  const uint64_t blob = fs::file_size(dir_ / "scene.bin");
  std::vector<uint64_t> sorted = offsets;
  std::sort(sorted.begin(), sorted.end());
  uint64_t largest = blob - sorted.back();
  for (size_t i = 0; i + 1 < sorted.size(); ++i) {
    largest = std::max(largest, sorted[i + 1] - sorted[i]);
  }
  ASSERT_LT(largest, blob);
  for (json* view : views) (*view)["offset"] = 0;
  d["buffer"] = "overlap.bin";
  fs::copy_file(dir_ / "scene.bin", dir_ / "overlap.bin");
  fs::resize_file(dir_ / "overlap.bin", largest);
  std::ofstream(dir_ / "overlap.json") << d.dump();
  try {
    raster::loadTrace(dir_ / "overlap.json", largest);
    FAIL() << "views of " << blob << " bytes in all were read from a " << largest
           << "-byte sidecar under a " << largest << "-byte bound";
  } catch (const raster::TraceError& e) {
    EXPECT_NE(std::string(e.what()).find("the views read so far copy"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("more than the " + std::to_string(largest)),
              std::string::npos)
        << e.what();
  }
  // Under the real bound the same file loads as far as the views go (its contents are then
  // refused by validation, or not: only the size bound matters here).
  try {
    raster::loadTrace(dir_ / "overlap.json");
  } catch (const raster::TraceError& e) {
    EXPECT_EQ(std::string(e.what()).find("the views read so far copy"), std::string::npos)
        << e.what();
  }
}

TEST_F(TraceFiles, NonFiniteNumbersAreRefused) {
  raster::FrameTrace bad = trace_;
  bad.view.staticMesh.positions[3].y = std::numeric_limits<float>::infinity();
  EXPECT_THROW(raster::validateTrace(bad, "x"), raster::TraceError);
  bad = trace_;
  bad.frame.passes[2].lightViewProj.m[5] = std::nanf("");
  EXPECT_THROW(raster::validateTrace(bad, "x"), raster::TraceError);
}

// `accumulation` (spec §8): absent means "u8", "fixed8_8" round-trips, anything else is named.
TEST_F(TraceFiles, AccumulationIsOptionalAndChecked) {
  json d = doc_;
  d.erase("accumulation");
  std::ofstream(dir_ / "old.json") << d.dump();
  EXPECT_EQ(raster::loadTrace(dir_ / "old.json").frame.accumulation, raster::Accumulation::kU8);
  raster::FrameTrace fixed = trace_;
  fixed.frame.accumulation = raster::Accumulation::kFixed8_8;
  raster::saveTrace(fixed, dir_ / "fixed.json");
  EXPECT_EQ(raster::loadTrace(dir_ / "fixed.json"), fixed);
  // Linear accumulation carries its shade table; without one (or with one elsewhere) the
  // frame is refused, naming the field.
  raster::FrameTrace linear = trace_;
  linear.frame.accumulation = raster::Accumulation::kLinear;
  linear.frame.shadeTable.resize(raster::kShadeCodes * raster::kShadeSteps);
  for (size_t i = 0; i < linear.frame.shadeTable.size(); ++i) {
    linear.frame.shadeTable[i] = static_cast<uint8_t>(i * 7);
  }
  raster::saveTrace(linear, dir_ / "linear.json");
  EXPECT_EQ(raster::loadTrace(dir_ / "linear.json"), linear);
  raster::FrameTrace noTable = linear;
  noTable.frame.shadeTable.pop_back();
  try {
    raster::validateTrace(noTable, "short.json");
    ADD_FAILURE() << "a short shade table must be refused";
  } catch (const raster::TraceError& e) {
    EXPECT_NE(std::string(e.what()).find("short.json: shade_table"), std::string::npos) << e.what();
  }
  raster::FrameTrace stray = trace_;
  stray.frame.shadeTable.resize(3);
  EXPECT_THROW(raster::validateTrace(stray, "stray.json"), raster::TraceError);
  for (const json& value : {json("u16"), json(1), json("FIXED8_8"), json("wide")}) {
    d["accumulation"] = value;
    const std::string e = errorFor(d);
    EXPECT_NE(e.find("bad.json: accumulation"), std::string::npos) << e;
  }
}

// S in 8.8 levels (spec §5): a trace whose S are all whole levels is written as version 1
// (3 bytes per S, as before), one with fractions as version 2 (3 x u16); both read back
// exactly, and a version-2 value above 255 levels is named.
TEST_F(TraceFiles, FineTransfersRoundTripAsVersion2) {
  EXPECT_EQ(doc_["version"], 1);
  raster::FrameTrace fine = trace_;
  fine.frame.passes[1].receiverS[4].g = 0x1234;
  fine.frame.passes[2].objectS[0].r = core::kMaxFineLevel;
  raster::saveTrace(fine, dir_ / "fine.json");
  std::ifstream in(dir_ / "fine.json");
  json d = json::parse(in);
  EXPECT_EQ(d["version"], 2);
  EXPECT_EQ(raster::loadTrace(dir_ / "fine.json"), fine);
  // The sidecar of fine.json is fine.bin: point bad.json at it, and corrupt one S there.
  d["buffer"] = "fine.bin";
  const size_t offset = d["passes"][1]["receiver_s"]["offset"].get<size_t>() + 2;
  std::fstream bin(dir_ / "fine.bin", std::ios::in | std::ios::out | std::ios::binary);
  bin.seekp(static_cast<std::streamoff>(offset));
  const char above[2] = {char(0x01), char(0xFF)};  // 0xFF01 = 65281
  bin.write(above, 2);
  bin.close();
  const std::string e = errorFor(d);
  EXPECT_NE(e.find("bad.json: passes[1].receiver_s"), std::string::npos) << e;
  EXPECT_NE(e.find("65281"), std::string::npos) << e;
}

TEST_F(TraceFiles, NotJsonAndMissingFilesAreRefused) {
  std::ofstream(dir_ / "garbage.json") << "{ this is not json";
  EXPECT_THROW(raster::loadTrace(dir_ / "garbage.json"), raster::TraceError);
  EXPECT_THROW(raster::loadTrace(dir_ / "absent.json"), raster::TraceError);
  json d = doc_;
  d["buffer"] = "absent.bin";
  EXPECT_NE(errorFor(d).find("buffer"), std::string::npos);
}

// docs/input-limits.md, "Frame traces": each kind of bad value gets `file: field: what was
// expected` (issue 18: these came out as nlohmann's or libstdc++'s messages, or without
// the file).
TEST_F(TraceFiles, WrongTypesAreNamedWithTheValue) {
  json d = doc_;
  d["format"] = 7;
  EXPECT_EQ(errorFor(d), (dir_ / "bad.json").string() + ": format: expected a string, got 7");
  d = doc_;
  d["passes"][1]["pcf2x2"] = "yes";
  EXPECT_EQ(errorFor(d), (dir_ / "bad.json").string() +
                             ": passes[1].pcf2x2: expected true or false, got a string");
}

TEST_F(TraceFiles, NumbersBeyondDoubleAreNamedByField) {
  json d = doc_;
  d["passes"][0]["depth_bias"] = 0.125;
  std::string text = d.dump();
  text.replace(text.find("0.125"), 5, "1e400");
  std::ofstream(dir_ / "bad.json") << text;
  try {
    raster::loadTrace(dir_ / "bad.json");
    FAIL() << "1e400 was accepted";
  } catch (const raster::TraceError& e) {
    EXPECT_EQ(std::string(e.what()),
              (dir_ / "bad.json").string() +
                  ": passes[0].depth_bias: expected a number within double's range, got 1e400");
  }
}

TEST_F(TraceFiles, TooManyPassesAreRefusedBeforeTheyAreRead) {
  json d = doc_;
  while (d["passes"].size() <= raster::kMaxPasses) d["passes"].push_back(d["passes"][0]);
  EXPECT_EQ(errorFor(d), (dir_ / "bad.json").string() +
                             ": passes: expected an array of 0 to 257 elements, got 258");
}

TEST_F(TraceFiles, ASingularCameraIsNamedWithTheFile) {
  json d = doc_;
  d["camera_view_proj"] = json::array();
  for (int i = 0; i < 16; ++i) d["camera_view_proj"].push_back(0.0);
  EXPECT_EQ(errorFor(d), (dir_ / "bad.json").string() + ": camera_view_proj: matrix is singular");
}

// The trace and its sidecar must be regular files within their limits: a directory used to
// give "basic_filebuf::underflow", /dev/zero was read until memory ran out.
TEST_F(TraceFiles, PathsToDirectoriesAndDevicesAreRefused) {
  try {
    raster::loadTrace(dir_);
    FAIL() << "a directory was read as a trace";
  } catch (const raster::TraceError& e) {
    EXPECT_EQ(std::string(e.what()), dir_.string() + ": is a directory");
  }
  fs::create_directories(dir_ / "folder.bin");
  json d = doc_;
  d["buffer"] = "folder.bin";
  EXPECT_EQ(errorFor(d), (dir_ / "bad.json").string() +
                             ": buffer: " + (dir_ / "folder.bin").string() + ": is a directory");
  d["buffer"] = "/dev/zero";
  EXPECT_EQ(errorFor(d),
            (dir_ / "bad.json").string() +
                ": buffer: /dev/zero: is not a regular file (a device, fifo or socket)");
}

}  // namespace
}  // namespace penumbra
