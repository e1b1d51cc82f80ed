// Fixed-point triangle setup: snapping, clipping, edge functions, exact row spans, and
// the depth and 8-bit attribute planes (docs/pipeline-spec.md §2–5).
//
// Everything here is scalar and exact; the SIMD kernels (raster/span_kernels.h) only
// evaluate the planes set up here over spans computed here.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "raster/frame_trace.h"

namespace penumbra::raster {

inline constexpr int kSubPixelBits = 8;
inline constexpr int32_t kSubPixelOne = 1 << kSubPixelBits;  // 256
inline constexpr float kGuardBand = 4.0f;                    // spec §3
// The snapping range (spec §3): a vertex whose window coordinate in 1/256 pixel lies beyond
// +-2^22, whose window depth is NaN, or whose clipped corner weight b1 or b2 lies outside
// [-1, 2] is refused before conversion to integers. The guard band keeps every vertex of a
// viewport up to 4096 px within +-2 621 440 (< 2^22) and its weights in [0, 1]; only
// binary32 overflow or cancellation on extreme input leaves the range.
inline constexpr float kMaxSnappedCoordinate = 4194304.0f;  // 2^22
inline constexpr float kMinClippedWeight = -1.0f;
inline constexpr float kMaxClippedWeight = 2.0f;

struct ClipVertex {
  float x, y, z, w;
};

// A clip-space vertex after clipping, with its weights on the original triangle's corners.
struct ClippedVertex {
  ClipVertex clip;
  std::array<float, 3> bary;
};

// A snapped screen-space vertex: 8 sub-pixel bits, window depth, 16-bit corner weights.
struct SnappedVertex {
  int32_t x = 0, y = 0;        // 1/256 pixel
  float z = 0;                 // window depth in [0, 1]
  std::array<int32_t, 3> w{};  // sum 65536 (spec §3)
};

// Transform of a world-space point (spec §2).
ClipVertex transformPoint(const core::Mat4& m, const core::Vec3& p);

// True when the point is inside all seven clip planes (spec §3): a triangle of three such
// vertices is drawn unclipped.
bool insideClipVolume(const ClipVertex& v);

// Snaps a clip-space vertex to a `width` x `height` viewport (spec §2), with `weights` as
// its corner weights. `v` must be inside the clip volume (insideClipVolume): then it is
// inside the snapping range; a vertex outside it snaps to (0, 0).
SnappedVertex snapVertex(const ClipVertex& v, uint32_t width, uint32_t height,
                         const std::array<int32_t, 3>& weights);

// Clips one triangle (spec §3) and snaps the resulting fan to a `width` x `height`
// viewport (spec §2). Appends 0, 1 or up to 5 triangles (3 vertices each) to `out`; none
// when a vertex of the clipped polygon is outside the snapping range (spec §3).
void clipAndSnapTriangle(const std::array<ClipVertex, 3>& tri, uint32_t width, uint32_t height,
                         std::vector<std::array<SnappedVertex, 3>>& out);

struct Edge {
  int64_t a = 0, b = 0, c = 0;  // E(X, Y) = a X + b Y + c (spec §4)
  int64_t bias = 0;             // 0 for top-left edges, 1 otherwise
  int64_t eval(int64_t x, int64_t y) const { return a * x + b * y + c - bias; }
};

struct DepthPlane {
  float z00 = 0, dzdx = 0, dzdy = 0;  // z = (z00 + dzdx*fx) + dzdy*fy (spec §5)
};

struct AttributePlane {
  uint32_t c = 0, gx = 0, gy = 0;  // v = c + gx*fx + gy*fy mod 2^32, 8.16 fixed (spec §5)
};

// A triangle ready to draw: edges with the fill rule folded in, pixel bounding box
// (clipped to the viewport; empty if minX >= maxX or minY >= maxY), depth plane.
struct SetupTriangle {
  std::array<SnappedVertex, 3> v;  // counter-clockwise in the det > 0 sense of spec §4
  std::array<Edge, 3> edges;
  int64_t det = 0;
  int32_t minX = 0, minY = 0, maxX = 0, maxY = 0;  // pixels, [min, max)
  DepthPlane depth;
  int32_t originX() const { return minX; }
  int32_t originY() const { return minY; }
};

// True when the snapped triangle has det > 0 as it comes (before setupTriangle orders its
// corners). Window y points down, so for a mesh wound counter-clockwise seen from outside
// these are the triangles facing away from the eye (the light, for a shadow map). Clipping
// keeps a triangle's winding, so it holds for each triangle of a clipped fan too.
bool facesAwayOnMap(const std::array<SnappedVertex, 3>& v);

// False when the triangle is degenerate (det = 0) or covers no pixel centre of the
// viewport's bounding box.
bool setupTriangle(const std::array<SnappedVertex, 3>& v, uint32_t width, uint32_t height,
                   SetupTriangle& out);

// The attribute plane of one channel (spec §5): `corners` are the channel's values in 8.8
// fixed point (at most 255 * 256) at the corners of the original, unclipped triangle; each
// snapped vertex weighs them by its 16-bit weights.
AttributePlane attributePlaneFine(const SetupTriangle& t, const std::array<uint16_t, 3>& corners);

// The same for 8-bit corner values (colours, whole-level S): their 8.8 values c * 256.
inline AttributePlane attributePlane(const SetupTriangle& t,
                                     const std::array<uint8_t, 3>& corners) {
  return attributePlaneFine(
      t, {static_cast<uint16_t>(corners[0] << 8), static_cast<uint16_t>(corners[1] << 8),
          static_cast<uint16_t>(corners[2] << 8)});
}

// Covered run of row `y`, clipped to [x0, x1): returns false if empty (spec §4).
bool rowSpan(const SetupTriangle& t, int32_t y, int32_t x0, int32_t x1, int32_t& xa, int32_t& xb);

// The runs of rowSpan() for consecutive rows, stepped exactly with integer
// quotient/remainder pairs instead of three divisions per row (spec §4: same runs).
//
// For an edge with a = 256 A > 0 the run starts at ceil(N / a), N = -K(y); with
// N = q a - r, 0 <= r < a, and the per-row step d = -256 B = dq a + dr, 0 <= dr < a:
// N + d = (q + dq) a + (dr - r) with -a < dr - r < a, so the next quotient is q + dq + 1
// when dr > r (remainder r + a - dr) and q + dq otherwise (remainder r - dr). Edges with
// a < 0 bound the run's end by floor(K / |a|) and step the same way with the signs flipped.
class RowWalker {
 public:
  RowWalker(const SetupTriangle& t, int32_t y);
  // The run of the current row clipped to [x0, x1); false if empty.
  bool span(int32_t x0, int32_t x1, int32_t& xa, int32_t& xb) const {
    if (empty_) return false;
    int64_t lo = std::max(x0, minX_), hi = std::min(x1, maxX_);
    for (int i = 0; i < count_; ++i) {
      const Bound& b = bounds_[i];
      if (b.lower) {
        lo = std::max(lo, b.q);
      } else {
        hi = std::min(hi, b.q + 1);
      }
    }
    if (lo >= hi) return false;
    xa = static_cast<int32_t>(lo);
    xb = static_cast<int32_t>(hi);
    return true;
  }
  void nextRow() {
    for (int i = 0; i < count_; ++i) {
      Bound& b = bounds_[i];
      if (b.lower) {
        const bool carry = b.dr > b.r;
        b.q += b.dq + (carry ? 1 : 0);
        b.r = carry ? b.r + b.divisor - b.dr : b.r - b.dr;
      } else {
        b.r += b.dr;
        const bool carry = b.r >= b.divisor;
        b.q += b.dq + (carry ? 1 : 0);
        b.r -= carry ? b.divisor : 0;
      }
    }
    empty_ = false;
    for (int i = 0; i < flatCount_; ++i) {
      flatK_[i] += flatStep_[i];
      empty_ = empty_ || flatK_[i] < 0;
    }
  }

