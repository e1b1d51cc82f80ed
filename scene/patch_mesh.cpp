#include "scene/patch_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "core/colour.h"
#include "scene/shadow_boundary_refinement.h"

namespace penumbra::scene {

void Aabb::extend(const glm::dvec3& p) {
  if (empty()) {
    min = max = p;
    return;
  }
  min = glm::min(min, p);
  max = glm::max(max, p);
}

Aabb Aabb::emptyBox() {
  const double inf = std::numeric_limits<double>::infinity();
  return Aabb{glm::dvec3(inf), glm::dvec3(-inf)};
}

glm::dvec3 Quad::normal() const {
  return glm::normalize(glm::cross(edgeU, edgeV));
}

double Quad::area() const {
  return glm::length(glm::cross(edgeU, edgeV));
}

const Material& Quad::materialAt(double s, double t) const {
  for (const Region& r : regions) {
    if (s >= r.s0 && s <= r.s1 && t >= r.t0 && t <= r.t1) return r.material;
  }
  return material;
}

uint32_t RoomDescription::addQuad(Quad quad) {
  if (!(glm::length(glm::cross(quad.edgeU, quad.edgeV)) > 0)) {
    throw std::invalid_argument("RoomDescription::addQuad: degenerate quad " + quad.name);
  }
  quads.push_back(std::move(quad));
  return static_cast<uint32_t>(quads.size() - 1);
}

namespace {

struct Face {
  const char* name;
  glm::dvec3 origin, u, v;
};

// The six faces of `b` with normals pointing inwards (into the box). Swapping u and v
// flips cross(u, v), which turns them outwards; the origin corner is common to both.
std::array<Face, 6> inwardFaces(const Aabb& b) {
  const glm::dvec3 d = b.size();
  const glm::dvec3 dx(d.x, 0, 0), dy(0, d.y, 0), dz(0, 0, d.z);
  const glm::dvec3 lo = b.min;
  return {{
      {"floor", lo, dz, dx},                                   // cross(z, x) = +y
      {"ceiling", glm::dvec3(lo.x, b.max.y, lo.z), dx, dz},    // cross(x, z) = -y
      {"wall_xmin", lo, dy, dz},                               // +x
      {"wall_xmax", glm::dvec3(b.max.x, lo.y, lo.z), dz, dy},  // -x
      {"wall_zmin", lo, dx, dy},                               // +z
      {"wall_zmax", glm::dvec3(lo.x, lo.y, b.max.z), dy, dx},  // -z
  }};
}

}  // namespace

uint32_t RoomDescription::addRoomShell(const Aabb& room, const Material& floor,
                                       const Material& walls, const Material& ceiling) {
  const auto faces = inwardFaces(room);
  uint32_t first = 0;
  for (size_t i = 0; i < faces.size(); ++i) {
    const Material& m = i == 0 ? floor : (i == 1 ? ceiling : walls);
    const uint32_t id =
        addQuad(Quad{faces[i].name, faces[i].origin, faces[i].u, faces[i].v, m, {}, {}});
    if (i == 0) first = id;
  }
  return first;
}

uint32_t RoomDescription::addSolidBox(const std::string& name, const Aabb& box,
                                      const Material& material, bool withBottom) {
  static constexpr const char* kSide[6] = {"bottom", "top", "xmin", "xmax", "zmin", "zmax"};
  const auto faces = inwardFaces(box);
  uint32_t first = static_cast<uint32_t>(quads.size());
  for (size_t i = withBottom ? 0 : 1; i < faces.size(); ++i) {
    addQuad(Quad{name + "_" + kSide[i], faces[i].origin, faces[i].v, faces[i].u, material, {}, {}});
  }
  solids.push_back(box);
  return first;
}

void RoomDescription::refineAroundSolids(double patchSize) {
  if (!(patchSize > 0) || !std::isfinite(patchSize)) {
    throw std::invalid_argument("refineAroundSolids: patch size must be positive and finite");
  }
  // A box closer to a quad's plane than this rests on it (the scene file's boxes stand on
  // the floor exactly; the tolerance absorbs a parsed 1e-12).
  constexpr double kTouch = 1e-6;
  for (Quad& q : quads) {
    const glm::dvec3 n = q.normal();
    const double lengthU = glm::length(q.edgeU), lengthV = glm::length(q.edgeV);
    for (const Aabb& box : solids) {
      std::array<glm::dvec3, 8> corners;
      for (size_t c = 0; c < 8; ++c) corners[c] = box.corner(c);
      double below = std::numeric_limits<double>::infinity(), height = -below;
      for (const glm::dvec3& corner : corners) {
        const double d = glm::dot(corner - q.origin, n);
        below = std::min(below, d);
        height = std::max(height, d);
      }
      // The box's own faces have it behind them (height <= 0); a box floating above the
      // quad casts no contact band.
      if (std::abs(below) > kTouch || !(height > kTouch)) continue;
      // The footprint in (s, t), grown by the height in metres along each edge. The quads
      // here are rectangles, so s and t are the projections on the edges.
      double s0 = std::numeric_limits<double>::infinity(), s1 = -s0, t0 = s0, t1 = -s0;
      for (const glm::dvec3& corner : corners) {
        const double s = glm::dot(corner - q.origin, q.edgeU) / (lengthU * lengthU);
        const double t = glm::dot(corner - q.origin, q.edgeV) / (lengthV * lengthV);
        s0 = std::min(s0, s), s1 = std::max(s1, s), t0 = std::min(t0, t), t1 = std::max(t1, t);
      }
      // Grown, clipped to the quad, and run on to its edge when that is closer than one
      // patch: a band stopping 5 cm short of a wall would leave a 5 cm sliver of patches
      // along it (seen by few probe pixels in capture, and no finer where it matters).
      const auto grow = [patchSize](double a, double b, double by, double length) {
        a -= by / length, b += by / length;
        const double slack = patchSize / length;
        return std::pair(a < slack ? 0.0 : a, b > 1.0 - slack ? 1.0 : b);
      };
      std::tie(s0, s1) = grow(s0, s1, height, lengthU);
      std::tie(t0, t1) = grow(t0, t1, height, lengthV);
      if (s0 < s1 && t0 < t1) q.refinements.push_back({s0, s1, t0, t1, patchSize});
    }
  }
}

std::optional<RayHit> RoomDescription::intersect(const glm::dvec3& origin, const glm::dvec3& dir,
                                                 double tMin, double tMax) const {
  std::optional<RayHit> best;
  double bestT = tMax;
  for (uint32_t qi = 0; qi < quads.size(); ++qi) {
    const Quad& q = quads[qi];
    const glm::dvec3 n = glm::cross(q.edgeU, q.edgeV);
    const double denom = glm::dot(n, dir);
    if (denom == 0) continue;  // parallel: no hit we could see
    const double t = glm::dot(n, q.origin - origin) / denom;
    if (!(t > tMin && t < bestT)) continue;
    // Parametric (s, u) by the 2x2 Gram system, valid for any parallelogram.
    const glm::dvec3 p = origin + t * dir;
    const glm::dvec3 r = p - q.origin;
    const double uu = glm::dot(q.edgeU, q.edgeU), uv = glm::dot(q.edgeU, q.edgeV);
    const double vv = glm::dot(q.edgeV, q.edgeV);
    const double ru = glm::dot(r, q.edgeU), rv = glm::dot(r, q.edgeV);
    const double det = uu * vv - uv * uv;
    const double s = (ru * vv - rv * uv) / det;
    const double u = (rv * uu - ru * uv) / det;
    if (s < 0 || s > 1 || u < 0 || u > 1) continue;
    bestT = t;
    best = RayHit{t, qi, s, u, p, glm::normalize(n)};
  }
  return best;
}

bool RoomDescription::segmentBlocked(const glm::dvec3& a, const glm::dvec3& b) const {
  // Slab test on the open parameter range (eps, 1 - eps): endpoints lying on a box face
  // (a receiver vertex on the desk top) do not count as blocked.
  constexpr double kEps = 1e-7;
  const glm::dvec3 d = b - a;
  for (const Aabb& box : solids) {
    double t0 = kEps, t1 = 1 - kEps;
    bool miss = false;
    for (int k = 0; k < 3 && !miss; ++k) {
      if (d[k] == 0) {
        // Parallel to this slab: strictly inside or it misses (touching a face is not
        // blocking, so a floor point beside the desk still sees the lights).
        if (!(a[k] > box.min[k] && a[k] < box.max[k])) miss = true;
        continue;
      }
      double ta = (box.min[k] - a[k]) / d[k], tb = (box.max[k] - a[k]) / d[k];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
      if (!(t0 < t1)) miss = true;
    }
    if (!miss) return true;
  }
  return false;
}

namespace {

// The intervals between region boundaries along one quad edge (fractions a < b of the
// edge) and the steps each is cut into: ceil(length / size), where size is the smallest
// patch size of the regions spanning the interval (else the target). Steps are kept as a
// double so a hostile extent is counted (patchCount) without overflowing an int.
struct GridInterval {
  double a, b, steps;
};

std::vector<GridInterval> gridIntervals(const std::vector<std::pair<double, double>>& spans,
                                        const std::vector<double>& spanSizes, double edgeLength,
                                        double targetSize) {
  std::vector<double> breaks{0.0, 1.0};
  for (const auto& [a, b] : spans) {
    breaks.push_back(std::clamp(a, 0.0, 1.0));
    breaks.push_back(std::clamp(b, 0.0, 1.0));
  }
  std::sort(breaks.begin(), breaks.end());
  breaks.erase(std::unique(breaks.begin(), breaks.end()), breaks.end());
  std::vector<GridInterval> out;
  for (size_t i = 0; i + 1 < breaks.size(); ++i) {
    const double a = breaks[i], b = breaks[i + 1];
    const double mid = 0.5 * (a + b);
    double size = targetSize;
    for (size_t r = 0; r < spans.size(); ++r) {
      if (mid > spans[r].first && mid < spans[r].second && spanSizes[r] > 0) {
        size = std::min(size, spanSizes[r]);
      }
    }
    const double len = (b - a) * edgeLength;
    // The small tolerance keeps an exact multiple (3 m / 0.5 m) from gaining a sliver.
    out.push_back({a, b, std::max(1.0, std::ceil(len / size - 1e-9))});
  }
  return out;
}

// Grid coordinates along one quad edge: every region boundary is a grid line, and each
// interval between boundaries is cut into its steps of equal length.
std::vector<double> gridLines(const std::vector<std::pair<double, double>>& spans,
                              const std::vector<double>& spanSizes, double edgeLength,
                              double targetSize) {
  std::vector<double> lines{0.0};
  for (const GridInterval& g : gridIntervals(spans, spanSizes, edgeLength, targetSize)) {
    const int n = static_cast<int>(g.steps);
    for (int k = 1; k < n; ++k) lines.push_back(g.a + (g.b - g.a) * k / n);
    lines.push_back(g.b);
  }
  lines.back() = 1.0;
  return lines;
}

// Region spans and patch sizes of a quad, along u (s) and v (t).
struct QuadSpans {
  std::vector<std::pair<double, double>> s, t;
  std::vector<double> sizes;
  explicit QuadSpans(const Quad& q) {
    for (const Region& r : q.regions) add(r.s0, r.s1, r.t0, r.t1, r.patchSize);
    for (const Refinement& r : q.refinements) add(r.s0, r.s1, r.t0, r.t1, r.patchSize);
  }
  void add(double s0, double s1, double t0, double t1, double size) {
    s.emplace_back(s0, s1);
    t.emplace_back(t0, t1);
    sizes.push_back(size);
  }
};

}  // namespace

double patchCount(const RoomDescription& room, double targetPatchSize) {
  double patches = 0;
  for (const Quad& q : room.quads) {
    const QuadSpans spans(q);
    double ns = 0, nt = 0;
    for (const GridInterval& g :
         gridIntervals(spans.s, spans.sizes, glm::length(q.edgeU), targetPatchSize)) {
      ns += g.steps;
    }
    for (const GridInterval& g :
         gridIntervals(spans.t, spans.sizes, glm::length(q.edgeV), targetPatchSize)) {
      nt += g.steps;
    }
    patches += ns * nt;
  }
  return patches;
}

namespace {

// The grid lines of one quad (buildPatchMesh's first step).
struct QuadGrid {
  std::vector<double> ss, ts;
  QuadGrid(const Quad& q, double targetPatchSize) {
    const QuadSpans spans(q);
    ss = gridLines(spans.s, spans.sizes, glm::length(q.edgeU), targetPatchSize);
    ts = gridLines(spans.t, spans.sizes, glm::length(q.edgeV), targetPatchSize);
  }
};

// Every emitting grid cell of the room as a light of the shadow-boundary test.
std::vector<LightSample> emittingCells(const RoomDescription& room, double targetPatchSize) {
  std::vector<LightSample> lights;
  for (const Quad& q : room.quads) {
    const QuadGrid grid(q, targetPatchSize);
    for (size_t j = 0; j + 1 < grid.ts.size(); ++j) {
      for (size_t i = 0; i + 1 < grid.ss.size(); ++i) {
        const double sc = 0.5 * (grid.ss[i] + grid.ss[i + 1]);
        const double tc = 0.5 * (grid.ts[j] + grid.ts[j + 1]);
        const Material& m = q.materialAt(sc, tc);
        if (!m.emits()) continue;
        const double area =
            q.area() * (grid.ss[i + 1] - grid.ss[i]) * (grid.ts[j + 1] - grid.ts[j]);
        lights.push_back({q.point(sc, tc), q.normal(), area, core::luminance(m.emission)});
      }
    }
  }
  return lights;
}

// A cell [s0, s1] x [t0, t1] of a quad's parameter square.
struct Cell {
  double s0, s1, t0, t1;
};

// The leaves of `cell`: itself, or the leaves of its four quarters while it straddles a
// shadow boundary and its longer side exceeds `size` (a relative 1e-9 absorbs the
// rounding of cells that are `size` exactly).
void shadowBoundaryLeaves(const ShadowBoundaryTest& test, const Quad& q, const Cell& cell,
                          double size, std::vector<Cell>& leaves) {
  const double longer = std::max((cell.s1 - cell.s0) * glm::length(q.edgeU),
                                 (cell.t1 - cell.t0) * glm::length(q.edgeV));
  if (!(longer > size * (1 + 1e-9)) || !test.straddles(q, cell.s0, cell.s1, cell.t0, cell.t1)) {
    leaves.push_back(cell);
    return;
  }
  const double sm = 0.5 * (cell.s0 + cell.s1), tm = 0.5 * (cell.t0 + cell.t1);
  for (const Cell& quarter : {Cell{cell.s0, sm, cell.t0, tm}, Cell{sm, cell.s1, cell.t0, tm},
                              Cell{cell.s0, sm, tm, cell.t1}, Cell{sm, cell.s1, tm, cell.t1}}) {
    shadowBoundaryLeaves(test, q, quarter, size, leaves);
  }
}

}  // namespace

PatchMesh buildPatchMesh(const RoomDescription& room, double targetPatchSize, double maxPatches) {
  if (!(targetPatchSize > 0)) {
    throw std::invalid_argument("buildPatchMesh: target patch size must be positive");
  }
  const double refineTo = room.shadowBoundaryPatchSize;
  std::optional<ShadowBoundaryTest> boundaries;
  // 2 %: the light a receiver vertex may lose to shaft pruning (ShaftBuildOptions::
  // pruneFraction), about a level of an 8-bit code in the mid-tones.
  if (refineTo > 0) boundaries.emplace(room, emittingCells(room, targetPatchSize), 0.02);
  PatchMesh mesh;
  std::vector<Cell> leaves;
  for (uint32_t qi = 0; qi < room.quads.size(); ++qi) {
    const Quad& q = room.quads[qi];
    const QuadGrid grid(q, targetPatchSize);
    const std::vector<double>& ss = grid.ss;
    const std::vector<double>& ts = grid.ts;
    const glm::dvec3 n = q.normal();
    const double quadArea = q.area();
    const uint32_t base = static_cast<uint32_t>(mesh.positions.size());
    const uint32_t ns = static_cast<uint32_t>(ss.size());
    for (double t : ts) {
      for (double s : ss) {
        mesh.positions.push_back(q.point(s, t));
        mesh.normals.push_back(n);
      }
    }
    // Vertices off the grid lines, by their exact (s, t): a cell's quarters and their
    // neighbours compute a shared corner from the same two numbers, so they find it here.
    std::map<std::pair<double, double>, uint32_t> refinedVertices;
    const auto vertexAt = [&](uint32_t i, uint32_t j, double s, double t) {
      if (s == ss[i] && t == ts[j]) return base + j * ns + i;
      const auto [at, added] =
          refinedVertices.try_emplace({s, t}, static_cast<uint32_t>(mesh.positions.size()));
      if (added) {
        mesh.positions.push_back(q.point(s, t));
        mesh.normals.push_back(n);
      }
      return at->second;
    };
    for (uint32_t j = 0; j + 1 < ts.size(); ++j) {
      for (uint32_t i = 0; i + 1 < ns; ++i) {
        const Cell cell{ss[i], ss[i + 1], ts[j], ts[j + 1]};
        leaves.clear();
        const double sc = 0.5 * (cell.s0 + cell.s1), tc = 0.5 * (cell.t0 + cell.t1);
        if (boundaries && !q.materialAt(sc, tc).emits()) {
          shadowBoundaryLeaves(*boundaries, q, cell, refineTo, leaves);
        } else {
          leaves.push_back(cell);
        }
        for (const Cell& leaf : leaves) {
          // A leaf's corners lie on the grid lines i, i + 1, j, j + 1 or between them.
          const uint32_t i1 = leaf.s1 == ss[i + 1] ? i + 1 : i,
                         j1 = leaf.t1 == ts[j + 1] ? j + 1 : j;
          const uint32_t v00 = vertexAt(i, j, leaf.s0, leaf.t0);
          const uint32_t v10 = vertexAt(i1, j, leaf.s1, leaf.t0);
          const uint32_t v01 = vertexAt(i, j1, leaf.s0, leaf.t1);
          const uint32_t v11 = vertexAt(i1, j1, leaf.s1, leaf.t1);
          const double lc = 0.5 * (leaf.s0 + leaf.s1), mc = 0.5 * (leaf.t0 + leaf.t1);
          const Material& m = q.materialAt(lc, mc);
          Patch p;
          p.centre = q.point(lc, mc);
          p.normal = n;
          p.area = quadArea * (leaf.s1 - leaf.s0) * (leaf.t1 - leaf.t0);
          p.reflectance = m.reflectance;
          p.emission = m.emission;
          p.quad = qi;
          p.firstTriangle = static_cast<uint32_t>(mesh.triangleCount());
          const uint32_t patchId = static_cast<uint32_t>(mesh.patches.size());
          mesh.patches.push_back(p);
          // Counter-clockwise about n: cross(U, U + V) = cross(U + V, V) = cross(U, V).
          mesh.indices.insert(mesh.indices.end(), {v00, v10, v11, v00, v11, v01});
          mesh.trianglePatch.push_back(patchId);
          mesh.trianglePatch.push_back(patchId);
        }
        if (double(mesh.patches.size()) > maxPatches) {
          throw std::length_error("buildPatchMesh: shadow-boundary refinement to " +
                                  std::to_string(refineTo) + " m makes more than " +
                                  std::to_string(static_cast<uint64_t>(maxPatches)) + " patches");
        }
      }
    }
  }
  return mesh;
}

core::Vec3 toVec3(const glm::dvec3& p) {
  return core::Vec3{static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
}

core::Mesh PatchMesh::toRasterMesh() const {
  core::Mesh out;
  out.positions.reserve(positions.size());
  for (const glm::dvec3& p : positions) out.positions.push_back(toVec3(p));
  out.indices = indices;
  return out;
}

double pointToPatchFormFactor(const glm::dvec3& x, const glm::dvec3& nx,
                              const glm::dvec3& patchCentre, const glm::dvec3& patchNormal,
                              double patchArea) {
  const glm::dvec3 d = patchCentre - x;
  const double r2 = glm::dot(d, d);
  if (!(r2 > 0)) return 0;
  const double r = std::sqrt(r2);
  const double cosI = glm::dot(nx, d) / r;
  const double cosJ = -glm::dot(patchNormal, d) / r;
  if (cosI <= 0 || cosJ <= 0) return 0;
  return cosI * cosJ * patchArea / (std::numbers::pi * r2 + patchArea);
}

}  // namespace penumbra::scene
