#include "simd/targets.h"

#include <hwy/highway.h>
#include <hwy/targets.h>

namespace penumbra::simd {

const char* isaName(Isa isa) {
  switch (isa) {
    case Isa::kScalar:
      return "scalar";
    case Isa::kSse4:
      return "sse4";
    case Isa::kAvx2:
      return "avx2";
    case Isa::kAvx512:
      return "avx512";
    case Isa::kNeon:
      return "neon";
  }
  return "unknown";
}

std::optional<Isa> parseIsa(std::string_view name) {
  for (Isa isa : {Isa::kScalar, Isa::kSse4, Isa::kAvx2, Isa::kAvx512, Isa::kNeon}) {
    if (name == isaName(isa)) return isa;
  }
  return std::nullopt;
}

int64_t highwayTarget(Isa isa) {
  switch (isa) {
    case Isa::kScalar:
      return 0;
#if HWY_ARCH_X86
    case Isa::kSse4:
      return HWY_SSE4;
    case Isa::kAvx2:
      return HWY_AVX2;
    case Isa::kAvx512:
      return HWY_AVX3;
#endif
#if HWY_ARCH_ARM_A64
    case Isa::kNeon:
      return HWY_NEON;
#endif
    default:
      return -1;
  }
}

std::vector<Isa> compiledIsas() {
  std::vector<Isa> out{Isa::kScalar};
  for (Isa isa : {Isa::kSse4, Isa::kAvx2, Isa::kAvx512, Isa::kNeon}) {
    const int64_t bit = highwayTarget(isa);
    if (bit > 0 && (HWY_TARGETS & bit) != 0) out.push_back(isa);
  }
  return out;
}

bool isSupported(Isa isa) {
  if (isa == Isa::kScalar) return true;
  const int64_t bit = highwayTarget(isa);
  if (bit <= 0 || (HWY_TARGETS & bit) == 0) return false;
#if HWY_ARCH_ARM_A64
  // Static dispatch: the baseline target always runs (see CMakeLists.txt and
  // google/highway#1206 — run-time detection misses NEON without AES).
  return bit == HWY_STATIC_TARGET;
#else
  return (hwy::SupportedTargets() & bit) != 0;
#endif
}

std::vector<Isa> supportedIsas() {
  std::vector<Isa> out;
  for (Isa isa : compiledIsas()) {
    if (isSupported(isa)) out.push_back(isa);
  }
  return out;
}

Isa bestIsa() {
  return supportedIsas().back();
}

}  // namespace penumbra::simd
