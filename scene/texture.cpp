#include "scene/texture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#ifdef PENUMBRA_HAVE_PNG
#include <png.h>
#endif
#ifdef PENUMBRA_HAVE_GLTF
#include <tiny_gltf.h>
#endif

namespace penumbra::scene {
namespace {

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw TextureError(name + ": " + what);
}

// t^2.4 for t in (0, 1], from IEEE +, -, *, / only: y = t^(12/5) is the root of y^5 = t^12,
// found by Newton's method from y0 = t^2 >= t^2.4. The iteration is convex there, so it
// decreases monotonically to the root; it stops when a step no longer decreases y (the
// rounding floor), which is the same step on every machine.
double pow24(double t) {
  const double t2 = t * t, t4 = t2 * t2, t8 = t4 * t4, a = t8 * t4;
  double y = t2;
  for (int i = 0; i < 200; ++i) {
    const double y2 = y * y, y4 = y2 * y2;
    const double next = y - (y4 * y - a) / (5.0 * y4);
    if (!(next < y)) break;
    y = next;
  }
  return y;
}

double srgbToLinearValue(double c) {
  if (c <= 0.04045) return c / 12.92;
  return pow24((c + 0.055) / 1.055);
}

const std::array<double, 256>& srgbTable() {
  static const std::array<double, 256> table = [] {
    std::array<double, 256> t{};
    for (int i = 0; i < 256; ++i) t[size_t(i)] = srgbToLinearValue(i / 255.0);
    return t;
  }();
  return table;
}

void checkSize(uint64_t w, uint64_t h, const std::string& name) {
  if (w == 0 || h == 0 || w > kMaxTextureSide || h > kMaxTextureSide) {
    fail(name, std::to_string(w) + " x " + std::to_string(h) + " pixels, expected 1 to " +
                   std::to_string(kMaxTextureSide) + " per side");
  }
}

// Netpbm PPM (P6 binary, P3 ASCII; maxval 1..65535): the format any tool can write, read
// here without a library so OBJ textures decode in every build.
Texture decodePpm(std::string_view b, const std::string& name) {
  const bool binary = b[1] == '6';
  size_t at = 2;
  const auto skipSpace = [&] {
    while (at < b.size()) {
      if (b[at] == '#') {
        while (at < b.size() && b[at] != '\n') ++at;
      } else if (b[at] == ' ' || b[at] == '\t' || b[at] == '\r' || b[at] == '\n') {
        ++at;
      } else {
        break;
      }
    }
  };
  const auto number = [&](const char* what) -> uint64_t {
    skipSpace();
    uint64_t v = 0;
    size_t digits = 0;
    while (at < b.size() && b[at] >= '0' && b[at] <= '9' && digits < 9) {
      v = v * 10 + uint64_t(b[at] - '0');
      ++at;
      ++digits;
    }
    if (digits == 0 || (at < b.size() && b[at] >= '0' && b[at] <= '9')) {
      fail(name, std::string("PPM: bad or missing ") + what);
    }
    return v;
  };
  const uint64_t w = number("width"), h = number("height"), maxval = number("maxval");
  checkSize(w, h, name);
  if (maxval == 0 || maxval > 65535) fail(name, "PPM: maxval must be 1 to 65535");
  const size_t samples = size_t(w) * size_t(h) * 3;
  std::vector<uint32_t> codes(samples);
  if (binary) {
    if (at >= b.size()) fail(name, "PPM: no pixel data");
    ++at;  // the single whitespace after maxval
    const size_t bytes = maxval > 255 ? 2 : 1;
    if (b.size() - at < samples * bytes) {
      fail(name, "PPM: truncated (" + std::to_string(b.size() - at) + " bytes of pixel data, " +
                     std::to_string(samples * bytes) + " expected)");
    }
    for (size_t i = 0; i < samples; ++i) {
      const auto* p = reinterpret_cast<const unsigned char*>(b.data() + at + i * bytes);
      codes[i] = bytes == 2 ? uint32_t(p[0]) << 8 | p[1] : p[0];
    }
  } else {
    for (size_t i = 0; i < samples; ++i) codes[i] = static_cast<uint32_t>(number("sample"));
  }
  Texture t{uint32_t(w), uint32_t(h), {}};
  t.texels.resize(size_t(w) * size_t(h));
  for (size_t i = 0; i < samples; ++i) {
    if (codes[i] > maxval) fail(name, "PPM: sample " + std::to_string(codes[i]) + " above maxval");
    const double c = maxval == 255 ? srgbTable()[codes[i]]
                                   : srgbToLinearValue(double(codes[i]) / double(maxval));
    t.texels[i / 3][int(i % 3)] = c;
  }
  return t;
}

#ifdef PENUMBRA_HAVE_PNG
// libpng's simplified API (1.6): errors come back in image.message, no setjmp. Read as 8-bit
// sRGB RGBA; the alpha channel (opacity, not colour) is dropped.
Texture decodePngWithLibpng(std::string_view b, const std::string& name) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&image, b.data(), b.size())) {
    fail(name, std::string("not a valid PNG: ") + image.message);
  }
  if (image.width == 0 || image.height == 0 || image.width > kMaxTextureSide ||
      image.height > kMaxTextureSide) {
    png_image_free(&image);
    checkSize(image.width, image.height, name);
  }
  image.format = PNG_FORMAT_RGBA;
  std::vector<unsigned char> rgba(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, rgba.data(), 0, nullptr)) {
    fail(name, std::string("not a valid PNG: ") + image.message);
  }
  return textureFromSamples(image.width, image.height, 4, 8, rgba.data());
}
#endif

