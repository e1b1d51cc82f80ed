#include "raster/triangle_setup.h"

#include <algorithm>
#include <cmath>

namespace penumbra::raster {
namespace {

// GCC and Clang provide 128-bit integers on x86-64 and aarch64 (spec §1).
__extension__ typedef __int128 Int128;

template <class T>
T floorDiv(T n, T d) {  // d > 0
  const T q = n / d;
  return (n % d != 0 && n < 0) ? q - 1 : q;
}
template <class T>
T ceilDiv(T n, T d) {  // d > 0
  const T q = n / d;
  return (n % d != 0 && n > 0) ? q + 1 : q;
}
// Round half up (spec §1).
template <class T>
T roundDiv(T n, T d) {
  return floorDiv(T(2) * n + d, T(2) * d);
}

// Signed distance to clip plane `p` (spec §3), evaluated exactly as written there.
float planeDistance(int p, const ClipVertex& v) {
  switch (p) {
    case 0:
      return v.w - 1e-5f;
    case 1:
      return v.z + v.w;
    case 2:
      return v.w - v.z;
    case 3:
      return kGuardBand * v.w - v.x;
    case 4:
      return kGuardBand * v.w + v.x;
    case 5:
      return kGuardBand * v.w - v.y;
    default:
      return kGuardBand * v.w + v.y;
  }
}
constexpr int kPlaneCount = 7;

// The clipped polygon's capacity. In exact arithmetic a convex polygon gains at most one
// vertex per plane (3 + 7 = 10), but the inside tests below are made on rounded intersection
// points, so the polygon a plane sees need not be convex: its vertices can change sides many
// times (the fuzzer found a triangle that overflowed 10). A bound that holds for any sequence
// of inside/outside answers: a plane keeps the I inside vertices of n and adds one per change
// of side; changes come in pairs around each maximal run of inside vertices, and there are at
// most min(I, n - I) runs, so m <= I + 2 min(I, n - I) <= 3n/2. From n = 3 over seven planes:
// 4, 6, 9, 13, 19, 28, 42.
constexpr int maxClippedVertices() {
  int n = 3;
  for (int p = 0; p < kPlaneCount; ++p) n = n * 3 / 2;
  return n;
}
constexpr int kMaxClippedVertices = maxClippedVertices();
static_assert(kMaxClippedVertices == 42);

// The intersection is always computed from the inside vertex towards the outside one, so
// an edge shared by two triangles yields the same vertex from both (watertight clipping).
ClippedVertex intersect(const ClippedVertex& in, float dIn, const ClippedVertex& out, float dOut) {
  const float t = dIn / (dIn - dOut);
  ClippedVertex r;
  r.clip.x = in.clip.x + t * (out.clip.x - in.clip.x);
  r.clip.y = in.clip.y + t * (out.clip.y - in.clip.y);
  r.clip.z = in.clip.z + t * (out.clip.z - in.clip.z);
  r.clip.w = in.clip.w + t * (out.clip.w - in.clip.w);
  for (int k = 0; k < 3; ++k) r.bary[k] = in.bary[k] + t * (out.bary[k] - in.bary[k]);
  return r;
}

// Spec §3, "Snapping range": the window coordinates, depth and weights of a vertex are
// checked as binary32 values before any of them is converted to an integer, so that a
// vertex binary32 could not keep inside the guard band (overflow to Inf, 0 * Inf = NaN in
// the intersection, a w cancelled to ~0 on the w plane) never reaches the integer setup.
// False: the vertex is outside the range the integer arithmetic of §4–5 is proved for.
bool snap(const ClippedVertex& v, uint32_t width, uint32_t height, SnappedVertex& s) {
  const float sx = 128.0f * static_cast<float>(width);   // 256 * hw, exact
  const float sy = 128.0f * static_cast<float>(height);  // 256 * hh, exact
  const float xw = (v.clip.x / v.clip.w) * sx + sx;
  const float yw = -(v.clip.y / v.clip.w) * sy + sy;
  // Clipped vertices can land a rounding step outside [-w, w]; GL clamps window depth too.
  const float zw = std::clamp((v.clip.z / v.clip.w) * 0.5f + 0.5f, 0.0f, 1.0f);
  // Written so that NaN fails every test.
  const bool inRange = std::fabs(xw) <= kMaxSnappedCoordinate &&
                       std::fabs(yw) <= kMaxSnappedCoordinate && zw >= 0.0f && zw <= 1.0f &&
                       v.bary[1] >= kMinClippedWeight && v.bary[1] <= kMaxClippedWeight &&
                       v.bary[2] >= kMinClippedWeight && v.bary[2] <= kMaxClippedWeight;
  if (!inRange) return false;
  s.x = static_cast<int32_t>(std::nearbyint(xw));
  s.y = static_cast<int32_t>(std::nearbyint(yw));
  s.z = zw;
  s.w[1] = static_cast<int32_t>(std::nearbyint(v.bary[1] * 65536.0f));
  s.w[2] = static_cast<int32_t>(std::nearbyint(v.bary[2] * 65536.0f));
  s.w[0] = 65536 - s.w[1] - s.w[2];
  return true;
}

}  // namespace

bool insideClipVolume(const ClipVertex& v) {
  for (int p = 0; p < kPlaneCount; ++p) {
    if (!(planeDistance(p, v) >= 0.0f)) return false;
  }
  return true;
}

SnappedVertex snapVertex(const ClipVertex& v, uint32_t width, uint32_t height,
                         const std::array<int32_t, 3>& weights) {
  ClippedVertex c;
  c.clip = v;
  c.bary = {0.0f, 0.0f, 0.0f};
  SnappedVertex s;
  // A vertex inside the clip volume is inside the guard band: snap() cannot refuse it.
  snap(c, width, height, s);
  s.w = weights;
  return s;
}

ClipVertex transformPoint(const core::Mat4& m, const core::Vec3& p) {
  const auto& a = m.m;
  return {((a[0] * p.x + a[1] * p.y) + a[2] * p.z) + a[3],
          ((a[4] * p.x + a[5] * p.y) + a[6] * p.z) + a[7],
          ((a[8] * p.x + a[9] * p.y) + a[10] * p.z) + a[11],
          ((a[12] * p.x + a[13] * p.y) + a[14] * p.z) + a[15]};
}

void clipAndSnapTriangle(const std::array<ClipVertex, 3>& tri, uint32_t width, uint32_t height,
                         std::vector<std::array<SnappedVertex, 3>>& out) {
  // Trivial accept / reject (spec §3).
  bool allInside = true;
  for (int p = 0; p < kPlaneCount; ++p) {
    int outside = 0;
    for (const ClipVertex& v : tri) outside += planeDistance(p, v) >= 0.0f ? 0 : 1;
    if (outside == 3) return;
    allInside = allInside && outside == 0;
  }
  std::array<ClippedVertex, kMaxClippedVertices> poly, next;
  int n = 3;
  for (int k = 0; k < 3; ++k) {
    poly[k].clip = tri[k];
    poly[k].bary = {0.0f, 0.0f, 0.0f};
    poly[k].bary[k] = 1.0f;
  }
  if (!allInside) {
    for (int p = 0; p < kPlaneCount && n > 0; ++p) {
      int m = 0;
      for (int i = 0; i < n; ++i) {
        const ClippedVertex& a = poly[i];
        const ClippedVertex& b = poly[(i + 1) % n];
        const float da = planeDistance(p, a.clip);
        const float db = planeDistance(p, b.clip);
        const bool aIn = da >= 0.0f, bIn = db >= 0.0f;
        if (aIn) next[m++] = a;
        if (aIn && !bIn) next[m++] = intersect(a, da, b, db);
        if (!aIn && bIn) next[m++] = intersect(b, db, a, da);
      }
      poly = next;
      n = m;
    }
    if (n < 3) return;
  }
  std::array<SnappedVertex, kMaxClippedVertices> snapped;
  for (int i = 0; i < n; ++i) {
    if (!snap(poly[i], width, height, snapped[i])) return;  // spec §3: the whole polygon
  }
  for (int i = 1; i + 1 < n; ++i) out.push_back({snapped[0], snapped[i], snapped[i + 1]});
}

bool facesAwayOnMap(const std::array<SnappedVertex, 3>& v) {
  return int64_t{v[1].x - v[0].x} * (v[2].y - v[0].y) -
             int64_t{v[2].x - v[0].x} * (v[1].y - v[0].y) >
         0;
}

bool setupTriangle(const std::array<SnappedVertex, 3>& vin, uint32_t width, uint32_t height,
                   SetupTriangle& t) {
  // Shadow maps set up ~24 k triangles per frame, many covering no pixel centre: the
  // bounding box (which does not depend on the winding) is tested before anything else.
  const int32_t x0 = vin[0].x, x1 = vin[1].x, x2 = vin[2].x;
  const int32_t y0 = vin[0].y, y1 = vin[1].y, y2 = vin[2].y;
  const int64_t loX = std::min({x0, x1, x2}), hiX = std::max({x0, x1, x2});
  const int64_t loY = std::min({y0, y1, y2}), hiY = std::max({y0, y1, y2});
  // Pixel px is a candidate when its centre 256 px + 128 lies in [lo, hi]: px >=
  // ceil((lo - 128) / 256) and px <= floor((hi - 128) / 256). Arithmetic shifts are the
  // floor of a division by 256 for every int64 (g++ and Clang shift arithmetically).
  const int64_t minX = std::max<int64_t>(0, (loX - 128 + 255) >> 8);
  const int64_t maxX = std::min<int64_t>(width, ((hiX - 128) >> 8) + 1);
  const int64_t minY = std::max<int64_t>(0, (loY - 128 + 255) >> 8);
  const int64_t maxY = std::min<int64_t>(height, ((hiY - 128) >> 8) + 1);
  if (minX >= maxX || minY >= maxY) return false;
  int64_t det = int64_t{x1 - x0} * (y2 - y0) - int64_t{x2 - x0} * (y1 - y0);
  if (det == 0) return false;
  t.v = vin;
  if (det < 0) {
    std::swap(t.v[1], t.v[2]);
    det = -det;
  }
  t.det = det;
  t.minX = static_cast<int32_t>(minX);
  t.maxX = static_cast<int32_t>(maxX);
  t.minY = static_cast<int32_t>(minY);
  t.maxY = static_cast<int32_t>(maxY);
  for (int i = 0; i < 3; ++i) {
    const SnappedVertex& a = t.v[i];
    const SnappedVertex& b = t.v[(i + 1) % 3];
    Edge& e = t.edges[i];
    e.a = int64_t{a.y} - b.y;
    e.b = int64_t{b.x} - a.x;
    e.c = int64_t{a.x} * b.y - int64_t{a.y} * b.x;
    const bool topLeft = e.a > 0 || (e.a == 0 && e.b > 0);
    e.bias = topLeft ? 0 : 1;
  }

  // Depth plane (spec §5), binary64 then rounded once to binary32.
  const double dx1 = t.v[1].x - t.v[0].x, dy1 = t.v[1].y - t.v[0].y;
  const double dx2 = t.v[2].x - t.v[0].x, dy2 = t.v[2].y - t.v[0].y;
  const double z0 = t.v[0].z;
  const double dz1 = static_cast<double>(t.v[1].z) - z0, dz2 = static_cast<double>(t.v[2].z) - z0;
  const double detD = static_cast<double>(det);
  const double gX = (dz1 * dy2 - dz2 * dy1) / detD;
  const double gY = (dz2 * dx1 - dz1 * dx2) / detD;
  const double ox = 256.0 * t.minX + 128.0 - t.v[0].x;
  const double oy = 256.0 * t.minY + 128.0 - t.v[0].y;
  const double zc = z0 + gX * ox + gY * oy;
  t.depth.z00 = static_cast<float>(zc);
  t.depth.dzdx = static_cast<float>(gX * 256.0);
  t.depth.dzdy = static_cast<float>(gY * 256.0);
  return true;
}

AttributePlane attributePlaneFine(const SetupTriangle& t, const std::array<uint16_t, 3>& corners) {
  std::array<int64_t, 3> v;
  for (int i = 0; i < 3; ++i) {
    // 8.8 corners times 16-bit weights are 8.24; back to 8.16 rounding half up (floor of a
    // possibly negative sum: a clipped vertex's weights may round just below 0). For
    // corners c * 256 the sum is 256 * sum(w c) and this is sum(w c) exactly, the 8-bit
    // rule of spec §5.
    const int64_t weighted = int64_t{t.v[i].w[0]} * corners[0] + int64_t{t.v[i].w[1]} * corners[1] +
                             int64_t{t.v[i].w[2]} * corners[2];
    v[i] = (weighted + 128) >> 8;
  }
  // |dv| < 2^24 and coordinate differences < 2^23, so nX, nY < 2^48; the origin term
  // multiplies them by another < 2^23 and needs 128 bits.
  const int64_t dv1 = v[1] - v[0], dv2 = v[2] - v[0];
  const int64_t nX = dv1 * (t.v[2].y - t.v[0].y) - dv2 * (t.v[1].y - t.v[0].y);
  const int64_t nY = dv2 * (t.v[1].x - t.v[0].x) - dv1 * (t.v[2].x - t.v[0].x);
  const int64_t gx = roundDiv<int64_t>(256 * nX, t.det);
  const int64_t gy = roundDiv<int64_t>(256 * nY, t.det);
  const Int128 ox = int64_t{256} * t.minX + 128 - t.v[0].x;
  const Int128 oy = int64_t{256} * t.minY + 128 - t.v[0].y;
  // The 128-bit quotient (a library call, ~100 cycles) only when the numerator needs it:
  // for the usual small offsets it fits in 62 bits and the int64 quotient is the same.
  const Int128 n = nX * ox + nY * oy;
  constexpr int64_t kFits = int64_t{1} << 61;
  const int64_t q = n >= -kFits && n <= kFits
                        ? roundDiv<int64_t>(static_cast<int64_t>(n), t.det)
                        : static_cast<int64_t>(roundDiv<Int128>(n, Int128{t.det}));
  const int64_t c = v[0] + q;
  // Reduction modulo 2^32 is the arithmetic of spec §5.
  return {static_cast<uint32_t>(c), static_cast<uint32_t>(gx), static_cast<uint32_t>(gy)};
}

bool rowSpan(const SetupTriangle& t, int32_t y, int32_t x0, int32_t x1, int32_t& xa, int32_t& xb) {
  int64_t lo = std::max(x0, t.minX), hi = std::min(x1, t.maxX);
  const int64_t yc = int64_t{256} * y + 128;
  for (const Edge& e : t.edges) {
    const int64_t k = e.a * 128 + e.b * yc + e.c - e.bias;
    const int64_t a = e.a * 256;
    if (a > 0) {
      lo = std::max(lo, ceilDiv(-k, a));
    } else if (a < 0) {
      hi = std::min(hi, floorDiv(k, -a) + 1);
    } else if (k < 0) {
      return false;
    }
  }
  if (lo >= hi) return false;
  xa = static_cast<int32_t>(lo);
  xb = static_cast<int32_t>(hi);
  return true;
}

RowWalker::RowWalker(const SetupTriangle& t, int32_t y) : minX_(t.minX), maxX_(t.maxX) {
  const int64_t yc = int64_t{256} * y + 128;
  for (const Edge& e : t.edges) {
    const int64_t k = e.a * 128 + e.b * yc + e.c - e.bias;
    const int64_t a = e.a * 256;
    const int64_t step = e.b * 256;  // K(y + 1) - K(y)
    if (a == 0) {
      flatK_[flatCount_] = k;
      flatStep_[flatCount_++] = step;
      continue;
    }
    Bound& b = bounds_[count_++];
    b.lower = a > 0;
    b.divisor = b.lower ? a : -a;
    // Lower bound tracks N = -K = q a - r; upper bound tracks K = q |a| + r.
    const int64_t n = b.lower ? -k : k;
    const int64_t d = b.lower ? -step : step;
    b.dq = floorDiv(d, b.divisor);
    b.dr = d - b.dq * b.divisor;
    if (b.lower) {
      b.q = ceilDiv(n, b.divisor);
      b.r = b.q * b.divisor - n;
    } else {
      b.q = floorDiv(n, b.divisor);
      b.r = n - b.q * b.divisor;
    }
  }
  for (int i = 0; i < flatCount_; ++i) empty_ = empty_ || flatK_[i] < 0;
}

TileCoverage classifyTile(const SetupTriangle& t, int32_t x0, int32_t y0, int32_t x1, int32_t y1) {
  if (x1 <= t.minX || x0 >= t.maxX || y1 <= t.minY || y0 >= t.maxY) return TileCoverage::kNone;
  const int64_t cx[2] = {int64_t{256} * x0 + 128, int64_t{256} * (x1 - 1) + 128};
  const int64_t cy[2] = {int64_t{256} * y0 + 128, int64_t{256} * (y1 - 1) + 128};
  bool full = true;
  for (const Edge& e : t.edges) {
    int inside = 0;
    for (int64_t yy : cy) {
      for (int64_t xx : cx) inside += e.eval(xx, yy) >= 0 ? 1 : 0;
    }
    if (inside == 0) return TileCoverage::kNone;
    full = full && inside == 4;
  }
  return full ? TileCoverage::kFull : TileCoverage::kPartial;
}

std::vector<uint8_t> coverageMask(const std::array<SnappedVertex, 3>& v, uint32_t width,
                                  uint32_t height) {
  std::vector<uint8_t> mask(size_t{width} * height, 0);
  SetupTriangle t;
  if (!setupTriangle(v, width, height, t)) return mask;
  for (int32_t y = t.minY; y < t.maxY; ++y) {
    int32_t xa, xb;
    if (!rowSpan(t, y, 0, static_cast<int32_t>(width), xa, xb)) continue;
    std::fill(mask.begin() + size_t{width} * y + xa, mask.begin() + size_t{width} * y + xb, 1);
  }
  return mask;
}

}  // namespace penumbra::raster
