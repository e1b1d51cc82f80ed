// Per-frame detail from the product's footprint on screen (issue 17): beside the frame-rate
// controller (Gibson 2003 §8), which spends the frame's time, this spends no more than the
// shadow can show. A product far from the camera covers few pixels, and so does its shadow:
//   - its shadow map needs no more texels than the pixels they land on. The light frustum
//     fits the product's bounding sphere (shadow/light_frustum.h), so a map of S texels
//     spans the sphere's diameter; where that diameter covers D pixels on screen, S = k D
//     texels give k texels per pixel at the product (texelsPerPixel). The shadow on a
//     receiver behind the product is magnified by its distance from the light, and the
//     showroom's tuned 256² maps (docs/tuning.md) are the teapot's need at 50 pixels: k = 4;
//   - its passes: a cluster's pass draws one step of the penumbra, and a penumbra a few
//     pixels wide shows no more steps than it has pixels. The ceiling falls in proportion to
//     D below fullDetailPx (the footprint that gets the bundle's whole ceiling). Measured,
//     a teapot of 50 pixels still needs its 50 passes (docs/accuracy.md), so the default
//     (48) leaves every showroom pose but the farthest at full detail.
// Without popping: the map moves to a smaller rung only once the footprint has shrunk an
// eighth past the rung's own need, and to a larger one as soon as the current map is
// coarser than k texels per pixel; the pass ceiling keeps still while its target stays
// within an eighth of it, and otherwise moves by at most maxStepPerFrame passes a frame. A
// footprint that wavers around a boundary therefore changes nothing (tests measure it).
#pragma once

#include <cstdint>
#include <vector>

#include "shadow/scene_bundle.h"

namespace penumbra::shadow {

// A sphere holding the product whatever its yaw: centred on the yaw axis (product-space x =
// z = 0) at the mid-height of the mesh's box, its radius the farthest vertex's distance.
struct YawSphere {
  double centreY = 0;
  double radius = 0;
};
YawSphere yawSphere(const core::Mesh& mesh);

// The diameter in pixels of `sphere` at `pose` (moved to (x, z), lifted; the yaw turns the
// product inside it) as `view`'s camera sees it, or +inf where the camera is inside the sphere
// or not in front of it. The projected radius is r f / w with w the centre's clip w (its
// depth along the view axis) and f = |row 1 of the view-projection's 3x3| height / 2, the
// focal length in pixels: the view is rigid, so that row is the projection's y scale times a
// unit vector. Double arithmetic and one sqrt: the same value on every machine.
double productFootprintPx(const raster::StaticView& view, const YawSphere& sphere,
                          const ProductPose& pose);

struct FootprintDetailOptions {
  uint32_t fullDetailPx = 48;  // footprint with the whole pass ceiling; 0 turns this off
  uint32_t texelsPerPixel = 4;
  uint32_t minPasses = 4;
  uint32_t maxStepPerFrame = 4;
};

class FootprintDetail {
 public:
  struct Limits {
    uint32_t passes;
    uint32_t shadowMapSize;
  };

  // `ladder`: map sizes, largest first (shadowMapLadder); `maxPasses` the ceiling at full
  // detail. Throws std::invalid_argument for an empty ladder or maxPasses 0.
  FootprintDetail(const FootprintDetailOptions& options, uint32_t maxPasses,
                  std::vector<uint32_t> ladder);

  // The limits for a frame whose product covers `footprintPx` pixels (NaN and +inf: full
  // detail). Starts at full detail; each call moves at most as the header says.
  Limits next(double footprintPx);

 private:
  FootprintDetailOptions options_;
  uint32_t maxPasses_;
  std::vector<uint32_t> ladder_;
  size_t rung_ = 0;
  uint32_t passes_;
};

}  // namespace penumbra::shadow
