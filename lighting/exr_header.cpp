#include "lighting/exr_header.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "lighting/hdr_image.h"

namespace penumbra::lighting {
namespace {

// Version field flags (OpenEXR File Layout, "Version Field").
constexpr uint32_t kTiledFlag = 0x200, kLongNamesFlag = 0x400, kNonImageFlag = 0x800,
                   kMultiPartFlag = 0x1000;

// Scan lines per chunk of each compression, by OpenEXR's Compression enum value: NONE, RLE,
// ZIPS, ZIP, PIZ, PXR24, B44, B44A, DWAA, DWAB.
constexpr std::array<int64_t, 10> kLinesPerChunk = {1, 1, 1, 16, 32, 16, 32, 32, 32, 256};
constexpr std::array<const char*, 10> kCompressionNames = {"NONE",  "RLE", "ZIPS", "ZIP",  "PIZ",
                                                           "PXR24", "B44", "B44A", "DWAA", "DWAB"};

// Products of header fields, which can each be up to 2^32: saturate instead of wrapping, so
// a product past a limit always compares as past it.
int64_t mulSat(int64_t a, int64_t b) {
  int64_t r = 0;
  return __builtin_mul_overflow(a, b, &r) ? std::numeric_limits<int64_t>::max() : r;
}

int64_t ceilDiv(int64_t a, int64_t b) {
  return (a + b - 1) / b;
}

// EXR stores every integer little-endian.
int32_t littleEndian32(const char* bytes) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | uint8_t(bytes[i]);
  return int32_t(v);
}

// Little-endian reads over bytes with the file offset of each, for messages.
class HeaderReader {
 public:
  HeaderReader(const std::filesystem::path& path, std::string name)
      : in_(path, std::ios::binary), name_(std::move(name)) {
    std::error_code ec;
    size_ = int64_t(std::filesystem::file_size(path, ec));
    if (ec || !in_) fail("cannot open the file");
  }

  int64_t offset() const { return offset_; }
  int64_t remaining() const { return size_ - offset_; }

  [[noreturn]] void failAt(int64_t at, const std::string& what) const {
    throw HdrError(name_ + ": byte " + std::to_string(at) + ": " + what);
  }
  [[noreturn]] void fail(const std::string& what) const { throw HdrError(name_ + ": " + what); }

  std::string bytes(int64_t n, const std::string& what) {
    need(n, what);
    std::string s(size_t(n), '\0');
    in_.read(s.data(), std::streamsize(n));
    if (!in_) failAt(offset_, "cannot read " + what);
    offset_ += n;
    return s;
  }
  void skip(int64_t n, const std::string& what) {
    need(n, what);
    in_.seekg(std::streamoff(n), std::ios::cur);
    offset_ += n;
  }
  int32_t i32(const std::string& what) { return littleEndian32(bytes(4, what).data()); }
  // A zero-terminated name of at most maxLength characters.
  std::string name(size_t maxLength, const std::string& what) {
    const int64_t at = offset_;
    std::string s;
    for (;;) {
      if (remaining() <= 0) failAt(at, what + " runs past the end of the file");
      const int c = in_.get();
      if (!in_) failAt(offset_, "cannot read " + what);
      ++offset_;
      if (c == 0) return s;
      if (s.size() == maxLength) {
        failAt(at, what + " is longer than " + std::to_string(maxLength) + " characters");
      }
      s.push_back(char(c));
    }
  }

 private:
  void need(int64_t n, const std::string& what) const {
    if (n > remaining()) {
      failAt(offset_, what + " of " + std::to_string(n) + " bytes runs past the end of the file (" +
                          std::to_string(size_) + " bytes)");
    }
  }

