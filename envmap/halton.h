// The sample pattern of live lighting (Havran et al. 2005 §3.2): the 2D Halton sequence in
// bases 2 and 3, relaxed once by Lloyd's algorithm towards blue noise, used progressively: the
// light with Halton index i always comes from point i, so the first k points of the pattern
// are the k-light set for every k, and adding or removing lights never moves the others.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace penumbra::envmap {

// The radical inverse of `index` in `base` (van der Corput): the digits of index mirrored
// about the radix point. Exact in binary64 for base 2; for base 3 one rounding per digit.
// Throws std::invalid_argument for base < 2.
double radicalInverse(uint64_t index, uint32_t base);

// Halton point `index` (index ≥ 1: point 0 is the corner (0, 0)) in bases 2 and 3.
glm::dvec2 haltonPoint(uint64_t index);

// Points 1..count of the Halton sequence, relaxed by one Lloyd step over the unit square:
// every point moves to the centroid of its Voronoi cell. The cells are measured on a grid of
// `gridPerPoint`² cells per point (nearest point by squared distance, ties to the lower
// index; sums in grid order), so the pattern is the same bits everywhere. The relaxation is
// computed once for the largest light count and the prefixes are used (Havran 2005 §3.2:
// "at the preprocessing stage ... then the resulting samples can be used for all VEM").
class SamplePattern {
 public:
  explicit SamplePattern(uint32_t count, bool relaxed = true, uint32_t gridPerPoint = 16);

  uint32_t size() const { return static_cast<uint32_t>(points_.size()); }
  // Point of Halton index `index` (1 ≤ index ≤ size()), in [0, 1]².
  const glm::dvec2& point(uint32_t index) const { return points_[index - 1]; }

 private:
  std::vector<glm::dvec2> points_;
};

}  // namespace penumbra::envmap
