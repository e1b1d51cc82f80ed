// The real room as the shadow pipeline sees it: axis-aligned quads and solid boxes with
// diffuse materials, triangulated into a patch mesh (Gibson 2003 §4–5: the receiver and
// source sets are patches of a reconstructed scene model carrying a diffuse reflectance
// and, for light sources, an emitted radiance).
//
// Facing convention (used by every function here): a quad's normal is
// normalize(cross(edgeU, edgeV)) and points into the room's free air, i.e. towards the
// side from which the camera, the lights and the receivers see it. addRoomShell() makes
// the six walls of a room face inwards; addSolidBox() makes the faces of a box standing
// in the room (a desk) face outwards, which is again "into the air". Triangles are wound
// counter-clockwise about that normal (the rasterizer draws both windings; the winding
// only documents the side).
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/geometry.h"

namespace penumbra::scene {

struct Material {
  glm::dvec3 reflectance{0.5};  // diffuse albedo per channel, in [0, 1]
  glm::dvec3 emission{0.0};     // emitted radiance per channel (relative units)
  bool emits() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
};

struct Aabb {
  glm::dvec3 min{0.0}, max{0.0};
  glm::dvec3 centre() const { return (min + max) * 0.5; }
  glm::dvec3 size() const { return max - min; }
  // Corner i of 8: bit 0 picks max.x over min.x, bit 1 max.y, bit 2 max.z.
  glm::dvec3 corner(size_t i) const {
    return {(i & 1) ? max.x : min.x, (i & 2) ? max.y : min.y, (i & 4) ? max.z : min.z};
  }
  // Grows the box to contain `p`; an empty() box becomes the point.
  void extend(const glm::dvec3& p);
  bool empty() const { return !(min.x <= max.x && min.y <= max.y && min.z <= max.z); }
  static Aabb emptyBox();
};

// A sub-rectangle of a quad with its own material and patch size, in the quad's
// parametric coordinates (s along edgeU, t along edgeV, both in [0, 1]): a window in a
// wall, a light panel in a ceiling. Regions of one quad must not overlap.
struct Region {
  std::string name;
  double s0 = 0, s1 = 1, t0 = 0, t1 = 1;
  Material material;
  double patchSize = 0;  // metres; 0 = the mesh's target size
};

// A sub-rectangle of a quad cut into patches of at most `patchSize` without changing its
// material (RoomDescription::refineAroundSolids), in the quad's (s, t) as a Region. May
// overlap regions and other refinements: the smallest size wins.
struct Refinement {
  double s0 = 0, s1 = 1, t0 = 0, t1 = 1;
  double patchSize = 0;  // metres, > 0
};

// The parallelogram origin + s*edgeU + t*edgeV, s, t in [0, 1] (a rectangle for the
// axis-aligned rooms built here).
struct Quad {
  std::string name;
  glm::dvec3 origin{0.0}, edgeU{1, 0, 0}, edgeV{0, 1, 0};
  Material material;
  std::vector<Region> regions;
  std::vector<Refinement> refinements;

  glm::dvec3 normal() const;
  double area() const;
  glm::dvec3 point(double s, double t) const { return origin + s * edgeU + t * edgeV; }
  // The material at (s, t): the first region containing it, else the quad's own.
  const Material& materialAt(double s, double t) const;
};

struct RayHit {
  double t = 0;         // ray parameter (distance if the direction is unit length)
  uint32_t quad = 0;    // index into RoomDescription::quads
  double s = 0, u = 0;  // parametric position on the quad (s along edgeU, u along edgeV)
  glm::dvec3 point{0.0};
  glm::dvec3 normal{0.0};  // the quad's normal (facing convention above)
};

// The room model: quads (drawn, patched, ray-cast) and solid boxes (their faces are
// quads too; the boxes themselves block shadow rays, as the desk in Gibson 2003 §9).
class RoomDescription {
 public:
  // Adds a quad; returns its index.
  uint32_t addQuad(Quad quad);
  // The six inward-facing walls of `room` (y up): floor (y = min.y), ceiling, then the
  // walls x = min.x, x = max.x, z = min.z, z = max.z. Returns the index of the floor quad;
  // the others follow in that order. Regions can be added to them afterwards.
  uint32_t addRoomShell(const Aabb& room, const Material& floor, const Material& walls,
                        const Material& ceiling);
  // A solid box standing in the room, faces outward, in the order bottom, top, x = min.x,
  // x = max.x, z = min.z, z = max.z (the bottom is skipped when `withBottom` is false,
  // e.g. a box resting on the floor). Returns the index of its first quad.
  uint32_t addSolidBox(const std::string& name, const Aabb& box, const Material& material,
                       bool withBottom);