  std::ifstream in_;
  std::string name_;
  int64_t size_ = 0, offset_ = 0;
};

// Little-endian reads inside one attribute's value.
struct ValueCursor {
  const std::string& bytes;
  size_t at = 0;
  bool has(size_t n) const { return n <= bytes.size() - at; }
  int32_t i32() {
    at += 4;
    return littleEndian32(bytes.data() + at - 4);
  }
};

void requireType(const HeaderReader& r, int64_t at, const std::string& name,
                 const std::string& type, const char* expected) {
  if (type != expected) {
    r.failAt(at,
             "attribute \"" + name + "\" has type \"" + type + "\": expected \"" + expected + "\"");
  }
}

// chlist: per channel name\0, int32 pixel type, uint8 pLinear, 3 reserved bytes, int32 x and
// y sampling; then a zero byte.
void readChannels(const HeaderReader& r, int64_t valueAt, const std::string& value,
                  ExrLayout& layout) {
  ValueCursor c{value};
  for (;;) {
    const size_t end = value.find('\0', c.at);
    if (end == std::string::npos) r.failAt(valueAt, "channel list does not end with a zero byte");
    const std::string channel = value.substr(c.at, end - c.at);
    c.at = end + 1;
    if (channel.empty()) break;
    if (!c.has(16)) r.failAt(valueAt, "channel \"" + channel + "\" is cut short");
    const int32_t type = c.i32();
    c.at += 4;  // pLinear and reserved
    const int32_t xSampling = c.i32(), ySampling = c.i32();
    // UINT, HALF, FLOAT
    constexpr int64_t kSampleBytes[3] = {4, 2, 4};
    if (type < 0 || type > 2) {
      r.failAt(valueAt, "channel \"" + channel + "\" has pixel type " + std::to_string(type) +
                            ": expected 0 (uint), 1 (half) or 2 (float)");
    }
    if (xSampling < 1 || ySampling < 1) {
      r.failAt(valueAt, "channel \"" + channel + "\" has sampling " + std::to_string(xSampling) +
                            "x" + std::to_string(ySampling) + ": expected at least 1x1");
    }
    ++layout.channels;
    layout.bytesPerPixel += kSampleBytes[type];
  }
  if (c.at != value.size()) {
    r.failAt(valueAt, "channel list ends " + std::to_string(value.size() - c.at) +
                          " bytes before its attribute does");
  }
}

// Attribute types that hold sizes of their own, which OpenEXR allocates from: each must fit
// in the attribute.
void checkInnerSizes(const HeaderReader& r, int64_t valueAt, const std::string& name,
                     const std::string& type, const std::string& value) {
  ValueCursor c{value};
  if (type == "preview") {
    // uint32 width, height, then width x height RGBA bytes.
    if (!c.has(8)) r.failAt(valueAt, "preview \"" + name + "\" is shorter than 8 bytes");
    const int64_t w = uint32_t(c.i32()), h = uint32_t(c.i32());
    if (mulSat(mulSat(w, h), 4) != int64_t(value.size()) - 8) {
      r.failAt(valueAt, "preview \"" + name + "\" of " + std::to_string(w) + "x" +
                            std::to_string(h) + " pixels does not fit its " +
                            std::to_string(value.size()) + " bytes");
    }
  } else if (type == "stringvector") {
    // int32 length, then the string; repeated to the attribute's end.
    while (c.at < value.size()) {
      const size_t at = c.at;
      if (!c.has(4)) r.failAt(valueAt + int64_t(at), "string vector \"" + name + "\" is cut short");
      const int32_t length = c.i32();
      if (length < 0 || !c.has(size_t(length))) {
        r.failAt(valueAt + int64_t(at), "string of " + std::to_string(length) + " bytes in \"" +
                                            name + "\" does not fit the attribute");
      }
      c.at += size_t(length);
    }
  }
}

// Levels of one axis of a tiled image, as a file that rounds level sizes up has them:
// ceil(log2(size)) + 1. Rounding up gives as many levels as rounding down or more, each at
// least as large, so the tile count below bounds either file's (and is exact for round-up).
int levelCount(int64_t size) {
  int n = 0;
  while ((int64_t{1} << n) < size) ++n;
  return n + 1;
}

int64_t levelSize(int64_t size, int level) {
  return std::max<int64_t>(1, ceilDiv(size, int64_t{1} << level));
}

// Tiles over every level. At most 26 x 26 levels of at most 2^25 tiles: no overflow.
int64_t tileCount(const ExrLayout& l) {
  const auto tilesOf = [&](int lx, int ly) {
    return ceilDiv(levelSize(l.width, lx), l.tileWidth) *
           ceilDiv(levelSize(l.height, ly), l.tileHeight);
  };
  if (l.levelMode == 0) return tilesOf(0, 0);
  int64_t total = 0;
  if (l.levelMode == 1) {
    const int n = levelCount(std::max(l.width, l.height));
    for (int i = 0; i < n; ++i) total += tilesOf(i, i);
    return total;
  }
  const int nx = levelCount(l.width), ny = levelCount(l.height);
  for (int y = 0; y < ny; ++y) {
    for (int x = 0; x < nx; ++x) total += tilesOf(x, y);
  }
  return total;
}

}  // namespace

