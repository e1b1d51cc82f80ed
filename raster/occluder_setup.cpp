// SIMD targets of raster/occluder_setup.h, and the scalar reference, which is the per-vertex
// and per-triangle functions of raster/triangle_setup.h themselves.
// raster/occluder_setup_test.cpp compares every target with it field by field.
#include "raster/occluder_setup.h"

#include <algorithm>
#include <array>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "raster/occluder_setup.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace penumbra::raster::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Spec §2–3 per lane, as transformPoint, insideClipVolume and snap() compute them.
bool SnapInside(const core::Mat4& m, const core::Vec3* points, size_t count, uint32_t size,
                int32_t* x, int32_t* y, float* z) {
  const hn::ScalableTag<float> df;
  const hn::RebindToSigned<decltype(df)> di;
  const size_t lanes = hn::Lanes(df);
  static_assert(hn::MaxLanes(decltype(df)()) <= kOccluderBatch, "batch arrays too small");
  const auto& a = m.m;
  auto row = [&](int r, auto px, auto py, auto pz) {
    return hn::Add(
        hn::Add(hn::Add(hn::Mul(hn::Set(df, a[4 * r]), px), hn::Mul(hn::Set(df, a[4 * r + 1]), py)),
                hn::Mul(hn::Set(df, a[4 * r + 2]), pz)),
        hn::Set(df, a[4 * r + 3]));
  };
  const auto zero = hn::Zero(df), guard = hn::Set(df, kGuardBand);
  const auto sx = hn::Set(df, 128.0f * static_cast<float>(size));  // 256 * hw, exact
  const auto half = hn::Set(df, 0.5f), one = hn::Set(df, 1.0f);
  HWY_ALIGN float px[kOccluderBatch], py[kOccluderBatch], pz[kOccluderBatch];
  for (size_t first = 0; first < count; first += lanes) {
    const size_t n = std::min(lanes, count - first);
    for (size_t k = 0; k < lanes; ++k) {  // tail lanes repeat the last point
      const core::Vec3& p = points[first + std::min(k, n - 1)];
      px[k] = p.x;
      py[k] = p.y;
      pz[k] = p.z;
    }
    const auto vx = hn::Load(df, px), vy = hn::Load(df, py), vz = hn::Load(df, pz);
    const auto cx = row(0, vx, vy, vz), cy = row(1, vx, vy, vz);
    const auto cz = row(2, vx, vy, vz), cw = row(3, vx, vy, vz);
    const auto gw = hn::Mul(guard, cw);
    // insideClipVolume's seven planes; NaN fails every test, as there.
    const auto inside = hn::And(
        hn::And(
            hn::And(hn::Ge(hn::Sub(cw, hn::Set(df, 1e-5f)), zero), hn::Ge(hn::Add(cz, cw), zero)),
            hn::And(hn::Ge(hn::Sub(cw, cz), zero), hn::Ge(hn::Sub(gw, cx), zero))),
        hn::And(hn::Ge(hn::Add(gw, cx), zero),
                hn::And(hn::Ge(hn::Sub(gw, cy), zero), hn::Ge(hn::Add(gw, cy), zero))));
    if (!hn::AllTrue(df, inside)) return false;
    // snap(): nearbyint (ties to even in the default rounding mode) is Round.
    const auto wx = hn::Round(hn::Add(hn::Mul(hn::Div(cx, cw), sx), sx));
    const auto wy = hn::Round(hn::Add(hn::Mul(hn::Neg(hn::Div(cy, cw)), sx), sx));
    const auto wz = hn::Add(hn::Mul(hn::Div(cz, cw), half), half);
    // std::clamp(v, 0, 1): v < 0 ? 0 : (1 < v ? 1 : v).
    const auto clamped =
        hn::IfThenElse(hn::Lt(wz, zero), zero, hn::IfThenElse(hn::Lt(one, wz), one, wz));
    hn::StoreU(hn::ConvertTo(di, wx), di, x + first);
    hn::StoreU(hn::ConvertTo(di, wy), di, y + first);
    hn::StoreU(clamped, df, z + first);
  }
  return true;
}

