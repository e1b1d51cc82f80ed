// Importance sampling of the hemisphere environment map by the inverse transform method of
// Havran et al. 2003, as used for live lighting (Havran et al. 2005 §3.1–3.2): a sample point
// of the unit square → concentric map → disk (u = r², azimuth in turns), both uniform; u is
// warped by the marginal CDF over the map's rows, the azimuth by the conditional CDF of that
// u, where the conditional CDF is linearly interpolated between the two neighbouring rows'
// CDFs so that the warp is continuous (§3.1: "the continuity of those mappings is preserved
// using a linear interpolation between neighboring 1D CDFs"); the warped disk point goes to the
// hemisphere by the area-preserving map. Every map pixel has the same solid angle
// (hemisphere_map.h), so the PDF is the luminance alone.
//
// Each light gets an equal share of the map's luminance power (§3.3: "all the light sources
// have the same power in a single frame") and the colour of the pixel it lands in; the RGB
// powers are then scaled per channel so that their sum is exactly the map's RGB power.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/error.h"
#include "envmap/directional_light.h"
#include "envmap/halton.h"
#include "envmap/hemisphere_map.h"

namespace penumbra::envmap {

class EnvmapError : public core::Error {
 public:
  using core::Error::Error;
};

// The CDFs of one environment map frame. Building it reads every pixel once; sampling costs
// two binary searches per light.
class EnvmapDistribution {
 public:
  // Throws EnvmapError naming `label` for an empty map, a wrong pixel count, or a negative
  // or non-finite radiance. Keeps a copy of the radiance (the lights' colours come from it).
  explicit EnvmapDistribution(const HemisphereMap& map,
                              const std::string& label = "environment map");
  // The same for the next frame, reusing this object's buffers (a live loop calls this once
  // per frame: no allocation once the map size is known). On error the object is left empty.
  void update(const HemisphereMap& map, const std::string& label = "environment map");

  // The map's power per channel: Σ radiance × pixel solid angle (fixed pixel order).
  const glm::dvec3& totalPower() const { return totalPower_; }
  double totalLuminancePower() const { return totalLuminance_; }

  // The inverse transform of a uniform disk point: the warped disk point (continuous in `p`).
  // Throws EnvmapError when the last update failed (as sample() does).
  DiskPolar warp(const DiskPolar& p) const;

  // Lights from the first `count` points of `pattern` (count ≤ pattern.size()), ids 1..count.
  // Light i depends on pattern point i and the map only, except for the common power scale:
  // the first k of n lights have the directions of the k-light set (Havran 2005 §3.2).
  LightSet sample(const SamplePattern& pattern, uint32_t count) const;

 private:
  void requireMap() const;  // throws when the last update failed
  // The conditional CDF between rows row0 and row0 + 1 (weight t of the second), at column
  // boundary j.
  double conditionalCdf(uint32_t row0, uint32_t row1, double t, uint32_t j) const;

  std::vector<float> radiance_;  // the map's pixels (core::ImageF layout)
  uint32_t rows_ = 0, cols_ = 0;
  std::vector<double> marginal_;     // rows + 1 entries, 0 … 1
  std::vector<double> conditional_;  // rows × (cols + 1) entries, each row 0 … 1
  glm::dvec3 totalPower_{0.0};
  double totalLuminance_ = 0;
};

}  // namespace penumbra::envmap
