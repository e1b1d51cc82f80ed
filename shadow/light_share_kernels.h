// The product's light shares over runs of doubles (ClusterTransfers, linear accumulation):
// a cluster's transfer to a run of vertices, summed over its sources' rows, and each
// channel's share of the vertex's light (lightShare, shadow/intensity_transfer.h).
//
// A run is the x, y, z doubles of consecutive vertices; element j of every run belongs to
// the same vertex and channel, so each element is a chain of its own and a vector lane runs
// it with the scalar reference's IEEE operations in its order. Compiled per SIMD target;
// every target gives the scalar reference's bits (tested on each).
// Cost: per element, one add per source row, then one division.
#pragma once

#include <cstddef>
#include <cstdint>

#include "simd/targets.h"

namespace penumbra::shadow {

struct LightShareKernels {
  // sum[j] = ((0 + rows[0][j]) + rows[1][j]) + ... + rows[count - 1][j] for j < n: rows in
  // the order given (a cluster's sources in selection order), each sum rounded in turn.
  void (*sumRows)(const double* const* rows, size_t count, size_t n, double* sum);
  // out[j] = lightShare(part[j], whole[j]) for j < n.
  void (*shares)(const double* part, const double* whole, size_t n, uint16_t* out);
};

// Kernels for `isa` (kScalar: the reference); the caller checks simd::isSupported(isa).
const LightShareKernels& lightShareKernelsFor(simd::Isa isa);

}  // namespace penumbra::shadow
