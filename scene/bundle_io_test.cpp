// The bundle container: exact round trip, and refusal of every damaged file.
#include "scene/bundle_io.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include "scene/sha256.h"

namespace penumbra::scene {
namespace {

namespace fs = std::filesystem;

class BundleFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = fs::temp_directory_path() /
            ("penumbra-bundle-" +
             std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    BundleWriter w(3);
    const std::vector<float> floats{1.5f, -2.0f, 1e-30f};
    const std::vector<uint32_t> ints{7, 8, 9, 10};
    w.add<float>("floats", floats);
    w.add<uint32_t>("ints", ints);
    w.addValue<uint64_t>("one", 42);
    w.add<uint8_t>("empty", {});
    w.write(path_);
  }
  void TearDown() override { fs::remove(path_); }
  std::string errorOf(uint32_t version = 3) {
    try {
      BundleReader r(path_, version);
    } catch (const BundleError& e) {
      return e.what();
    }
    return "";
  }
  fs::path path_;
};

TEST_F(BundleFiles, RoundTrip) {
  BundleReader r(path_, 3);
  EXPECT_EQ(r.get<float>("floats"), (std::vector<float>{1.5f, -2.0f, 1e-30f}));
  EXPECT_EQ(r.get<uint32_t>("ints"), (std::vector<uint32_t>{7, 8, 9, 10}));
  EXPECT_EQ(r.getValue<uint64_t>("one"), 42u);
  EXPECT_TRUE(r.get<uint8_t>("empty").empty());
  EXPECT_FALSE(r.has("absent"));
  EXPECT_THROW(r.get<float>("absent"), BundleError);
  EXPECT_THROW(r.get<double>("floats"), BundleError);  // element size differs
  EXPECT_THROW(r.getValue<uint32_t>("ints"), BundleError);
}

TEST_F(BundleFiles, WrongVersionIsRefused) {
  EXPECT_NE(errorOf(4).find("version 3"), std::string::npos);
}

TEST_F(BundleFiles, CorruptionIsDetected) {
  {
    std::fstream f(path_, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(-3, std::ios::end);
    f.put('\x55');
  }
  EXPECT_NE(errorOf().find("checksum"), std::string::npos) << errorOf();
}

TEST_F(BundleFiles, TruncationIsDetected) {
  fs::resize_file(path_, fs::file_size(path_) - 10);
  EXPECT_NE(errorOf().find(path_.string()), std::string::npos);
  fs::resize_file(path_, 20);
  EXPECT_NE(errorOf().find("bad magic"), std::string::npos);
}

// A section name length near 2^32 with a valid checksum (a crafted file, not a damaged one):
// refused by name, never read past the buffer (it wrapped a 32-bit bounds check once).
TEST_F(BundleFiles, HugeSectionNameIsRefusedEvenWithAValidChecksum) {
  for (uint32_t length : {0xFFFFFFF8u, 0xFFFFFFF4u, 256u}) {
    BundleWriter w(3);
    const std::vector<uint8_t> one{1};
    w.add<uint8_t>("x", one);
    w.write(path_);
    std::vector<uint8_t> bytes;
    {
      std::ifstream in(path_, std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(in), {});
    }
    constexpr size_t kHeader = 16 + 4 + 4 + 32;
    std::memcpy(bytes.data() + kHeader, &length, 4);
    Sha256 hash;
    hash.update(std::span<const uint8_t>(bytes).subspan(kHeader));
    const auto digest = hash.finish();
    std::memcpy(bytes.data() + 24, digest.data(), 32);
    std::ofstream(path_, std::ios::binary)
        .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    EXPECT_NE(errorOf().find("name of " + std::to_string(length) + " bytes"), std::string::npos)
        << errorOf();
  }
}

TEST_F(BundleFiles, NotABundle) {
  std::ofstream(path_) << "{\"format\": \"something else\"}";
  EXPECT_NE(errorOf().find("bad magic"), std::string::npos);
  EXPECT_THROW(BundleReader(path_.string() + ".absent", 3), BundleError);
}

}  // namespace
}  // namespace penumbra::scene