#ifdef PENUMBRA_HAVE_GLTF
// stb_image through tinygltf (PNG, JPEG), 8 or 16 bits per channel.
Texture decodeWithStb(std::string_view b, const std::string& name) {
  tinygltf::Image image;
  std::string err, warn;
  if (b.size() > size_t(std::numeric_limits<int>::max()) ||
      !tinygltf::LoadImageData(&image, 0, &err, &warn, 0, 0,
                               reinterpret_cast<const unsigned char*>(b.data()), int(b.size()),
                               nullptr)) {
    fail(name, "cannot decode the image" + (err.empty() ? std::string() : ": " + err));
  }
  const uint32_t w = uint32_t(image.width), h = uint32_t(image.height);
  checkSize(w, h, name);
  const size_t bytesPer = image.bits == 16 ? 2 : 1;
  if (image.component < 1 || image.component > 4 ||
      image.image.size() != size_t{w} * h * size_t(image.component) * bytesPer) {
    fail(name, "decoded image has an unexpected layout");
  }
  return textureFromSamples(w, h, image.component, image.bits, image.image.data());
}
#endif

// Repeat: the fractional part; mirrored repeat: period 2, reflected in [1, 2); clamp: [0, 1].
// Exact for |c| < 2^52 (floor and the subtractions are exact there).
double wrapCoordinate(double c, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::kRepeat:
      return c - std::floor(c);
    case TextureWrap::kMirroredRepeat: {
      const double m = c - 2.0 * std::floor(c * 0.5);
      return m <= 1.0 ? m : 2.0 - m;
    }
    case TextureWrap::kClampToEdge:
      break;
  }
  return std::clamp(c, 0.0, 1.0);
}

// The texel index `i` (possibly -1 or `size`) under the wrap mode.
uint32_t wrapIndex(int64_t i, uint32_t size, TextureWrap wrap) {
  const int64_t n = size;
  switch (wrap) {
    case TextureWrap::kRepeat:
      return uint32_t(((i % n) + n) % n);
    case TextureWrap::kMirroredRepeat: {
      const int64_t m = ((i % (2 * n)) + 2 * n) % (2 * n);
      return uint32_t(m < n ? m : 2 * n - 1 - m);
    }
    case TextureWrap::kClampToEdge:
      break;
  }
  return uint32_t(std::clamp<int64_t>(i, 0, n - 1));
}

}  // namespace

double srgbToLinear(uint8_t code) {
  return srgbTable()[code];
}

