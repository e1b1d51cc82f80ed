#include "envmap/live_lights.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace penumbra::envmap {

namespace {

// The options a LiveLights can run with; the reasons are in the header.
const LiveLightsOptions& checked(const LiveLightsOptions& o) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("live lights: " + what); };
  if (o.samples == 0 || o.samples > kMaxLiveSamples)
    fail("samples " + std::to_string(o.samples) + " outside 1.." + std::to_string(kMaxLiveSamples));
  if (o.maxLights == 0 || o.maxLights > o.samples)
    fail("maxLights " + std::to_string(o.maxLights) + " outside 1..samples (" +
         std::to_string(o.samples) + ")");
  if (!std::isfinite(o.clusterCorrection) || !(o.clusterCorrection > 0))
    fail("clusterCorrection " + std::to_string(o.clusterCorrection) + " is not a positive number");
  if (!std::isfinite(o.radianceScale) || !(o.radianceScale > 0))
    fail("radianceScale " + std::to_string(o.radianceScale) + " is not a positive number");
  // A rotation (or reflection) only: a scale or shear would change the lights' angles, and
  // the clustering radius and per-light shadow maps assume unit directions.
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double d = glm::dot(o.toWorld[i], o.toWorld[j]) - (i == j ? 1.0 : 0.0);
      if (!std::isfinite(d) || std::abs(d) > 1e-9)
        fail("toWorld is not orthonormal (column " + std::to_string(i) + " · column " +
             std::to_string(j) + " is off by " + std::to_string(d) + ")");
    }
  return o;
}

// M·d renormalised, the products added in column order (M is orthonormal, so the length is 1
// up to rounding; renormalising keeps the unit length the consumers assume).
glm::dvec3 toWorldDirection(const glm::dmat3& m, const glm::dvec3& d) {
  const glm::dvec3 w = (m[0] * d.x + m[1] * d.y) + m[2] * d.z;
  return w / std::sqrt(glm::dot(w, w));
}

}  // namespace

uint32_t prefixSampleCount(uint32_t samples, uint32_t maxLights, size_t count) {
  if (samples == 0 || maxLights == 0 || maxLights > samples || count == 0)
    throw std::invalid_argument("prefixSampleCount: needs 1 ≤ maxLights ≤ samples and count ≥ 1");
  const uint64_t q = std::min<uint64_t>(count, maxLights);
  const uint64_t n = (uint64_t(samples) * q + maxLights - 1) / maxLights;  // ⌈N·q/Q⌉, exact
  return uint32_t(std::clamp<uint64_t>(n, q, samples));
}

LightSet rescaledPrefix(const LightSet& filtered, uint32_t n, const glm::dvec3& total) {
  if (n > filtered.size())
    throw std::invalid_argument("rescaledPrefix: " + std::to_string(n) + " of " +
                                std::to_string(filtered.size()) + " lights");
  LightSet prefix(filtered.begin(), filtered.begin() + n);
  // The dropped samples' power goes to the kept ones in proportion (§3.3: every light of a
  // frame has the same luminance power, so the prefix is an unbiased estimate of the whole map
  // with its share scaled by N/n): the frame's brightness does not depend on the pass budget.
  const glm::dvec3 sum = envmap::totalPower(prefix);
  for (int c = 0; c < 3; ++c) {
    const double scale = sum[c] > 0 ? total[c] / sum[c] : 0.0;
    for (DirectionalLight& light : prefix)
      light.power[c] = sum[c] > 0 ? light.power[c] * scale : total[c] / double(n);
  }
  return prefix;
}

LiveLights::LiveLights(const LiveLightsOptions& options)
    : options_(checked(options)), pattern_(options.samples), cache_(options.maxLights) {}

void LiveLights::update(const HemisphereMap& map, const std::string& label) {
  if (distribution_)
    distribution_->update(map, label);
  else
    distribution_.emplace(map, label);
  // All N every frame (see the header): the filter tracks every id through every frame.
  if (options_.temporalFilter) {
    filtered_ = filter_.push(distribution_->sample(pattern_, options_.samples));
    total_ = filter_.filteredTotalPower();
  } else {
    filtered_ = distribution_->sample(pattern_, options_.samples);
    total_ = envmap::totalPower(filtered_);
  }
  ++updates_;
}

const LightSet& LiveLights::lights(size_t count) {
  if (!ready()) throw std::logic_error("live lights: lights() asked before the first update()");
  if (count == 0) throw std::invalid_argument("live lights: a budget of 0 shadow passes");
  const uint32_t q = uint32_t(std::min<size_t>(count, options_.maxLights));
  CacheEntry& entry = cache_[q - 1];
  if (entry.update == updates_) return entry.lights;

  const uint32_t n = prefixSampleCount(options_.samples, options_.maxLights, q);
  const LightSet prefix = rescaledPrefix(filtered_, n, total_);
  // Clustering in the environment frame (a rotation does not change angles), then the frame
  // and units of the room: the camera's radiance scale is one factor per light, so the sum
  // stays the filtered total × scale up to one rounding per light.
  entry.lights = clusterLights(prefix, q, options_.clusterCorrection,
                               options_.coherentClusters ? &entry.memory : nullptr)
                     .lights;
  for (DirectionalLight& light : entry.lights) {
    light.direction = toWorldDirection(options_.toWorld, light.direction);
    light.power *= options_.radianceScale;
  }
  entry.update = updates_;
  return entry.lights;
}

const LightSet& LiveLights::fineLights() {
  if (!ready()) throw std::logic_error("live lights: fineLights() asked before the first update()");
  if (fineUpdate_ != updates_) {
    fine_ = filtered_;
    for (DirectionalLight& light : fine_) {
      light.direction = toWorldDirection(options_.toWorld, light.direction);
      light.power *= options_.radianceScale;
    }
    fineUpdate_ = updates_;
  }
  return fine_;
}

glm::dvec3 LiveLights::totalPower() const {
  return ready() ? total_ * options_.radianceScale : glm::dvec3(0.0);
}

}  // namespace penumbra::envmap
