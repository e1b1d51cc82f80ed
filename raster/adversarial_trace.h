// Random adversarial frame traces: the cases where a second implementation of
// docs/pipeline-spec.md is most likely to part from the first (issue 13 item 4), drawn
// deterministically from a seed, for `penumbra-synth-trace --random` and the GL replay's
// agreement tests (bench/gl_replay).
//
// Each trace is u8 (version 1: whole-level S) and holds, by construction:
//   * receivers with a vertex behind the eye and across the near plane (spec §3 clipping,
//     clipped corner weights of S),
//   * receivers beyond a light's far plane and outside its map (spec §7: +inf texels and
//     texels outside [0, size) never occlude),
//   * passes with negative depth bias (where a map's clear value is visible: a finite clear
//     value plus a negative bias would occlude),
//   * coplanar duplicate receivers: triangles appended to the static mesh a second time with
//     the same vertex indices, listed in the same pass as the original (spec §6: only the
//     triangle whose id won the depth test subtracts),
//   * occluders crossing the light's near and far planes, binary and 2x2 PCF passes,
//   * a shadow in view in most passes (a canopy over the floor among the occluders),
//   * object receivers (self-shadowing) in half the passes, with negative bias in some.
//
// A separate library (penumbra_adversarial_trace) in the layer that owns the trace format:
// the product does not link it. Cost: microseconds to milliseconds per trace.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "raster/frame_trace.h"

namespace penumbra::raster {

// The trace of `seed`: the same seed gives the same trace (and the same file bytes through
// saveTrace) on every machine — only IEEE basic operations and sqrt, no libm trigonometry.
// The result passes validateTrace.
FrameTrace adversarialTrace(uint64_t seed);

// GL-convention perspective * look-at, row-major (clip = M (x, y, z, 1)), summed in binary64
// and rounded once to binary32; `focal` = 1 / tan(fovy / 2), given directly so that the
// adversarial traces draw it without libm trigonometry. The GL tests' traces use it too.
core::Mat4 lookAtPerspective(const std::array<double, 3>& eye, const std::array<double, 3>& at,
                             double focal, double aspect, double zNear, double zFar);

// How many listed receiver triangles (over all passes) show each adversarial feature,
// counted from the trace itself with the spec's transforms (spec §2–3, §7).
struct AdversarialFeatures {
  size_t behindEye = 0;        // a vertex with camera clip w <= 0
  size_t beyondLightFar = 0;   // a vertex beyond the pass's light far plane (z > w > 0)
  size_t outsideLightMap = 0;  // a vertex outside the light's x/y frustum (|x| > w or |y| > w)
  size_t negativeBiasPasses = 0;
  size_t duplicatePairs = 0;  // pairs of listed triangles with the same three vertices
  size_t pcfPasses = 0;
  size_t objectReceiverPasses = 0;  // passes listing object triangles
};
AdversarialFeatures adversarialFeatures(const FrameTrace& trace);

}  // namespace penumbra::raster
