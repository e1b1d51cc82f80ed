// SIMD targets: which instruction sets Penumbra compiles, which this CPU runs, and the
// run-time switch that forces one (`--isa`).
//
// Every kernel family (simd/u8_ops.h, raster/span_kernels.h) is compiled once per target and
// looked up by `Isa`; the scalar reference is a target like any other. All targets produce
// identical bytes (docs/pipeline-spec.md), which tests/invariance_test.cpp proves.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

namespace penumbra::simd {

enum class Isa : uint8_t {
  kScalar,  // plain C++ loops that follow docs/pipeline-spec.md line by line
  kSse4,
  kAvx2,
  kAvx512,
  kNeon,
};

// "scalar", "sse4", "avx2", "avx512", "neon".
const char* isaName(Isa isa);

// Parses an ISA name as printed by isaName(); "best" is not a target (see bestIsa()).
std::optional<Isa> parseIsa(std::string_view name);

// Targets compiled into this binary (scalar always; x86: SSE4, AVX2, AVX-512; aarch64: NEON).
std::vector<Isa> compiledIsas();

// Compiled and runnable on this CPU, in increasing order of width.
std::vector<Isa> supportedIsas();

bool isSupported(Isa isa);

// The widest supported target.
Isa bestIsa();

// Highway's target bit for `isa` (0 for the scalar reference). For kernel tables only.
int64_t highwayTarget(Isa isa);

}  // namespace penumbra::simd
