#include "lighting/exr_header.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "lighting/hdr_image.h"
#include "tests/scratch_dir.h"
#include "tests/test_data.h"

namespace penumbra::lighting {
namespace {

// An OpenEXR header written byte by byte (OpenEXR File Layout), so each test states the one
// field it breaks. Pixel data never follows: the walk must decide from the header alone.
struct HeaderBytes {
  std::string bytes;
  explicit HeaderBytes(uint32_t versionFlags = 0) {
    i32(20000630);
    i32(int32_t(2 | versionFlags));
  }
  void i32(int32_t v) {
    for (int i = 0; i < 4; ++i) bytes.push_back(char(uint32_t(v) >> (8 * i)));
  }
  void attribute(const std::string& name, const std::string& type, const std::string& value) {
    bytes += name + '\0' + type + '\0';
    i32(int32_t(value.size()));
    bytes += value;
  }
  static std::string ints(std::initializer_list<int32_t> values) {
    HeaderBytes b;
    b.bytes.clear();
    for (int32_t v : values) b.i32(v);
    return b.bytes;
  }
  // R, G, B of one pixel type (0 uint, 1 half, 2 float), full resolution.
  void channels(int type, int count = 3) {
    std::string v;
    const char* names[] = {"B", "G", "R", "A"};
    for (int c = 0; c < count; ++c) {
      v += std::string(names[c]) + '\0' + ints({type}) + std::string(4, '\0') + ints({1, 1});
    }
    attribute("channels", "chlist", v + '\0');
  }
  void compression(int c) { attribute("compression", "compression", std::string(1, char(c))); }
  void window(int32_t w, int32_t h) {
    attribute("dataWindow", "box2i", ints({0, 0, w - 1, h - 1}));
  }
  void tiles(uint32_t tw, uint32_t th, int mode) {
    attribute("tiles", "tiledesc", ints({int32_t(tw), int32_t(th)}) + char(mode));
  }
  // A complete header: the attributes above, then the end of the header.
  static HeaderBytes image(int32_t w, int32_t h, int compression, int type = 2) {
    HeaderBytes b;
    b.channels(type);
    b.compression(compression);
    b.window(w, h);
    return b;
  }
  // The same, tiled (version flag 0x200), uncompressed.
  static HeaderBytes tiledImage(int32_t w, int32_t h, uint32_t tw, uint32_t th, int mode,
                                int type = 2) {
    HeaderBytes b(0x200);
    b.channels(type);
    b.compression(0);
    b.window(w, h);
    b.tiles(tw, th, mode);
    return b;
  }
};

class ExrHeader : public ::testing::Test {
 protected:
  std::filesystem::path dir = test::scratchPath("exr_header");
  void SetUp() override { std::filesystem::create_directories(dir); }
  void TearDown() override { std::filesystem::remove_all(dir); }

