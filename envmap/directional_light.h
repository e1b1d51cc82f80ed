// What live lighting produces (Havran et al. 2005 §3): directional lights, each with a stable
// id, for per-light shading and shadow maps. A light's id is the Halton index of the sample it
// came from (halton.h), or, after clustering (light_clustering.h), the id of the cluster's
// first light: the same light keeps its id from frame to frame, which the temporal filter
// (light_filter.h) and a per-light shadow-map cache rely on.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace penumbra::envmap {

struct DirectionalLight {
  uint32_t id = 0;
  // Unit vector from the scene towards the light, in the environment map's frame (z the
  // zenith; hemisphere_map.h).
  glm::dvec3 direction{0.0, 0.0, 1.0};
  // RGB power: radiance × solid angle (the irradiance the light gives a surface facing it),
  // in the environment map's radiance units × sr.
  glm::dvec3 power{0.0};
};

using LightSet = std::vector<DirectionalLight>;

// Sum of the lights' powers, in their order (a fixed order: the same bits everywhere).
glm::dvec3 totalPower(const LightSet& lights);

}  // namespace penumbra::envmap
