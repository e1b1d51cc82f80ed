// The hemisphere parametrisation of live lighting (Havran et al. 2005 §3.1, after Havran,
// Dmitriev & Seidel 2003): a point of the unit square goes to the unit disk by Shirley & Chiu's
// concentric map, and the disk goes to the upper hemisphere by an area-preserving map. Both
// steps preserve area, so equal areas of the square become equal solid angles.
//
// The environment map itself (HemisphereMap) is stored in the disk's polar coordinates:
// rows uniform in u = r² (= 1 − z, the cosine of the zenith angle subtracted from 1) and
// columns uniform in the azimuth. Every pixel then covers the same solid angle 2π/(rows·cols)
// (Archimedes: a band of the sphere has an area proportional to its height), so the Jacobian
// is constant and the sampling CDF comes from luminance alone (envmap_sampling.h).
//
// Frame: z is the zenith (the fisheye camera's optical axis), azimuth 0 along +x, counter-
// clockwise towards +y. Arithmetic: IEEE +, −, ×, ÷ and sqrt in a fixed order, sine and cosine
// from scene/portable_trig.h: the same bits on every machine (design §3).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "core/image.h"

namespace penumbra::envmap {

// A point of the unit disk in polar form: u = r² in [0, 1] and the azimuth in turns
// (fraction of a full turn) in [0, 1). Both are uniform on [0, 1) for a point uniform on the
// disk, which is what the inverse-transform sampler draws from.
struct DiskPolar {
  double u = 0;
  double turns = 0;
};

// Shirley & Chiu 1997, "A low distortion map between disk and square" (the concentric map),
// for (s, t) in [0, 1]²: the square's concentric squares go to the disk's concentric circles,
// so neighbouring points stay neighbours and the map is continuous everywhere, including
// across azimuth 0 (Havran 2005 §3.1, Fig. 2: the standard method's seam).
DiskPolar concentricSquareToDisk(double s, double t);

// Havran 2005 §3.1 / Havran et al. 2003: the area-preserving map from the disk to the upper
// hemisphere, z = 1 − r², (x, y) = (r cos φ, r sin φ)·√(2 − r²). Returns a unit vector.
glm::dvec3 diskToHemisphere(const DiskPolar& p);

// The environment map over the hemisphere, RGB radiance (linear, non-negative) in a
// core::ImageF of `cols` × `rows` (row 0 at the zenith). Pixel (col, row) covers
// u ∈ [row/rows, (row+1)/rows) and turns ∈ [col/cols, (col+1)/cols).
struct HemisphereMap {
  core::ImageF radiance;

  uint32_t rows() const { return radiance.height; }
  uint32_t cols() const { return radiance.width; }
  // Solid angle of one pixel (sr): 2π / (rows · cols).
  double pixelSolidAngle() const;
  // The direction through the centre of pixel (col, row).
  glm::dvec3 pixelCentre(uint32_t col, uint32_t row) const;
};

// The paper's map size (Havran 2005 §6: "polar projection of the resolution 360 × 90").
inline constexpr uint32_t kEnvmapCols = 360;
inline constexpr uint32_t kEnvmapRows = 90;

}  // namespace penumbra::envmap