ExrLayout readExrLayout(const std::filesystem::path& path) {
  const std::string file = path.filename().string();
  HeaderReader r(path, file);
  if (r.remaining() < 8)
    r.fail("is " + std::to_string(r.remaining()) + " bytes: not an OpenEXR file");
  if (r.i32("magic number") != 20000630) r.failAt(0, "not an OpenEXR file (magic number)");
  const uint32_t version = uint32_t(r.i32("version"));
  if ((version & 0xff) != 2) {
    r.failAt(4, "OpenEXR format version " + std::to_string(version & 0xff) + ": expected 2");
  }
  if ((version & kMultiPartFlag) != 0 || (version & kNonImageFlag) != 0) {
    r.failAt(4, "a multi-part or deep OpenEXR file: expected a single-part flat image");
  }
  if ((version & ~uint32_t(0xff | kTiledFlag | kLongNamesFlag)) != 0) {
    r.failAt(4, "unknown version flags " + std::to_string(version >> 8));
  }
  ExrLayout layout;
  layout.tiled = (version & kTiledFlag) != 0;
  const size_t maxName = (version & kLongNamesFlag) != 0 ? 255 : 31;
  bool haveChannels = false, haveCompression = false, haveWindow = false, haveTiles = false;
  for (;;) {
    const int64_t at = r.offset();
    const std::string name = r.name(maxName, "attribute name");
    if (name.empty()) break;
    const std::string type = r.name(maxName, "type of attribute \"" + name + "\"");
    const int32_t size = r.i32("size of attribute \"" + name + "\"");
    const std::string what = "attribute \"" + name + "\"";
    if (size < 0) r.failAt(at, what + " has a negative size");
    const int64_t valueAt = r.offset();
    if (name == "channels") {
      requireType(r, at, name, type, "chlist");
      readChannels(r, valueAt, r.bytes(size, what), layout);
      haveChannels = true;
    } else if (name == "compression") {
      requireType(r, at, name, type, "compression");
      const std::string v = r.bytes(size, what);
      if (size != 1 || uint8_t(v[0]) >= kLinesPerChunk.size()) {
        r.failAt(valueAt, "compression: expected one byte from 0 to 9");
      }
      layout.compression = uint8_t(v[0]);
      haveCompression = true;
    } else if (name == "dataWindow") {
      requireType(r, at, name, type, "box2i");
      if (size != 16) r.failAt(valueAt, "dataWindow: expected 16 bytes");
      const int64_t xMin = r.i32(name), yMin = r.i32(name), xMax = r.i32(name), yMax = r.i32(name);
      layout.width = xMax - xMin + 1;
      layout.height = yMax - yMin + 1;
      haveWindow = true;
    } else if (name == "tiles") {
      requireType(r, at, name, type, "tiledesc");
      if (size != 9) r.failAt(valueAt, "tiles: expected 9 bytes");
      layout.tileWidth = uint32_t(r.i32(name));
      layout.tileHeight = uint32_t(r.i32(name));
      const int mode = uint8_t(r.bytes(1, name)[0]);
      layout.levelMode = mode & 0x0f;
      if (layout.levelMode > 2 || (mode >> 4) > 1) {
        r.failAt(valueAt + 8, "tiles: level mode " + std::to_string(mode) +
                                  ": expected levels 0 to 2 and rounding 0 or 1");
      }
      haveTiles = true;
    } else if (name == "type") {
      const std::string v = r.bytes(size, what);
      if (type != "string" || v != (layout.tiled ? "tiledimage" : "scanlineimage")) {
        r.failAt(valueAt, "type: expected \"" +
                              std::string(layout.tiled ? "tiledimage" : "scanlineimage") + "\"");
      }
    } else if (type == "preview" || type == "stringvector") {
      checkInnerSizes(r, valueAt, name, type, r.bytes(size, what));
    } else {
      r.skip(size, what);
    }
  }
  const char* missing = !haveChannels                  ? "channels"
                        : !haveCompression             ? "compression"
                        : !haveWindow                  ? "dataWindow"
                        : (layout.tiled && !haveTiles) ? "tiles"
                                                       : nullptr;
  if (missing != nullptr) r.fail(std::string("header has no \"") + missing + "\" attribute");

  const int64_t w = layout.width, h = layout.height;
  if (w <= 0 || h <= 0 || w > kMaxExrPixels || h > kMaxExrPixels || w * h > kMaxExrPixels) {
    r.fail("data window of " + std::to_string(w) + "x" + std::to_string(h) +
           " pixels: expected 1 to " + std::to_string(kMaxExrPixels) + " pixels");
  }
  if (layout.channels == 0) r.fail("channels: the list is empty");
  std::string chunk;
  if (layout.tiled) {
    if (layout.tileWidth < 1 || layout.tileHeight < 1) {
      r.fail("tiles: tile size " + std::to_string(layout.tileWidth) + "x" +
             std::to_string(layout.tileHeight) + ": expected at least 1x1");
    }
    // OpenEXR buffers whole tiles, and reading a tiled file by scan lines (as readExr does)
    // a row of tiles across the data window.
    layout.chunkBytes =
        mulSat(mulSat(std::max(layout.tileWidth, w), layout.tileHeight), layout.bytesPerPixel);
    layout.chunks = tileCount(layout);
    chunk = "tile rows of " + std::to_string(std::max(layout.tileWidth, w)) + "x" +
            std::to_string(layout.tileHeight) + " pixels";
  } else {
    layout.linesPerChunk = kLinesPerChunk[size_t(layout.compression)];
    layout.chunkBytes = mulSat(mulSat(w, layout.linesPerChunk), layout.bytesPerPixel);
    layout.chunks = ceilDiv(h, layout.linesPerChunk);
    chunk = std::string(kCompressionNames[size_t(layout.compression)]) + " chunks of " +
            std::to_string(layout.linesPerChunk) + " lines of " + std::to_string(w) + " pixels";
  }
  if (layout.chunkBytes > kMaxExrChunkBytes) {
    r.fail(chunk + " at " + std::to_string(layout.bytesPerPixel) +
           " bytes a pixel: " + std::to_string(layout.chunkBytes) +
           " bytes a chunk, expected at most " + std::to_string(kMaxExrChunkBytes));
  }
  if (layout.chunks > kMaxExrChunks) {
    r.fail(std::to_string(layout.chunks) + " chunks (" + chunk + "): expected at most " +
           std::to_string(kMaxExrChunks));
  }
  return layout;
}

}  // namespace penumbra::lighting
