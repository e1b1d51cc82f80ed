// Animated environments for live lighting (issue 16 item 8): a still light probe (a lat-long
// map such as Debian blender-data's CC0 studio lights) made into a sequence of the changes a
// showroom's light goes through: the probe turning about the zenith, a lamp (the probe's
// brightest region) switched off, a cloud passing over the window (a smooth intensity drop in
// one region), sensor noise, and mains flicker (lamps pulsing at twice the mains frequency,
// sampled by the camera's frame rate). Frames are computed on demand, deterministically (noise
// from core/random.h keyed by frame and pixel), so tests and tools make the sequences at run
// time from the installed probes instead of shipping them.
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "core/image.h"

namespace penumbra::envmap {

struct ProbeAnimation {
  double degreesPerFrame = 0;  // rotation about the zenith
  // The brightest region (pixels within `lampRadiusDegrees` of the brightest upper-hemisphere
  // pixel and above a fifth of its luminance) drops to `lampOffLevel` of its radiance from
  // frame `lampOffFrame` on (−1: never).
  int64_t lampOffFrame = -1;
  double lampRadiusDegrees = 25, lampOffLevel = 0.02;
  // A cloud over the brightest direction: radiance × (1 − cloudDepth · s(t) · w(angle)), s a
  // triangle rising from frame cloudFrom to the middle and falling to cloudTo, w a smooth disc
  // of cloudRadiusDegrees (cloudTo ≤ cloudFrom: no cloud).
  int64_t cloudFrom = 0, cloudTo = 0;
  double cloudDepth = 0.8, cloudRadiusDegrees = 30;
  double noise = 0;         // per-sample uniform noise of ± this fraction (sensor noise)
  double flickerDepth = 0;  // gain 1 + depth · sin(2π · flickerHz · k / frameHz)
  double flickerHz = 100, frameHz = 21;
  uint64_t seed = 1;
};

// The brightest direction of the upper hemisphere of `latLong` (unit vector, lat_long.h's
// frame): where the lamp and the cloud of an animation are.
glm::dvec3 brightestDirection(const core::ImageF& latLong);

// Frame `frame` of the animation of `probe` (a lat-long RGB map; negative values as 0).
// Throws std::invalid_argument for an empty or inconsistent probe.
core::ImageF animateProbe(const core::ImageF& probe, const ProbeAnimation& animation,
                          uint64_t frame);

}  // namespace penumbra::envmap
