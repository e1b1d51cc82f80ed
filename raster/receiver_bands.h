// Receiver bands: the parts of a pass's receivers that its shadow map cannot darken.
//
// About half of a showroom pass's receiver pixels look up texels that no occluder triangle
// wrote (the map's 8x8 block table says so, ShadowMap::blocks): their occluded weight W is 0
// (spec §7), they add nothing to the sums (spec §6 step 4, §8), and yet interpolating their S
// and sweeping them cost as much as a shadowed pixel until the block gather. A band is up to
// kReceiverBandRows rows of one static receiver (sub-)triangle, summarised once, when the
// static cache is built: the bounding box and depth range of the pixels it can match, and how
// many there are. Per pass, LightFootprint::unwritten() bounds where those pixels' lookups
// can land in the map, in the lookup's own binary32 arithmetic, and a band that meets no
// written block is skipped whole: the same bytes, and its matched count stands in for the
// kernel's (FrameStats::passPixels feeds the simulator's cost model).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "raster/shadow_map.h"
#include "raster/span_kernels.h"

namespace penumbra::raster {

inline constexpr int32_t kReceiverBandRows = 8;

struct ReceiverBand {
  // Inclusive pixel bounding box of the matched pixels (meaningless when matched = 0).
  int32_t x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  float zMin = 0, zMax = 0;  // the static depth buffer's values at those pixels
  uint32_t matched = 0;      // pixels of the band's runs whose static id is the triangle's
};

// Appends the bands of one static sub-triangle: rows [minY, maxY) in bands of
// kReceiverBandRows rows from minY, `runs[y - minY]` its covered run of row y (empty when
// xa >= xb); a pixel matches when staticId holds `owner` (the triangle's index). `depth` and
// `id` are the static cache's planes, rows `stride` pixels apart.
void appendReceiverBands(int32_t minY, int32_t maxY, const std::pair<int32_t, int32_t>* runs,
                         const float* depth, const uint32_t* id, size_t stride, uint32_t owner,
                         std::vector<ReceiverBand>& out);

// The band covering both (the union of their pixels).
ReceiverBand unite(const ReceiverBand& a, const ReceiverBand& b);

// One pass's test: unwritten(band) is true only when no pixel of `band` with a depth in
// [zMin, zMax] can get W > 0 from `lookup`: every valid lookup's footprint starts in a block
// `map` never marked (ShadowMap::sumBlocks must have run), or no lookup is valid. False
// whenever the bound cannot be proved (a non-positive q3, huge matrix entries or depths): the
// band is then drawn as usual. About 40 binary32 operations per band.
class LightFootprint {
 public:
  // With the lookup's penumbraScale > 0 (an area-penumbra pass, spec §7) each band's
  // footprint is widened by the largest blocker-search half-width its pixels can have,
  // K (d - nearest) for the largest light depth d the band can reach (in [1,
  // kMaxPenumbraHalfWidth]), plus one texel. The lookup is read when a band is asked about, so it
  // may change in between.
  LightFootprint(const ShadowLookup& lookup, const ShadowMap& map);
  bool unwritten(const ReceiverBand& band) const;

 private:
  const ShadowLookup& lookup_;
  const ShadowMap& map_;
  bool bounded_;  // every entry of the lookup's matrix within kLimit (receiver_bands.cpp)
};

}  // namespace penumbra::raster
