#include "simd/u8_ops.h"

#include <cstdlib>

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "simd/u8_ops.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

#include "simd/u8_ops-inl.h"

HWY_BEFORE_NAMESPACE();
namespace penumbra::simd::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Each array kernel runs on u16 lanes: a vector's worth of bytes is promoted, combined and
// demoted; the tail goes through the scalar definition, which is the same function.
const hn::ScalableTag<uint16_t> d16;
const hn::RebindToSigned<decltype(d16)> di16;
const hn::Rebind<uint8_t, decltype(d16)> d8;

// Highway 1.0.3 demotes only signed 16-bit lanes to u8; results here are <= 255, so the
// signed view of the same bits is the same value.
template <class V>
HWY_INLINE auto demoteU8(V v) {
  return hn::DemoteTo(d8, hn::BitCast(di16, v));
}

template <class Op, class ScalarOp>
void forEachU16(const uint8_t* a, const uint8_t* b, uint8_t* out, size_t n, Op op,
                ScalarOp scalarOp) {
  const size_t lanes = hn::Lanes(d16);
  size_t i = 0;
  for (; i + lanes <= n; i += lanes) {
    const auto va = hn::PromoteTo(d16, hn::LoadU(d8, a + i));
    const auto vb = hn::PromoteTo(d16, hn::LoadU(d8, b + i));
    hn::StoreU(demoteU8(op(va, vb)), d8, out + i);
  }
  for (; i < n; ++i) out[i] = scalarOp(a[i], b[i]);
}

void ProductArray(const uint8_t* a, const uint8_t* b, uint8_t* out, size_t n) {
  forEachU16(
      a, b, out, n, [](auto va, auto vb) { return ProductU8(d16, va, vb); }, productU8);
}

void SubtractSaturateArray(const uint8_t* a, const uint8_t* b, uint8_t* out, size_t n) {
  forEachU16(
      a, b, out, n, [](auto va, auto vb) { return hn::SaturatedSub(va, vb); }, subtractSaturateU8);
}

void SubtractMaskedArray(uint8_t* dst, const uint8_t* s, const uint8_t* m, size_t n) {
  const size_t lanes = hn::Lanes(d16);
  size_t i = 0;
  for (; i + lanes <= n; i += lanes) {
    const auto vd = hn::PromoteTo(d16, hn::LoadU(d8, dst + i));
    const auto vs = hn::PromoteTo(d16, hn::LoadU(d8, s + i));
    const auto vm = hn::PromoteTo(d16, hn::LoadU(d8, m + i));
    hn::StoreU(demoteU8(hn::SaturatedSub(vd, ProductU8(d16, vs, vm))), d8, dst + i);
  }
  for (; i < n; ++i) dst[i] = subtractMaskedU8(dst[i], s[i], m[i]);
}

const U8Ops* Table() {
  static const U8Ops ops{&ProductArray, &SubtractSaturateArray, &SubtractMaskedArray};
  return &ops;
}

}  // namespace penumbra::simd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include "simd/target_table.h"

namespace penumbra::simd {
namespace {

void productScalar(const uint8_t* a, const uint8_t* b, uint8_t* out, size_t n) {
  for (size_t i = 0; i < n; ++i) out[i] = productU8(a[i], b[i]);
}
void subtractSaturateScalar(const uint8_t* a, const uint8_t* b, uint8_t* out, size_t n) {
  for (size_t i = 0; i < n; ++i) out[i] = subtractSaturateU8(a[i], b[i]);
}
void subtractMaskedScalar(uint8_t* dst, const uint8_t* s, const uint8_t* m, size_t n) {
  for (size_t i = 0; i < n; ++i) dst[i] = subtractMaskedU8(dst[i], s[i], m[i]);
}
const U8Ops kScalarOps{&productScalar, &subtractSaturateScalar, &subtractMaskedScalar};

}  // namespace

const U8Ops& u8OpsFor(Isa isa) {
  if (isa == Isa::kScalar) return kScalarOps;
  return *PENUMBRA_TARGET_TABLE_LOOKUP(Table, isa);
}

}  // namespace penumbra::simd
#endif  // HWY_ONCE