// setupTriangle per lane in binary64: the snapped coordinates are integers below 2^22 in
// magnitude (a vertex inside the guard band of a map at most 4096 texels wide), so their
// differences, the products of two differences (< 2^46) and the edge constants
// x_a y_b - y_a x_b (< 2^45) are exact in binary64 — the int64 values of setupTriangle. The
// bounding box divides exact integers by 256, also exact. The depth plane is binary64
// there too, operation for operation.
size_t SetupTriangles(const int32_t* x, const int32_t* y, const float* z, const uint32_t* indices,
                      size_t count, uint32_t size, bool cullBackFaces, SetupTriangle* out) {
  const hn::ScalableTag<double> dd;
  using VD = hn::Vec<decltype(dd)>;
  const size_t lanes = hn::Lanes(dd);
  static_assert(hn::MaxLanes(decltype(dd)()) <= kOccluderBatch, "batch arrays too small");
  HWY_ALIGN double cx[3][kOccluderBatch], cy[3][kOccluderBatch], cz[3][kOccluderBatch];
  HWY_ALIGN double res[19][kOccluderBatch];
  const VD zero = hn::Zero(dd), one = hn::Set(dd, 1.0);
  const VD k128 = hn::Set(dd, 128.0), k255 = hn::Set(dd, 255.0), k256 = hn::Set(dd, 256.0);
  const VD inv256 = hn::Set(dd, 1.0 / 256.0), limit = hn::Set(dd, static_cast<double>(size));
  size_t written = 0;
  for (size_t first = 0; first < count; first += lanes) {
    const size_t n = std::min(lanes, count - first);
    for (size_t k = 0; k < lanes; ++k) {  // tail lanes repeat the last triangle
      const uint32_t* tri = indices + 3 * (first + std::min(k, n - 1));
      for (int c = 0; c < 3; ++c) {
        cx[c][k] = x[tri[c]];
        cy[c][k] = y[tri[c]];
        cz[c][k] = z[tri[c]];
      }
    }
    const VD x0 = hn::Load(dd, cx[0]), x1 = hn::Load(dd, cx[1]), x2 = hn::Load(dd, cx[2]);
    const VD y0 = hn::Load(dd, cy[0]), y1 = hn::Load(dd, cy[1]), y2 = hn::Load(dd, cy[2]);
    // Bounding box of pixel centres: floor((lo - 128 + 255) / 256) and
    // floor((hi - 128) / 256) + 1, clamped to the viewport (setupTriangle's shifts).
    auto floorDiv256 = [&](VD v) { return hn::Floor(hn::Mul(v, inv256)); };
    const VD minX =
        hn::Max(zero, floorDiv256(hn::Add(hn::Sub(hn::Min(x0, hn::Min(x1, x2)), k128), k255)));
    const VD maxX =
        hn::Min(limit, hn::Add(floorDiv256(hn::Sub(hn::Max(x0, hn::Max(x1, x2)), k128)), one));
    const VD minY =
        hn::Max(zero, floorDiv256(hn::Add(hn::Sub(hn::Min(y0, hn::Min(y1, y2)), k128), k255)));
    const VD maxY =
        hn::Min(limit, hn::Add(floorDiv256(hn::Sub(hn::Max(y0, hn::Max(y1, y2)), k128)), one));
    const VD det0 = hn::Sub(hn::Mul(hn::Sub(x1, x0), hn::Sub(y2, y0)),
                            hn::Mul(hn::Sub(x2, x0), hn::Sub(y1, y0)));
    // det0 < 0 faces the light (facesAwayOnMap is det0 > 0); det0 = 0 is never drawn.
    const auto drawn = cullBackFaces ? hn::Lt(det0, zero) : hn::Ne(det0, zero);
    const auto accepted = hn::And(hn::And(hn::Lt(minX, maxX), hn::Lt(minY, maxY)), drawn);
    if (hn::AllFalse(dd, accepted)) continue;
    // Counter-clockwise order: v1 and v2 swap where det < 0.
    const auto flip = hn::Lt(det0, zero);
    const VD z0 = hn::Load(dd, cz[0]);
    const VD sx1 = hn::IfThenElse(flip, x2, x1), sx2 = hn::IfThenElse(flip, x1, x2);
    const VD sy1 = hn::IfThenElse(flip, y2, y1), sy2 = hn::IfThenElse(flip, y1, y2);
    const VD rz1 = hn::Load(dd, cz[1]), rz2 = hn::Load(dd, cz[2]);
    const VD sz1 = hn::IfThenElse(flip, rz2, rz1), sz2 = hn::IfThenElse(flip, rz1, rz2);
    const VD det = hn::Abs(det0);
    // Edge i from v[i] to v[i + 1]: a = y_i - y_j, b = x_j - x_i, c = x_i y_j - y_i x_j.
    const std::array<VD, 3> vx = {x0, sx1, sx2}, vy = {y0, sy1, sy2};
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3;
      const VD ea = hn::Sub(vy[i], vy[j]), eb = hn::Sub(vx[j], vx[i]);
      const VD ec = hn::Sub(hn::Mul(vx[i], vy[j]), hn::Mul(vy[i], vx[j]));
      hn::Store(ea, dd, res[3 * i]);
      hn::Store(eb, dd, res[3 * i + 1]);
      hn::Store(ec, dd, res[3 * i + 2]);
    }
    // Depth plane (spec §5), as setupTriangle computes it.
    const VD dx1 = hn::Sub(sx1, x0), dy1 = hn::Sub(sy1, y0);
    const VD dx2 = hn::Sub(sx2, x0), dy2 = hn::Sub(sy2, y0);
    const VD dz1 = hn::Sub(sz1, z0), dz2 = hn::Sub(sz2, z0);
    const VD gX = hn::Div(hn::Sub(hn::Mul(dz1, dy2), hn::Mul(dz2, dy1)), det);
    const VD gY = hn::Div(hn::Sub(hn::Mul(dz2, dx1), hn::Mul(dz1, dx2)), det);
    const VD ox = hn::Sub(hn::Add(hn::Mul(k256, minX), k128), x0);
    const VD oy = hn::Sub(hn::Add(hn::Mul(k256, minY), k128), y0);
    const VD zc = hn::Add(hn::Add(z0, hn::Mul(gX, ox)), hn::Mul(gY, oy));
    hn::Store(det, dd, res[9]);
    hn::Store(minX, dd, res[10]);
    hn::Store(maxX, dd, res[11]);
    hn::Store(minY, dd, res[12]);
    hn::Store(maxY, dd, res[13]);
    hn::Store(zc, dd, res[14]);
    hn::Store(hn::Mul(gX, k256), dd, res[15]);
    hn::Store(hn::Mul(gY, k256), dd, res[16]);
    hn::Store(hn::IfThenElseZero(flip, one), dd, res[17]);
    hn::Store(hn::IfThenElseZero(accepted, one), dd, res[18]);
    for (size_t k = 0; k < n; ++k) {
      if (res[18][k] == 0.0) continue;
      SetupTriangle& t = out[written++];
      const uint32_t* tri = indices + 3 * (first + k);
      const bool swap = res[17][k] != 0.0;
      const uint32_t corner[3] = {tri[0], swap ? tri[2] : tri[1], swap ? tri[1] : tri[2]};
      for (int c = 0; c < 3; ++c) {
        t.v[c] = {x[corner[c]], y[corner[c]], z[corner[c]], {65536, 0, 0}};
      }
      for (int i = 0; i < 3; ++i) {
        Edge& e = t.edges[i];
        e.a = static_cast<int64_t>(res[3 * i][k]);
        e.b = static_cast<int64_t>(res[3 * i + 1][k]);
        e.c = static_cast<int64_t>(res[3 * i + 2][k]);
        e.bias = (e.a > 0 || (e.a == 0 && e.b > 0)) ? 0 : 1;
      }
      t.det = static_cast<int64_t>(res[9][k]);
      t.minX = static_cast<int32_t>(res[10][k]);
      t.maxX = static_cast<int32_t>(res[11][k]);
      t.minY = static_cast<int32_t>(res[12][k]);
      t.maxY = static_cast<int32_t>(res[13][k]);
      t.depth = {static_cast<float>(res[14][k]), static_cast<float>(res[15][k]),
                 static_cast<float>(res[16][k])};
    }
  }
  return written;
}

