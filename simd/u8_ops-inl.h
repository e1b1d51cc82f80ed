// Per-target vector forms of simd/u8_ops.h, for kernels compiled with foreach_target.h.
// Re-included once per target: the guard toggles with HWY_TARGET_TOGGLE (Highway idiom).
#if defined(PENUMBRA_SIMD_U8_OPS_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef PENUMBRA_SIMD_U8_OPS_INL_H_
#undef PENUMBRA_SIMD_U8_OPS_INL_H_
#else
#define PENUMBRA_SIMD_U8_OPS_INL_H_
#endif

#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace penumbra::simd::HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// round(a * b / 255) on integer lanes holding values in [0, 255] (u16, u32 or i32).
// t = a*b + 128 <= 65153 and t + (t >> 8) <= 65407 fit in 16 bits, so u16 lanes do not
// wrap. Equal to productU8() on all 65,536 pairs (Blinn's form; tests check every pair).
template <class D, class V>
HWY_INLINE V ProductU8(D d, V a, V b) {
  const V t = hn::Add(hn::Mul(a, b), hn::Set(d, 128));
  return hn::ShiftRight<8>(hn::Add(t, hn::ShiftRight<8>(t)));
}

// fineAmount() on u32 lanes holding S <= 65280 and W <= 65536.
template <class D, class V>
HWY_INLINE V FineAmount(D d, V s, V w) {
  return hn::ShiftRight<16>(hn::Add(hn::Mul(s, w), hn::Set(d, 32768u)));
}

// fixed8_8Levels() on int32 / u32 lanes holding sums below 2^31 - 128.
template <class D, class V>
HWY_INLINE V Fixed8_8Levels(D d, V sum) {
  return hn::ShiftRight<8>(hn::Add(sum, hn::Set(d, 128)));
}

// max(a - b, 0) on signed integer lanes holding values in [0, 255].
template <class D, class V>
HWY_INLINE V SubtractSaturate(D d, V a, V b) {
  return hn::Max(hn::Sub(a, b), hn::Zero(d));
}

}  // namespace penumbra::simd::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#endif  // include guard
