// Triangle setup with arbitrary floats (raster/triangle_setup.h): the bit-exact core that
// every frame goes through. Input: a viewport (two u16, each taken modulo 1024, plus 1),
// then either twelve raw floats (three clip-space vertices, any bit pattern: NaN, infinity,
// denormals) or, when the first byte is odd, sixteen matrix elements and nine world
// coordinates transformed as a trace's camera_view_proj does. Every triangle that clipping
// and snapping produce is set up, its attribute plane computed, and its rows walked twice:
// the stepped RowWalker must give exactly rowSpan()'s runs (spec §4).
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "raster/triangle_setup.h"

namespace {

using namespace penumbra;
using namespace penumbra::raster;

class Bytes {
 public:
  Bytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  template <class T>
  T next() {
    T value{};
    const size_t n = std::min(sizeof(T), size_ - at_);
    std::memcpy(&value, data_ + at_, n);
    at_ += n;
    return value;
  }

 private:
  const uint8_t* data_;
  size_t size_, at_ = 0;
};

void walkRows(const SetupTriangle& t, uint32_t width) {
  RowWalker walker(t, t.minY);
  for (int32_t y = t.minY; y < t.maxY; ++y, walker.nextRow()) {
    int32_t a0 = 0, b0 = 0, a1 = 0, b1 = 0;
    const bool expected = rowSpan(t, y, 0, int32_t(width), a0, b0);
    const bool walked = walker.span(0, int32_t(width), a1, b1);
    if (expected != walked || (expected && (a0 != a1 || b0 != b1))) {
      std::fprintf(stderr, "row %d: rowSpan %d [%d, %d), RowWalker %d [%d, %d)\n", y, int(expected),
                   a0, b0, int(walked), a1, b1);
      std::abort();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  Bytes in(data, size);
  const uint8_t mode = in.next<uint8_t>();
  const uint32_t width = in.next<uint16_t>() % 1024u + 1;
  const uint32_t height = in.next<uint16_t>() % 1024u + 1;
  std::array<ClipVertex, 3> tri{};
  if (mode & 1) {
    core::Mat4 m;
    for (float& e : m.m) e = in.next<float>();
    for (ClipVertex& v : tri) {
      const core::Vec3 p{in.next<float>(), in.next<float>(), in.next<float>()};
      v = transformPoint(m, p);
    }
  } else {
    for (ClipVertex& v : tri)
      v = {in.next<float>(), in.next<float>(), in.next<float>(), in.next<float>()};
  }
  std::vector<std::array<SnappedVertex, 3>> snapped;
  clipAndSnapTriangle(tri, width, height, snapped);
  for (const std::array<SnappedVertex, 3>& v : snapped) {
    SetupTriangle t;
    if (!setupTriangle(v, width, height, t)) continue;
    (void)attributePlane(t, {in.next<uint8_t>(), in.next<uint8_t>(), in.next<uint8_t>()});
    walkRows(t, width);
  }
  return 0;
}