const OccluderKernels* OccluderTable() {
  static const OccluderKernels kernels{&SnapInside, &SetupTriangles};
  return &kernels;
}

}  // namespace penumbra::raster::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/target_table.h"

namespace penumbra::raster {
namespace {

bool snapInsideScalar(const core::Mat4& m, const core::Vec3* points, size_t count, uint32_t size,
                      int32_t* x, int32_t* y, float* z) {
  for (size_t i = 0; i < count; ++i) {
    const ClipVertex c = transformPoint(m, points[i]);
    if (!insideClipVolume(c)) return false;
    const SnappedVertex s = snapVertex(c, size, size, {65536, 0, 0});
    x[i] = s.x;
    y[i] = s.y;
    z[i] = s.z;
  }
  return true;
}

size_t setupTrianglesScalar(const int32_t* x, const int32_t* y, const float* z,
                            const uint32_t* indices, size_t count, uint32_t size,
                            bool cullBackFaces, SetupTriangle* out) {
  size_t written = 0;
  for (size_t k = 0; k < count; ++k) {
    std::array<SnappedVertex, 3> v;
    for (int c = 0; c < 3; ++c) {
      const uint32_t i = indices[3 * k + c];
      v[c] = {x[i], y[i], z[i], {65536, 0, 0}};
    }
    if (cullBackFaces && facesAwayOnMap(v)) continue;
    if (setupTriangle(v, size, size, out[written])) ++written;
  }
  return written;
}

const OccluderKernels kScalar{&snapInsideScalar, &setupTrianglesScalar};

}  // namespace

const OccluderKernels& occluderKernelsFor(simd::Isa isa) {
  if (isa == simd::Isa::kScalar) return kScalar;
  return *PENUMBRA_TARGET_TABLE_LOOKUP(OccluderTable, isa);
}

}  // namespace penumbra::raster
#endif  // HWY_ONCE
