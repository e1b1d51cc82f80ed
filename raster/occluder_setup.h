// Shadow-map occluders set up several vertices and triangles per vector
// (docs/pipeline-spec.md §2–5): the transform, clip test and snap of spec §2–3 for an
// occluder that lies wholly inside the light's clip volume (the usual case: the light
// frustum is fitted to the occluder, Gibson 2003 §7.2), and setupTriangle for its
// triangles. Every target returns exactly what the scalar functions of
// raster/triangle_setup.h return: the same IEEE operations in the same order, integer
// products evaluated in binary64 where they are exact.
//
// A showroom pass draws 484 occluder triangles into its map; setupTriangle alone, one
// triangle at a time, was 9% of a frame's CPU time (docs/performance.md, round 5).
#pragma once

#include <cstddef>
#include <cstdint>

#include "raster/frame_trace.h"
#include "raster/triangle_setup.h"
#include "simd/targets.h"

namespace penumbra::raster {

struct OccluderKernels {
  // Transforms points[0, count) by `m` (transformPoint). If every point is inside the clip
  // volume (insideClipVolume), writes each one's snapVertex to a size x size viewport as
  // x[i], y[i], z[i] and returns true; otherwise returns false, and x, y, z hold anything.
  // x, y and z must have room for count rounded up to a multiple of kOccluderBatch.
  bool (*snapInside)(const core::Mat4& m, const core::Vec3* points, size_t count, uint32_t size,
                     int32_t* x, int32_t* y, float* z);
  // setupTriangle for each triangle k < count of vertices indices[3k], [3k + 1], [3k + 2]
  // among snapped vertices (x, y, z) whose corner weights are {65536, 0, 0} (snapInside's):
  // writes the triangles it accepts to out[0, n), in order, and returns n. `out` must have
  // room for `count`. With cullBackFaces it also leaves out the triangles that face away
  // from the light (facesAwayOnMap).
  size_t (*setupTriangles)(const int32_t* x, const int32_t* y, const float* z,
                           const uint32_t* indices, size_t count, uint32_t size, bool cullBackFaces,
                           SetupTriangle* out);
};

// The widest batch any target processes at once (16 floats of AVX-512).
inline constexpr size_t kOccluderBatch = 16;

// The kernels of `isa`; the caller checks simd::isSupported(isa).
const OccluderKernels& occluderKernelsFor(simd::Isa isa);

}  // namespace penumbra::raster
