// Receiver refinement at the lights' static shadow boundaries (issue 15).
//
// The shadow pipeline interpolates each pass's light share across a receiver triangle from
// its corners (docs/pipeline-spec.md §5, §8). A share includes the room's own occlusion of
// the pass's sources: where a solid box (the desk) hides a light from one corner of a patch
// and not from another, the interpolated share is wrong at every pixel between them. The
// product's shadow there then subtracts the desk-blocked light a second time on the dark
// side and too little on the lit side (the desk corners of docs/accuracy.md: cutting there
// took the chair's mean error 1.561 -> 1.200 levels and the bunny's 1.872 -> 1.125).
//
// The geometric contact band (RoomDescription::refineAroundSolids) cuts whole strips of a
// quad finer around a box's base. Here the patch mesh is cut only where a light's static
// visibility actually changes: a cell of the grid is split into four, recursively, while
// its sample points disagree on which lights they see by more than `significance` of the
// light there, down to a smallest patch size. The test uses the emitting patches of the
// room model (light panels, windows) as the lights, each as its centre point; secondary
// light from walls is left out, it is smooth and dim next to the emitters' shadow edges.
#pragma once

#include <vector>

#include <glm/glm.hpp>

#include "scene/patch_mesh.h"

namespace penumbra::scene {

// One emitting patch as seen by the test: a point light with a patch's form factor.
struct LightSample {
  glm::dvec3 centre{0.0}, normal{0.0};
  double area = 0;
  double power = 0;  // emitted luminance (core::luminance of the emission)
};

class ShadowBoundaryTest {
 public:
  // `significance`: the share of the light (at the brightest sample point of a cell) that
  // lights with a disagreeing visibility may carry before the cell is split.
  ShadowBoundaryTest(const RoomDescription& room, std::vector<LightSample> lights,
                     double significance);

  // True when the cell [s0, s1] x [t0, t1] of `quad` straddles a shadow boundary that
  // matters. Sample points: the four corners, the four edge midpoints and the centre, a
  // tenth of a millimetre off the surface (as the transfers' shadow rays start). A cell
  // kept whole therefore has, at every one of its 9 points, the same set of visible lights
  // up to lights carrying less than `significance` of the light in total: its corners'
  // interpolated visibility is that close at its centre and at its edges' midpoints, which
  // is where a neighbour cut finer places its own vertices (the T-junctions of
  // buildPatchMesh, whose seams the same bound limits).
  bool straddles(const Quad& quad, double s0, double s1, double t0, double t1) const;

 private:
  const RoomDescription& room_;
  std::vector<LightSample> lights_;
  double significance_;
};

}  // namespace penumbra::scene