 private:
  struct Bound {
    int64_t q, r, dq, dr, divisor;
    bool lower;  // a > 0: x >= q; a < 0: x <= q
  };
  std::array<Bound, 3> bounds_;
  int count_ = 0;
  bool empty_ = false;              // an edge with A = 0 excludes the current row
  std::array<int64_t, 3> flatK_{};  // K of edges with A = 0, and its per-row step
  std::array<int64_t, 3> flatStep_{};
  int flatCount_ = 0;
  int32_t minX_, maxX_;
};

// Calls fn(y, xa, xb) for every covered run of `t` in rows [y0, y1) and columns [x0, x1);
// `full` (a trivially accepted tile) means every pixel there is covered.
template <class Fn>
void forEachRun(const SetupTriangle& t, int32_t x0, int32_t y0, int32_t x1, int32_t y1, bool full,
                Fn&& fn) {
  const int32_t rowBegin = std::max(y0, t.minY), rowEnd = std::min(y1, t.maxY);
  if (full) {
    for (int32_t y = rowBegin; y < rowEnd; ++y) fn(y, x0, x1);
    return;
  }
  RowWalker walker(t, rowBegin);
  for (int32_t y = rowBegin; y < rowEnd; ++y, walker.nextRow()) {
    int32_t xa, xb;
    if (walker.span(x0, x1, xa, xb)) fn(y, xa, xb);
  }
}

// Tile classification against the three edges (spec §4): trivial reject, trivial accept,
// or partial. Tile covers pixels [x0, x1) x [y0, y1).
enum class TileCoverage : uint8_t { kNone, kPartial, kFull };
TileCoverage classifyTile(const SetupTriangle& t, int32_t x0, int32_t y0, int32_t x1, int32_t y1);

// Pixel-exact coverage of one already-snapped triangle in a width x height image, row 0 at
// the top: 1 where covered. For the coverage tests and the Mesa comparison.
std::vector<uint8_t> coverageMask(const std::array<SnappedVertex, 3>& v, uint32_t width,
                                  uint32_t height);

}  // namespace penumbra::raster
