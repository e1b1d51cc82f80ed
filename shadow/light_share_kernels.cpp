#include "shadow/light_share_kernels.h"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "shadow/light_share_kernels.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "core/colour.h"
#include "shadow/intensity_transfer.h"

// Each lane runs one element's chain with the reference's operations (Add in row order;
// Div, the clamp, Mul then Add for the share, never MulAdd: design §3); a run's tail goes
// through the reference itself.
HWY_BEFORE_NAMESPACE();
namespace penumbra::shadow::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

const hn::ScalableTag<double> d;

void SumRows(const double* const* rows, size_t count, size_t n, double* sum) {
  const size_t lanes = hn::Lanes(d);
  size_t j = 0;
  // Four vectors per sweep over the rows: each row's loads stream, the sums stay in registers.
  for (; j + 4 * lanes <= n; j += 4 * lanes) {
    auto s0 = hn::Zero(d), s1 = hn::Zero(d), s2 = hn::Zero(d), s3 = hn::Zero(d);
    for (size_t i = 0; i < count; ++i) {
      const double* row = rows[i] + j;
      s0 = hn::Add(s0, hn::LoadU(d, row));
      s1 = hn::Add(s1, hn::LoadU(d, row + lanes));
      s2 = hn::Add(s2, hn::LoadU(d, row + 2 * lanes));
      s3 = hn::Add(s3, hn::LoadU(d, row + 3 * lanes));
    }
    hn::StoreU(s0, d, sum + j);
    hn::StoreU(s1, d, sum + j + lanes);
    hn::StoreU(s2, d, sum + j + 2 * lanes);
    hn::StoreU(s3, d, sum + j + 3 * lanes);
  }
  for (; j + lanes <= n; j += lanes) {
    auto s = hn::Zero(d);
    for (size_t i = 0; i < count; ++i) s = hn::Add(s, hn::LoadU(d, rows[i] + j));
    hn::StoreU(s, d, sum + j);
  }
  for (; j < n; ++j) {
    double s = 0.0;
    for (size_t i = 0; i < count; ++i) s += rows[i][j];
    sum[j] = s;
  }
}

void Shares(const double* part, const double* whole, size_t n, uint16_t* out) {
  const hn::Rebind<int32_t, decltype(d)> di;
  const hn::Rebind<uint16_t, decltype(d)> du;
  const size_t lanes = hn::Lanes(d);
  const auto zero = hn::Zero(d);
  const auto one = hn::Set(d, 1.0);
  const auto scale = hn::Set(d, double(core::kMaxFineLevel));
  const auto half = hn::Set(d, 0.5);
  size_t j = 0;
  for (; j + lanes <= n; j += lanes) {
    const auto p = hn::LoadU(d, part + j);
    const auto w = hn::LoadU(d, whole + j);
    const auto q = hn::Div(p, w);
    // lightShare's clamp (1 < q ? 1 : q) and its unlit and NaN cases as 0; the lanes left
    // lie in [0.5, 65280.5], where the truncating conversions are exact.
    const auto x = hn::Add(hn::Mul(hn::IfThenElse(hn::Lt(one, q), one, q), scale), half);
    const auto lit = hn::And(hn::And(hn::Gt(w, zero), hn::Gt(p, zero)), hn::Eq(q, q));
    hn::StoreU(hn::DemoteTo(du, hn::DemoteTo(di, hn::IfThenElseZero(lit, x))), du, out + j);
  }
  for (; j < n; ++j) out[j] = lightShare(part[j], whole[j]);
}

const LightShareKernels* Kernels() {
  static const LightShareKernels kernels{&SumRows, &Shares};
  return &kernels;
}

}  // namespace penumbra::shadow::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/target_table.h"

namespace penumbra::shadow {
namespace {

// The references the targets must match, in the order light_share_kernels.h states.
void sumRowsScalar(const double* const* rows, size_t count, size_t n, double* sum) {
  for (size_t j = 0; j < n; ++j) {
    double s = 0.0;
    for (size_t i = 0; i < count; ++i) s += rows[i][j];
    sum[j] = s;
  }
}

void sharesScalar(const double* part, const double* whole, size_t n, uint16_t* out) {
  for (size_t j = 0; j < n; ++j) out[j] = lightShare(part[j], whole[j]);
}

}  // namespace

const LightShareKernels& lightShareKernelsFor(simd::Isa isa) {
  static const LightShareKernels scalar{&sumRowsScalar, &sharesScalar};
  if (isa == simd::Isa::kScalar) return scalar;
  return *PENUMBRA_TARGET_TABLE_LOOKUP(Kernels, isa);
}

}  // namespace penumbra::shadow
#endif  // HWY_ONCE
