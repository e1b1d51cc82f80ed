// The simulated board's cost of a frame (design §3): with a VirtualClock it makes a whole
// kiosk session, and the frame-rate controller's decisions in it, replay to identical bytes.
#pragma once

#include <cstdint>
#include <vector>

namespace penumbra::shadow {

// A deterministic model of one frame's rendering cost, all in integers so the simulated
// session is bit-exact on every platform:
//
//   ns = fixedNs + load * (passes * (perPassNs + (perPassVertexPs * productVertices
//                                                  + perPassTransferredVertexPs * transferred)
//                                      / 1000)
//                          + (perTexelPs * shadowMapTexels
//                             + perPixelPs * shadowedPixels + perProductVertexPs * productVertices
//                             + perShadowMapTrianglePs * shadowMapTriangles
//                             + perTransferredVertexPs * transferred
//                             + perShadedVertexPs * shadedVertices) / 1000)
//
// following the shape of Gibson 2003 §9 (frame time grows with blending passes on top of a
// fixed shading/compositing part) and design.md §1 step 7 (each pass renders a size×size
// shadow map, then touches its shadowed pixels; with a map size per cluster the passes' maps
// differ, so the frame is charged the texels of all of them); the product's terms are its own
// stages (issue 13): its triangles in the pass list and in every pass grow with its vertices and
// the passes, and the occluder triangles the passes really drew into their maps (a pass that draws
// the fine shadow proxy draws several times the coarse one's; issue 17); its transfers (per vertex,
// and per vertex and cluster) and its shading are paid only in the frames that work them out again
// (it moved, or the clusters changed). The coefficients come from counted instructions
// (bench/board_cost_model.py, docs/kiosk.md "Cost model"). `load` is a scripted factor, piecewise
// constant in time, that stands for the scene getting heavier or lighter (a load step); it scales
// the variable part only, so the fixed part stays what the controller was told.
class CostModel {
 public:
  struct LoadStep {
    int64_t atNs;       // in effect from this virtual time on
    uint32_t permille;  // load factor × 1000 (1000 = nominal)
  };

  struct Params {
    int64_t fixedNs = 0;
    int64_t perPassNs = 0;
    int64_t perTexelPs = 0;                  // shadow-map texels (size^2 of each pass's map)
    int64_t perPixelPs = 0;                  // shadowed pixels in the frame, picoseconds each
    int64_t perPassVertexPs = 0;             // product vertices per pass
    int64_t perProductVertexPs = 0;          // product vertices, once per frame
    int64_t perShadedVertexPs = 0;           // product vertices shaded this frame
    int64_t perTransferredVertexPs = 0;      // product vertices whose transfers were worked out
    int64_t perPassTransferredVertexPs = 0;  // the same, per pass (cluster)
    int64_t perShadowMapTrianglePs = 0;      // occluder triangles drawn, summed over the passes
  };

  // What one frame did (the kiosk hands it over in kiosk::FrameWork).
  struct Workload {
    uint32_t passes = 0;
    uint64_t shadowedPixels = 0;   // receiver pixels summed over the passes
    uint64_t shadowMapTexels = 0;  // of every pass's map, summed (raster::FrameStats)
    uint32_t productVertices = 0, shadedVertices = 0, transferredVertices = 0;
    uint64_t shadowMapTriangles = 0;  // raster::FrameStats::shadowMapTriangles
  };

  // The Raspberry Pi 4's central coefficients (docs/kiosk.md "Cost model", from counted
  // aarch64 instructions; docs/board-cost-model.md): the board every session of data/sessions
  // simulates, and what `penumbra tune` prices a frame with.
  static Params raspberryPi4();

  // Throws std::invalid_argument for negative costs, or load steps that are not in strictly
  // increasing time order or have a zero factor.
  explicit CostModel(Params params, std::vector<LoadStep> loadSteps = {});

  // The load factor (‰) in effect at `nowNs`: 1000 before the first step.
  uint32_t loadPermilleAt(int64_t nowNs) const;

  // Workload::shadowMapTexels of `passes` maps of `size` texels a side each.
  static uint64_t uniformMapTexels(uint32_t passes, uint32_t size) {
    return uint64_t{passes} * size * size;
  }

  // Cost of a frame that starts at `nowNs`. Saturates at INT64_MAX rather than wrapping.
  int64_t frameNs(int64_t nowNs, const Workload& work) const;

  const Params& params() const { return params_; }

 private:
  Params params_;
  std::vector<LoadStep> loadSteps_;
};

}  // namespace penumbra::shadow