Texture textureFromSamples(uint32_t width, uint32_t height, int components, int bits,
                           const unsigned char* data) {
  Texture t{width, height, std::vector<glm::dvec3>(size_t{width} * height)};
  const std::array<double, 256>& lut = srgbTable();
  const size_t stride = size_t(components) * (bits == 16 ? 2 : 1);
  for (size_t i = 0; i < t.texels.size(); ++i) {
    const unsigned char* p = data + i * stride;
    for (int c = 0; c < 3; ++c) {
      const size_t ch = components >= 3 ? size_t(c) : 0;  // 1 or 2 components: grey
      if (bits == 16) {
        uint16_t v;
        std::memcpy(&v, p + 2 * ch, 2);  // stb_image gives native-endian 16-bit samples
        t.texels[i][c] = srgbToLinearValue(v / 65535.0);
      } else {
        t.texels[i][c] = lut[p[ch]];
      }
    }
  }
  return t;
}

std::optional<std::pair<uint32_t, uint32_t>> pngOrJpegSize(const unsigned char* b, size_t n) {
  const auto be16 = [&](size_t i) { return uint32_t(b[i]) << 8 | b[i + 1]; };
  const auto be32 = [&](size_t i) { return be16(i) << 16 | be16(i + 2); };
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (n >= 24 && std::memcmp(b, kPng, 8) == 0) return std::pair(be32(16), be32(20));
  if (n < 4 || b[0] != 0xff || b[1] != 0xd8) return std::nullopt;
  for (size_t i = 2; i + 9 <= n;) {
    if (b[i] != 0xff) return std::nullopt;
    const unsigned char marker = b[i + 1];
    // SOF0-SOF15 carry the size, except DHT (C4), JPG (C8) and DAC (CC).
    if (marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc) {
      return std::pair(be16(i + 7), be16(i + 5));
    }
    i += 2 + be16(i + 2);
  }
  return std::nullopt;
}

std::optional<Texture> decodeTexture(std::string_view bytes, const std::string& name) {
  if (bytes.size() >= 2 && bytes[0] == 'P' && (bytes[1] == '6' || bytes[1] == '3')) {
    return decodePpm(bytes, name);
  }
  const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
  const bool png = bytes.size() >= 8 && b[0] == 0x89 && b[1] == 'P' && b[2] == 'N' && b[3] == 'G';
  const bool jpeg = bytes.size() >= 2 && b[0] == 0xff && b[1] == 0xd8;
  if (!png && !jpeg) fail(name, "not a PNG, JPEG or PPM image");
  const auto size = pngOrJpegSize(b, bytes.size());
  if (!size) fail(name, std::string("truncated ") + (png ? "PNG" : "JPEG") + " header");
  checkSize(size->first, size->second, name);
#ifdef PENUMBRA_HAVE_PNG
  if (png) return decodePngWithLibpng(bytes, name);
#endif
#ifdef PENUMBRA_HAVE_GLTF
  return decodeWithStb(bytes, name);
#else
  return std::nullopt;
#endif
}

glm::dvec3 sampleBilinear(const Texture& t, double u, double v, TextureWrap wrapU,
                          TextureWrap wrapV) {
  // Wrapped into [0, 1] (or [0, 1) for repeat) first, so the texel indices below stay small.
  const double x = wrapCoordinate(u, wrapU) * t.width - 0.5;
  const double y = wrapCoordinate(v, wrapV) * t.height - 0.5;
  const double x0 = std::floor(x), y0 = std::floor(y);
  const double fx = x - x0, fy = y - y0;
  const uint32_t i0 = wrapIndex(int64_t(x0), t.width, wrapU);
  const uint32_t i1 = wrapIndex(int64_t(x0) + 1, t.width, wrapU);
  const uint32_t j0 = wrapIndex(int64_t(y0), t.height, wrapV);
  const uint32_t j1 = wrapIndex(int64_t(y0) + 1, t.height, wrapV);
  const auto at = [&](uint32_t i, uint32_t j) { return t.texels[size_t(j) * t.width + i]; };
  const glm::dvec3 top = at(i0, j0) * (1.0 - fx) + at(i1, j0) * fx;
  const glm::dvec3 bottom = at(i0, j1) * (1.0 - fx) + at(i1, j1) * fx;
  return top * (1.0 - fy) + bottom * fy;
}

}  // namespace penumbra::scene
