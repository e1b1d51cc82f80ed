// Which of the environment's directions each receiver vertex sees past the room's own
// furniture (issue 16 item 6: "visibility of the static room"). Live lighting treats the
// environment camera's lights as distant (Havran et al. 2005 §3): the map is the room as
// that camera sees it — walls, windows, ceiling lamps — so those surfaces are the lights,
// not occluders. What stands inside the room does occlude: the floor beside the desk does
// not see the window behind the desk, and the product's shadow of that window's light must
// not be subtracted there a second time (the photograph already holds the desk's shadow).
//
// The enclosing shell is told from the furniture by geometry alone, as the bundle keeps no
// labels: a room triangle is shell when every vertex of the room lies on its front side
// (within 1 mm) — the floor, walls and ceiling of a room that is convex inside. Every other
// triangle (a desk's top and sides) is an occluder. An alcove of a non-convex room counts
// as an occluder too, which is what its walls are to a receiver outside it.
//
// Per receiver vertex, visibility is precomputed once over a fixed grid of kGrid x kGrid
// directions of the upper hemisphere (+y up): one ray per cell centre from the vertex
// (lifted 1 mm along its normal) against the occluder triangles (Moller & Trumbore 1997, in
// double: the same bits on every machine, design §3). The grid is the hemisphere's
// octahedral map turned by 45 degrees — s = u + w, t = u - w with (u, w) = (x, z) / (|x| +
// y + |z|) — which covers the square [-1, 1]^2 continuously and needs no trigonometry. A
// light between cell centres gets the bilinear blend of the four nearest cells' bits, so
// its visibility changes continuously as it moves and a light crossing a desk's edge fades
// instead of popping.
//
// Limits, stated: the grid resolves about 11 degrees (a desk 2 m away blocks a light
// whose direction misses its edge by 0.4 m, or not); the product's own shading is not
// occluded by the room (its vertices move every frame; precomputing them is not possible).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "core/job_pool.h"
#include "scene/patch_mesh.h"

namespace penumbra::shadow {

class StaticRoomVisibility {
 public:
  static constexpr int kGrid = 16;
  static constexpr size_t kWords = kGrid * kGrid / 64;

  // A direction's place on the grid: the four nearest cell centres and their bilinear
  // weights (summing to 1). Per light, once a frame.
  struct Lookup {
    std::array<uint16_t, 4> cell{};
    std::array<double, 4> weight{};
  };

  // `receiverVertices`: mesh vertices of `mesh` (RadianceTransfers::receiverVertices). The
  // rays are cast on `pool` (null: serially); the bits do not depend on it.
  StaticRoomVisibility(const scene::PatchMesh& mesh, std::span<const uint32_t> receiverVertices,
                       core::JobPool* pool);

  // `towardsLight` need not be unit; a direction below the horizon is looked up on it.
  static Lookup lookup(const glm::dvec3& towardsLight);
  // The unit direction at the centre of cell (i, j), i along s, j along t.
  static glm::dvec3 cellDirection(int i, int j);

  // True when receiver vertex r sees every cell: visibility 1 in every direction.
  bool seesEverything(uint32_t r) const { return blocked_[r] == 0; }
  // In [0, 1]: the share of the light from `l`'s direction that reaches receiver vertex r.
  double visibility(uint32_t r, const Lookup& l) const;
  // Whether cell c of receiver vertex r is seen.
  bool sees(uint32_t r, uint32_t cell) const {
    return blocked_[r] == 0 || (bits_[r * kWords + cell / 64] >> (cell % 64) & 1) != 0;
  }

  size_t occluderTriangles() const { return occluders_.size(); }
  // Receiver vertices with at least one direction blocked.
  size_t partlyBlockedVertices() const;

 private:
  struct Triangle {
    glm::dvec3 a, edge1, edge2;
  };
  // Occluder triangles in runs of kRun, each run with its bounding box.
  static constexpr size_t kRun = 16;
  struct Run {
    glm::dvec3 lo, hi;
    uint32_t first, count;
  };
  bool occluded(const glm::dvec3& origin, const glm::dvec3& direction) const;

  std::vector<Triangle> occluders_;
  std::vector<Run> runs_;
  std::vector<uint64_t> bits_;     // kWords per receiver vertex, bit c = cell c seen
  std::vector<uint16_t> blocked_;  // per receiver vertex: cells not seen
};

}  // namespace penumbra::shadow
