// Looking up one target's kernel table without touching Highway's global dispatch state,
// so two renderers in one process (or one test) can run different targets side by side.
//
// Usage, inside `#if HWY_ONCE` of a foreach_target.h translation unit that defines
// `const T* FN()` in every target namespace:
//     return *PENUMBRA_TARGET_TABLE_LOOKUP(FN, isa);
#pragma once

#include <cstdio>
#include <cstdlib>

#include <hwy/highway.h>

#include "simd/targets.h"

#if HWY_ARCH_X86 && (HWY_TARGETS & HWY_SSE4)
#define PENUMBRA_TT_SSE4(FN)         \
  case ::penumbra::simd::Isa::kSse4: \
    return N_SSE4::FN();
#else
#define PENUMBRA_TT_SSE4(FN)
#endif
#if HWY_ARCH_X86 && (HWY_TARGETS & HWY_AVX2)
#define PENUMBRA_TT_AVX2(FN)         \
  case ::penumbra::simd::Isa::kAvx2: \
    return N_AVX2::FN();
#else
#define PENUMBRA_TT_AVX2(FN)
#endif
#if HWY_ARCH_X86 && (HWY_TARGETS & HWY_AVX3)
#define PENUMBRA_TT_AVX3(FN)           \
  case ::penumbra::simd::Isa::kAvx512: \
    return N_AVX3::FN();
#else
#define PENUMBRA_TT_AVX3(FN)
#endif
#if HWY_ARCH_ARM_A64 && (HWY_TARGETS & HWY_NEON)
#define PENUMBRA_TT_NEON(FN)         \
  case ::penumbra::simd::Isa::kNeon: \
    return N_NEON::FN();
#else
#define PENUMBRA_TT_NEON(FN)
#endif

#define PENUMBRA_TARGET_TABLE_LOOKUP(FN, ISA)                                 \
  ([&]() {                                                                    \
    switch (ISA) {                                                            \
      PENUMBRA_TT_SSE4(FN)                                                    \
      PENUMBRA_TT_AVX2(FN)                                                    \
      PENUMBRA_TT_AVX3(FN)                                                    \
      PENUMBRA_TT_NEON(FN)                                                    \
      default:                                                                \
        std::fprintf(stderr, "penumbra: SIMD target %s is not compiled in\n", \
                     ::penumbra::simd::isaName(ISA));                         \
        std::abort();                                                         \
    }                                                                         \
  }())
