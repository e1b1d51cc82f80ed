// Live lighting per frame (Havran et al. 2005, docs/live-lighting.md): the chain that turns the
// environment camera's hemisphere maps into the directional lights the shadow pipeline casts.
//
//   update(map), once per environment frame:
//     CDFs (envmap_sampling.h, §3.1) → N lights along the Lloyd-relaxed Halton prefix (§3.2)
//     → the temporal FIR, lights tracked by their Halton id (light_filter.h, §3.3)
//   lights(count), once per rendered frame, for a budget of `count` shadow passes:
//     the first n(count) filtered lights (§3.2: the count adapts along the prefix, so adding or
//     removing lights never moves the others) → powers rescaled to carry the filtered total
//     → clustered into at most q = min(count, Q) lights (light_clustering.h, §4.3)
//     → directions into the world frame, powers into the room camera's units.
//
// All N samples are drawn and filtered every frame, whatever the budget: a light's filter
// history must not depend on whether the controller asked for it last frame, or lights would
// jump when the budget changes. Per frame everything is IEEE scalar arithmetic in a fixed
// order (design §3): the same bits on every machine, whatever the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "envmap/directional_light.h"
#include "envmap/envmap_sampling.h"
#include "envmap/halton.h"
#include "envmap/hemisphere_map.h"
#include "envmap/light_clustering.h"
#include "envmap/light_filter.h"

namespace penumbra::envmap {

struct LiveLightsOptions {
  uint32_t samples = 300;   // N, the Halton prefix sampled per environment frame (§3.2)
  uint32_t maxLights = 72;  // Q at most (§4.3)
  double clusterCorrection = kClusterCorrection;
  glm::dmat3 toWorld{
      1.0};  // environment frame (z = zenith) -> world frame (columns: images of x, y, z)
  double radianceScale = 1.0;  // environment camera's radiance units -> the room camera's
  // §3.3's FIR on the lights. false: each map's samples as drawn, to measure what the filter
  // does against them (docs/live-lighting.md, "Flicker").
  bool temporalFilter = true;
  // Clusters kept from frame to frame with hysteresis (light_clustering.h, ClusterMemory).
  // false: each frame clustered afresh, as the paper does.
  bool coherentClusters = true;
};

// The largest N accepted: the temporal filter tracks lights by id in a table of this bound.
inline constexpr uint32_t kMaxLiveSamples = 1u << 20;

// n(count) = clamp(⌈N · q / Q⌉, q, N) with q = min(count, Q): how many of the N filtered samples
// a budget of `count` passes draws from. At the full budget all N; fewer passes, a proportionally
// shorter prefix, never fewer samples than clusters. Integer arithmetic (exact); count ≥ 1.
uint32_t prefixSampleCount(uint32_t samples, uint32_t maxLights, size_t count);

// The first `n` of `filtered` (n ≤ filtered.size()) with their powers scaled per channel so that
// they add up to `total` (a channel the prefix carries no power in: `total` shared equally).
LightSet rescaledPrefix(const LightSet& filtered, uint32_t n, const glm::dvec3& total);

class LiveLights {
 public:
  // Throws std::invalid_argument for samples = 0 or > kMaxLiveSamples, maxLights = 0 or
  // > samples, a cluster correction or radiance scale that is not finite and positive, or a
  // toWorld that is not orthonormal (|MᵀM − I| ≤ 1e-9 per entry). Computes the relaxed pattern.
  explicit LiveLights(const LiveLightsOptions& options);

  // A new environment frame: CDFs, N samples, the temporal filter. Throws EnvmapError naming
  // `label` for a map EnvmapDistribution refuses (empty, wrong pixel count, negative or
  // non-finite radiance); the filter and the lights of the last good frame are kept then.
  // A black map is a frame (a dark room): zero-power lights, not an error.
  void update(const HemisphereMap& map, const std::string& label = "environment map");

  bool ready() const { return updates_ > 0; }
  uint64_t updates() const { return updates_; }

  // The lights for a frame with budget for `count` shadow passes (count ≥ 1, clamped to Q), in
  // the world frame, powers × radianceScale, ids the Halton ids of the cluster seeds. Cached
  // per (last update, min(count, Q)): repeated calls in a frame cost nothing. The reference
  // stays valid until the next update(). Throws std::logic_error before the first update and
  // std::invalid_argument for count = 0.
  const LightSet& lights(size_t count);

  // The N filtered lights of the last update in the world frame, powers × radianceScale: the
  // fine lights of Havran 2005 §4.2's glossy strata (the frame's lights are clustered from a
  // prefix of them). Cached per update; throws std::logic_error before the first.
  const LightSet& fineLights();

  // The N filtered lights of the last update, in the environment frame and its units (for
  // tests and diagnostics; lights() draws its prefixes from these). Empty before the first.
  const LightSet& filtered() const { return filtered_; }

  // The filtered total power (the drawn total without the filter) in world units
  // (radianceScale applied); 0 before the first update.
  glm::dvec3 totalPower() const;

  const LiveLightsOptions& options() const { return options_; }

 private:
  struct CacheEntry {
    uint64_t update = 0;  // updates_ when computed; 0: never
    LightSet lights;
    ClusterMemory memory;  // this budget's clustering, remembered for its next frame
  };

  LiveLightsOptions options_;
  SamplePattern pattern_;
  std::optional<EnvmapDistribution>
      distribution_;  // built by the first map (it has no empty state)
  TemporalLightFilter filter_;
  LightSet filtered_;
  glm::dvec3 total_{0.0};
  LightSet fine_;            // fineLights()
  uint64_t fineUpdate_ = 0;  // updates_ when fine_ was made  // the power lights() hands out:
                             // filtered_'s total (filtered or not)
  uint64_t updates_ = 0;
  std::vector<CacheEntry> cache_;  // by q − 1
};

}  // namespace penumbra::envmap
