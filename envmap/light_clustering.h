// Light clustering for live lighting (Havran et al. 2005 §4.3): lights with similar directions
// are merged so that at most Q shadow maps are drawn per frame. Ordered greedy clustering: the
// lights are taken in their order (the Halton order, so the cluster seeds change little from
// frame to frame); the first light not yet in a cluster starts one and takes every later
// unclustered light within the angular distance e = c_f · arcsin(√(2/Q)) of it; a cluster's
// direction is the luminance-power-weighted mean of its lights' directions, renormalised, its
// power the sum of theirs (energy is conserved exactly up to rounding), its id the seed's.
//
// e is the radius of Q equal discs covering the hemisphere (each covers 2π/Q = π sin² e), times
// the paper's correction c_f ≈ 1.8–1.9 for the discs' overlap. When the greedy pass still
// makes more than Q clusters (light spread wider than the discs assume), each cluster beyond
// the Q-th is merged into the nearest of the first Q (largest dot product of the seeds'
// directions, ties to the earlier): "the number of light sources after clustering is bounded
// by the user selected Q".
//
// The paper searches with a BBD tree (Arya et al. 1994); for the few hundred lights here the
// greedy pass compares each light with the seeds only: O(lights × clusters).
#pragma once

#include <cstdint>
#include <vector>

#include "envmap/directional_light.h"

namespace penumbra::envmap {

inline constexpr double kClusterCorrection = 1.85;  // c_f, Havran 2005 §4.3: 1.8–1.9

// e = c_f · arcsin(√(2/Q)) in degrees (√(2/Q) taken as 1 for Q ≤ 2). Deterministic: arcsin by
// bisection on scene/portable_trig.h's sine.
double clusterRadiusDegrees(uint32_t maxClusters, double correction = kClusterCorrection);

struct LightClusters {
  LightSet lights;                  // the clusters, in the order of their seeds
  std::vector<uint32_t> clusterOf;  // per input light, the index of its cluster in `lights`
};

// Temporal coherence (beyond the paper): what one frame's clustering remembers for the next.
// The greedy pass is discontinuous: a light wandering across a seed's radius by a fraction of
// a degree changes cluster, or starts one, and every later seed and cluster can change with
// it — powers jump between clusters and shadows flicker however smoothly the FIR moves the
// lights (docs/live-lighting.md, "Flicker"). With a memory, a light stays with last frame's
// seed while within e·(1 + hysteresis) of it, joins another seed only within
// e·(1 − hysteresis), and a light that was a seed is taken by another only within
// e·(1 − hysteresis). A light the memory has not seen is clustered as the paper says.
struct ClusterMemory {
  std::vector<uint32_t> seedOf;  // by light id: the id of its cluster's seed last frame; 0: none
  double hysteresis = 0.15;
};

// Throws std::invalid_argument for maxClusters = 0 or a correction ≤ 0. With `memory`, the
// coherence above; the memory is updated for the next frame.
LightClusters clusterLights(const LightSet& lights, uint32_t maxClusters,
                            double correction = kClusterCorrection,
                            ClusterMemory* memory = nullptr);

}  // namespace penumbra::envmap