  // Nearest hit with t in (tMin, tMax), either side of a quad.
  std::optional<RayHit> intersect(const glm::dvec3& origin, const glm::dvec3& dir, double tMin,
                                  double tMax) const;
  // True when a solid box blocks the open segment from `a` to `b`. The room shell is
  // convex, so only the solid boxes can occlude (Gibson 2003 §5: point-to-patch
  // visibility by ray casting).
  bool segmentBlocked(const glm::dvec3& a, const glm::dvec3& b) const;

  // Contact refinement (issue 15 item 4): where a solid box stands on a quad (its base on
  // the quad's plane, the box on the air side), the quad is cut into patches of at most
  // `patchSize` over the box's footprint grown on every side by the box's height above the
  // quad. Why there: the room shell is convex, so the static visibility of the lights, and
  // with it each source's share of a receiver vertex's light, varies fast only near solid
  // boxes; a receiver point at distance d from a face of a box of height h loses the lights
  // below elevation atan(h / d), so for lights 45 degrees or more above the horizon the loss
  // stays within d < h. The 0.4 m showroom grid has one vertex row at the desk's foot and the
  // next 0.4 m away; a floor pixel between them had the desk hide the light its vertices
  // still saw, and the product's shadow there came out 40-50 levels too light (the corner
  // poses of docs/accuracy.md). The grid stays conforming (the strips run across the quad,
  // as regions' do). `patchSize` must be positive and finite (std::invalid_argument).
  void refineAroundSolids(double patchSize);

  std::vector<Quad> quads;
  std::vector<Aabb> solids;
  // Shadow-boundary refinement (scene key "shadow_boundary_patch_size";
  // scene/shadow_boundary_refinement.h): buildPatchMesh halves a non-emitting cell, down
  // to patches of at most this size, while the emitters' static visibility changes across
  // it. 0: off.
  double shadowBoundaryPatchSize = 0;
};

// One patch: a grid cell of a quad, drawn as two triangles.
struct Patch {
  glm::dvec3 centre{0.0};
  glm::dvec3 normal{0.0};
  double area = 0;
  glm::dvec3 reflectance{0.0};
  glm::dvec3 emission{0.0};
  uint32_t quad = 0;           // source quad in the RoomDescription
  uint32_t firstTriangle = 0;  // triangles firstTriangle and firstTriangle + 1
  bool emits() const { return emission.x > 0 || emission.y > 0 || emission.z > 0; }
};

struct PatchMesh {
  std::vector<glm::dvec3> positions;    // per vertex, world space
  std::vector<glm::dvec3> normals;      // per vertex (vertices are shared within a quad only)
  std::vector<uint32_t> indices;        // 3 per triangle
  std::vector<uint32_t> trianglePatch;  // per triangle: index into patches
  std::vector<Patch> patches;

  size_t triangleCount() const { return indices.size() / 3; }
  // Positions rounded to float once, same indices: the trace's static mesh.
  core::Mesh toRasterMesh() const;
};

// Splits every quad into a grid of patches about `targetPatchSize` metres on a side
// (each region's own size inside it), two triangles per patch. Grid lines pass through
// every region boundary so each patch has one material; a region's finer spacing runs
// across its whole quad as strips, which keeps the grid conforming (no T-junctions).
// With room.shadowBoundaryPatchSize > 0, grid cells straddling a shadow boundary are then
// cut as quadtrees (scene/shadow_boundary_refinement.h). Those meet their coarser
// neighbours in T-junctions: the id buffer gives every pixel one triangle, so no pixel is
// drawn twice or missed, and the shares on either side of such an edge differ by less than
// the test's significance at its midpoint. A quad whose cells all stay whole keeps the
// grid's vertices, patches and triangles exactly. Throws std::length_error when the
// refined mesh would hold more than `maxPatches` patches.
PatchMesh buildPatchMesh(const RoomDescription& room, double targetPatchSize,
                         double maxPatches = std::numeric_limits<double>::infinity());

// The number of patches buildPatchMesh() would make, counted without building them (in
// double: a hostile room or patch size gives a huge or infinite count, never an overflow).
double patchCount(const RoomDescription& room, double targetPatchSize);

// Point-to-patch form factor from a receiver point `x` with unit normal `nx` to a
// patch (centre, unit normal, area): cos_i cos_j A / (pi r^2 + A), each cosine clamped at
// 0 (Gibson 2003 §5). The "+ A" is the disc approximation of Wallace et al. 1989: it
// equals the point-to-patch form factor when r^2 >> A but stays below 1 as r -> 0, where
// the pure 1/r^2 term would blow up for receivers touching an emitter's edge.
double pointToPatchFormFactor(const glm::dvec3& x, const glm::dvec3& nx,
                              const glm::dvec3& patchCentre, const glm::dvec3& patchNormal,
                              double patchArea);

// Converts a double point to the trace's float vector (one rounding).
core::Vec3 toVec3(const glm::dvec3& p);

}  // namespace penumbra::scene