  std::filesystem::path write(const HeaderBytes& h, bool end = true) {
    const auto path = dir / "probe.exr";
    std::ofstream(path, std::ios::binary) << h.bytes << (end ? std::string(1, '\0') : "");
    return path;
  }
  // The message readExrLayout throws for `h`.
  std::string refusal(const HeaderBytes& h, bool end = true) {
    try {
      readExrLayout(write(h, end));
    } catch (const HdrError& e) {
      return e.what();
    }
    return "(accepted)";
  }
};

// Every real probe passes, and the walk reads what OpenEXR writes.
TEST_F(ExrHeader, BlenderProbesPass) {
  if (!std::filesystem::exists(penumbra::testing::blenderProbeDir()))
    GTEST_SKIP() << "blender-data is not installed";
  int probes = 0;
  for (const auto& e : std::filesystem::directory_iterator(penumbra::testing::blenderProbeDir())) {
    if (e.path().extension() != ".exr") continue;
    const ExrLayout l = readExrLayout(e.path());
    EXPECT_EQ(l.width, 2 * l.height) << e.path();
    EXPECT_GE(l.channels, 3) << e.path();
    EXPECT_LE(l.chunkBytes, kMaxExrChunkBytes) << e.path();
    ++probes;
  }
  EXPECT_EQ(probes, 8);
}

TEST_F(ExrHeader, ScanLineLayout) {
  const ExrLayout l = readExrLayout(write(HeaderBytes::image(100, 40, 3, 1)));  // ZIP, half
  EXPECT_FALSE(l.tiled);
  EXPECT_EQ(l.width, 100);
  EXPECT_EQ(l.height, 40);
  EXPECT_EQ(l.channels, 3);
  EXPECT_EQ(l.bytesPerPixel, 6);
  EXPECT_EQ(l.linesPerChunk, 16);
  EXPECT_EQ(l.chunkBytes, 100 * 16 * 6);
  EXPECT_EQ(l.chunks, 3);  // 16 + 16 + 8 lines
}

// Tile counts over levels, worked by hand for an 8 x 4 image in 2 x 2 tiles.
TEST_F(ExrHeader, TiledLayoutCountsEveryLevel) {
  const auto tiled = [&](int mode) {
    return readExrLayout(write(HeaderBytes::tiledImage(8, 4, 2, 2, mode)));
  };
  const ExrLayout one = tiled(0);
  EXPECT_TRUE(one.tiled);
  EXPECT_EQ(one.chunks, 4 * 2);
  EXPECT_EQ(one.chunkBytes, 8 * 2 * 12);  // a row of tiles across the window
  // Mipmaps 8x4, 4x2, 2x1, 1x1: 8 + 2 + 1 + 1 tiles.
  EXPECT_EQ(tiled(1).chunks, 12);
  // Ripmaps: widths 8, 4, 2, 1 (4 + 2 + 1 + 1 tiles across) by heights 4, 2, 1 (2 + 1 + 1).
  EXPECT_EQ(tiled(2).chunks, 8 * 4);
}

// The fuzz finding (tests/fuzz/regressions/exr): 16,777,210 x 6 half RGB, PXR24.
TEST_F(ExrHeader, RefusesTheWindowOpenExrWouldAllocateFrom) {
  EXPECT_EQ(refusal(HeaderBytes::image(16'777'210, 6, 5, 1)),
            "probe.exr: data window of 16777210x6 pixels: expected 1 to 33554432 pixels");
  EXPECT_EQ(refusal(HeaderBytes::image(0, 6, 5, 1)),
            "probe.exr: data window of 0x6 pixels: expected 1 to 33554432 pixels");
}

// Within the pixel limit, a chunk can still be too large: 2,000,000 x 16 float RGB is 32 Mpx,
// but ZIP's 16-line chunks of it are 384 MB. Uncompressed (one line a chunk) it passes.
TEST_F(ExrHeader, RefusesChunksPastTheLimit) {
  EXPECT_EQ(refusal(HeaderBytes::image(2'000'000, 16, 3)),
            "probe.exr: ZIP chunks of 16 lines of 2000000 pixels at 12 bytes a pixel: 384000000 "
            "bytes a chunk, expected at most 67108864");
  EXPECT_EQ(readExrLayout(write(HeaderBytes::image(2'000'000, 16, 0))).chunkBytes, 24'000'000);
  EXPECT_EQ(refusal(HeaderBytes::tiledImage(64, 64, 65536, 65536, 0)),
            "probe.exr: tile rows of 65536x65536 pixels at 12 bytes a pixel: 51539607552 bytes a "
            "chunk, expected at most 67108864");
  EXPECT_NE(refusal(HeaderBytes::tiledImage(64, 64, 0xffffffffu, 0xffffffffu, 0))
                .find("9223372036854775807 bytes a chunk"),
            std::string::npos);
}

TEST_F(ExrHeader, RefusesTooManyChunks) {
  EXPECT_EQ(refusal(HeaderBytes::image(1, 2'000'000, 0)),
            "probe.exr: 2000000 chunks (NONE chunks of 1 lines of 1 pixels): expected at most "
            "1048576");
  // 1024 x 1024 in 1 x 1 tiles: 1,048,576 on one level pass; with mipmaps 1,398,101 do not.
  HeaderBytes h = HeaderBytes::tiledImage(1024, 1024, 1, 1, 0, 1);
  EXPECT_EQ(readExrLayout(write(h)).chunks, 1'048'576);
  h.bytes.back() = char(1);  // the level mode byte ends the header
  EXPECT_EQ(refusal(h),
            "probe.exr: 1398101 chunks (tile rows of 1024x1 pixels): expected at most 1048576");
}

// Sizes inside attributes, which OpenEXR allocates from before it reads the pixels.
TEST_F(ExrHeader, RefusesSizesPastTheirAttributeOrFile) {
  HeaderBytes h = HeaderBytes::image(8, 8, 0);
  h.attribute("thumb", "preview", HeaderBytes::ints({65535, 65535}));
  EXPECT_EQ(refusal(h),
            "probe.exr: byte 167: preview \"thumb\" of 65535x65535 pixels does not "
            "fit its 8 bytes");
  h = HeaderBytes::image(8, 8, 0);
  h.attribute("views", "stringvector",
              HeaderBytes::ints({2}) + "ab" + HeaderBytes::ints({1 << 30}));
  EXPECT_EQ(refusal(h),
            "probe.exr: byte 178: string of 1073741824 bytes in \"views\" does not "
            "fit the attribute");
  h = HeaderBytes::image(8, 8, 0);
  h.bytes += "note";
  h.bytes += '\0';
  h.bytes += "string";
  h.bytes += '\0';
  h.i32(1 << 30);
  EXPECT_EQ(refusal(h),
            "probe.exr: byte 165: attribute \"note\" of 1073741824 bytes runs past "
            "the end of the file (166 bytes)");
  h = HeaderBytes::image(8, 8, 0);
  h.bytes += std::string("note\0string\0", 12);
  h.i32(-5);
  EXPECT_EQ(refusal(h), "probe.exr: byte 149: attribute \"note\" has a negative size");
  // No end of header: the file ends inside the attribute list.
  EXPECT_EQ(refusal(HeaderBytes::image(8, 8, 0), false),
            "probe.exr: byte 149: attribute name runs past the end of the file");
}

TEST_F(ExrHeader, RefusesMalformedFieldsNamed) {
  HeaderBytes h = HeaderBytes::image(8, 8, 0);
  h.bytes[0] = 'x';
  EXPECT_EQ(refusal(h), "probe.exr: byte 0: not an OpenEXR file (magic number)");
  EXPECT_EQ(refusal(HeaderBytes(0x1000)),
            "probe.exr: byte 4: a multi-part or deep OpenEXR file: expected a single-part flat "
            "image");
  EXPECT_EQ(refusal(HeaderBytes(0x800)),
            "probe.exr: byte 4: a multi-part or deep OpenEXR file: expected a single-part flat "
            "image");
  h = HeaderBytes();
  h.channels(7);
  EXPECT_EQ(refusal(h),
            "probe.exr: byte 28: channel \"B\" has pixel type 7: expected 0 (uint), "
            "1 (half) or 2 (float)");
  h = HeaderBytes();
  h.channels(2);
  h.compression(12);
  EXPECT_EQ(refusal(h), "probe.exr: byte 111: compression: expected one byte from 0 to 9");
  h = HeaderBytes();
  h.channels(2);
  h.attribute("dataWindow", "string", "x");
  EXPECT_EQ(refusal(h),
            "probe.exr: byte 83: attribute \"dataWindow\" has type \"string\": expected \"box2i\"");
  h = HeaderBytes();
  h.channels(2);
  h.compression(0);
  EXPECT_EQ(refusal(h), "probe.exr: header has no \"dataWindow\" attribute");
  h = HeaderBytes();
  h.attribute(std::string(40, 'n'), "int", HeaderBytes::ints({1}));
  EXPECT_EQ(refusal(h), "probe.exr: byte 8: attribute name is longer than 31 characters");
  h = HeaderBytes::image(8, 8, 0);
  h.attribute("type", "string", "deepscanline");
  EXPECT_EQ(refusal(h), "probe.exr: byte 165: type: expected \"scanlineimage\"");
  EXPECT_EQ(refusal(HeaderBytes()), "probe.exr: header has no \"channels\" attribute");
  std::ofstream(dir / "short.exr") << "v/1";
  EXPECT_THROW(
      {
        try {
          readExrLayout(dir / "short.exr");
        } catch (const HdrError& e) {
          EXPECT_STREQ(e.what(), "short.exr: is 3 bytes: not an OpenEXR file");
          throw;
        }
      },
      HdrError);
}

}  // namespace
}  // namespace penumbra::lighting
