// Latitude-longitude (equirectangular) environment maps, the format of light probes such as
// Blender's studio lights: width = 2 × height, row 0 at the zenith (+z), column x centred on
// the azimuth 360° · (x + 0.5) / width counter-clockwise from +x (hemisphere_map.h's frame).
// Used offline, to make test environments and simulated camera footage (libm allowed here).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "core/image.h"
#include "envmap/hemisphere_map.h"

namespace penumbra::envmap {

// Bilinear radiance of `latLong` in direction `d` (unit), wrapping in azimuth and clamping at
// the poles. `latLong` must be a non-empty RGB image.
glm::dvec3 sampleLatLong(const core::ImageF& latLong, const glm::dvec3& d);

// The upper hemisphere of `latLong`, turned by `azimuthDegrees` about +z, as a
// HemisphereMap of cols × rows: each pixel the mean of `supersample`² bilinear samples spread
// over it. Throws std::invalid_argument for an empty or inconsistent image.
HemisphereMap hemisphereFromLatLong(const core::ImageF& latLong, double azimuthDegrees = 0,
                                    uint32_t cols = kEnvmapCols, uint32_t rows = kEnvmapRows,
                                    uint32_t supersample = 2);

// The lat-long map averaged over `factor` × `factor` blocks (a smaller probe for fast tests).
// Throws std::invalid_argument when the size is not a multiple of the factor.
core::ImageF shrinkLatLong(const core::ImageF& latLong, uint32_t factor);

}  // namespace penumbra::envmap
