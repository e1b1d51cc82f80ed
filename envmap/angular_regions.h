// Angular regions (Havran et al. 2005 §4.1): under distant lighting, the lights that can reach
// a point depend only on its normal. The sphere of normals is covered by regions around fixed
// centres spread evenly over it; each frame, every region gets the list of lights that can
// light some normal inside it, and shading a point looks its normal up in a cube map (one
// lookup, constant time) and walks that region's list only.
//
// Region centres: the Fibonacci sphere (points at equal-area heights, golden-angle azimuths).
// The cube map gives each texel the centre nearest to the texel's centre direction; ρ bounds
// the angle from any normal to its looked-up centre (the largest texel-centre-to-centre angle
// plus the largest texel half-diagonal: the triangle inequality on the sphere). A light L can
// light a normal N (N·L > 0) only if the angle between the region centre P and L is below
// 90° + ρ, so region P lists exactly the lights with P·L > −sin ρ: no contributor is ever
// missed, some outside lights remain ("some light sources are still eliminated online since
// b > π/2"). Lists keep the lights' order, so a Halton-prefix light set stays a prefix in every
// region (the paper's Observation 1).
//
// Deterministic: centres and the cube map from scene/portable_trig.h's sine and cosine and
// IEEE arithmetic; arccos by bisection. Not built: §4.2's two strata for glossy surfaces.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "envmap/directional_light.h"

namespace penumbra::envmap {

class AngularRegions {
 public:
  // `regions` centres (the paper uses 200), a cube map of `cubeSize`² texels per face. Throws
  // std::invalid_argument for fewer than 2 regions or a cube size of 0.
  explicit AngularRegions(uint32_t regions = 200, uint32_t cubeSize = 32);

  uint32_t size() const { return uint32_t(centres_.size()); }
  const glm::dvec3& centre(uint32_t region) const { return centres_[region]; }
  // ρ in degrees: the bound on the angle between a normal and its region's centre.
  double radiusDegrees() const { return radiusDegrees_; }

  // The region of a normal (any non-zero vector): one cube-map lookup.
  uint32_t regionOf(const glm::dvec3& normal) const;

  // Per region, the indices into `lights` that can light a normal of the region, ascending.
  std::vector<std::vector<uint32_t>> assign(const LightSet& lights) const;

 private:
  uint32_t texelOf(const glm::dvec3& d) const;
  glm::dvec3 texelDirection(uint32_t face, double s, double t) const;

  std::vector<glm::dvec3> centres_;
  uint32_t cubeSize_;
  std::vector<uint32_t> cube_;  // 6 × cubeSize² region indices
  double radiusDegrees_ = 0;
  double minDot_ = 0;  // −sin ρ
};

}  // namespace penumbra::envmap
