#include "shadow/static_room_visibility.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra::shadow {
namespace {

constexpr double kShellTolerance = 1e-3;  // metres: a vertex this far behind a plane is "on" it
constexpr double kLift = 1e-3;            // metres along the normal: off the vertex's own surface
constexpr int kCells = StaticRoomVisibility::kGrid * StaticRoomVisibility::kGrid;

// The cell centres' directions, once.
std::array<glm::dvec3, kCells> cellDirections() {
  std::array<glm::dvec3, kCells> d{};
  size_t cell = 0;  // j * kGrid + i
  for (int j = 0; j < StaticRoomVisibility::kGrid; ++j) {
    for (int i = 0; i < StaticRoomVisibility::kGrid; ++i) {
      d[cell++] = StaticRoomVisibility::cellDirection(i, j);
    }
  }
  return d;
}

bool rayHitsBox(const glm::dvec3& o, const glm::dvec3& d, const glm::dvec3& lo,
                const glm::dvec3& hi) {
  double near = 0, far = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0) {
      if (o[a] < lo[a] || o[a] > hi[a]) return false;
      continue;
    }
    double t0 = (lo[a] - o[a]) / d[a], t1 = (hi[a] - o[a]) / d[a];
    if (t0 > t1) std::swap(t0, t1);
    near = std::max(near, t0);
    far = std::min(far, t1);
    if (near > far) return false;
  }
  return true;
}

}  // namespace

glm::dvec3 StaticRoomVisibility::cellDirection(int i, int j) {
  const double s = -1 + (2.0 * i + 1) / kGrid, t = -1 + (2.0 * j + 1) / kGrid;
  const double u = 0.5 * (s + t), w = 0.5 * (s - t);
  // |u| + |w| = max(|s|, |t|) <= 1: y >= 0, on the upper hemisphere's octahedron.
  return glm::normalize(glm::dvec3(u, 1 - std::abs(u) - std::abs(w), w));
}

StaticRoomVisibility::Lookup StaticRoomVisibility::lookup(const glm::dvec3& towardsLight) {
  const double y = std::max(0.0, towardsLight.y);
  const double norm = std::abs(towardsLight.x) + y + std::abs(towardsLight.z);
  const double u = norm > 0 ? towardsLight.x / norm : 0, w = norm > 0 ? towardsLight.z / norm : 0;
  // Cell i's centre sits at (s + 1) kGrid / 2 - 1/2 = i: the bilinear cell and fraction.
  const auto place = [](double c, int& first, double& fraction) {
    const double f = std::clamp((c + 1) * kGrid / 2 - 0.5, 0.0, double(kGrid - 1));
    first = std::min(static_cast<int>(f), kGrid - 2);
    fraction = f - first;
  };
  int i = 0, j = 0;
  double a = 0, b = 0;
  place(u + w, i, a);
  place(u - w, j, b);
  Lookup l;
  l.cell = {uint16_t(j * kGrid + i), uint16_t(j * kGrid + i + 1), uint16_t((j + 1) * kGrid + i),
            uint16_t((j + 1) * kGrid + i + 1)};
  l.weight = {(1 - a) * (1 - b), a * (1 - b), (1 - a) * b, a * b};
  return l;
}

StaticRoomVisibility::StaticRoomVisibility(const scene::PatchMesh& mesh,
                                           std::span<const uint32_t> receiverVertices,
                                           core::JobPool* pool) {
  // Shell or occluder, per patch (its two triangles share its plane): the lowest any room
  // vertex lies along the patch's normal, measured from its centre.
  std::vector<uint8_t> occluderPatch(mesh.patches.size(), 0);
  core::forEachChunk(pool, mesh.patches.size(), 64, [&](size_t begin, size_t end, int) {
    for (size_t p = begin; p < end; ++p) {
      const scene::Patch& patch = mesh.patches[p];
      double lowest = 0;
      for (const glm::dvec3& v : mesh.positions) {
        lowest = std::min(lowest, glm::dot(v - patch.centre, patch.normal));
      }
      occluderPatch[p] = lowest < -kShellTolerance;
    }
  });
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    if (!occluderPatch[mesh.trianglePatch[t]]) continue;
    const glm::dvec3& a = mesh.positions[mesh.indices[3 * t]];
    occluders_.push_back({a, mesh.positions[mesh.indices[3 * t + 1]] - a,
                          mesh.positions[mesh.indices[3 * t + 2]] - a});
  }
  for (size_t first = 0; first < occluders_.size(); first += kRun) {
    Run run{glm::dvec3(std::numeric_limits<double>::infinity()),
            glm::dvec3(-std::numeric_limits<double>::infinity()), uint32_t(first),
            uint32_t(std::min(kRun, occluders_.size() - first))};
    for (size_t k = first; k < first + run.count; ++k) {
      const Triangle& tri = occluders_[k];
      for (const glm::dvec3& p : {tri.a, tri.a + tri.edge1, tri.a + tri.edge2}) {
        run.lo = glm::min(run.lo, p);
        run.hi = glm::max(run.hi, p);
      }
    }
    runs_.push_back(run);
  }

  const auto directions = cellDirections();
  bits_.assign(receiverVertices.size() * kWords, 0);
  blocked_.assign(receiverVertices.size(), 0);
  // Each vertex writes only its own words: the same bits on any pool.
  core::forEachChunk(pool, receiverVertices.size(), 16, [&](size_t begin, size_t end, int) {
    for (size_t r = begin; r < end; ++r) {
      const uint32_t v = receiverVertices[r];
      const glm::dvec3 origin = mesh.positions[v] + kLift * mesh.normals[v];
      uint16_t blocked = 0;
      for (size_t c = 0; c < directions.size(); ++c) {
        if (occluders_.empty() || !occluded(origin, directions[c])) {
          bits_[r * kWords + c / 64] |= uint64_t{1} << (c % 64);
        } else {
          ++blocked;
        }
      }
      blocked_[r] = blocked;
    }
  });
}

bool StaticRoomVisibility::occluded(const glm::dvec3& origin, const glm::dvec3& d) const {
  for (const Run& run : runs_) {
    if (!rayHitsBox(origin, d, run.lo, run.hi)) continue;
    for (uint32_t k = run.first; k < run.first + run.count; ++k) {
      // Moller & Trumbore 1997, two-sided.
      const Triangle& tri = occluders_[k];
      const glm::dvec3 p = glm::cross(d, tri.edge2);
      const double det = glm::dot(tri.edge1, p);
      if (det == 0) continue;  // the ray runs in the triangle's plane
      const double inv = 1 / det;
      const glm::dvec3 s = origin - tri.a;
      const double u = glm::dot(s, p) * inv;
      if (u < 0 || u > 1) continue;
      const glm::dvec3 q = glm::cross(s, tri.edge1);
      const double v = glm::dot(d, q) * inv;
      if (v < 0 || u + v > 1) continue;
      if (glm::dot(tri.edge2, q) * inv > 0) return true;
    }
  }
  return false;
}

double StaticRoomVisibility::visibility(uint32_t r, const Lookup& l) const {
  if (blocked_[r] == 0) return 1;
  double seen = 0;
  for (size_t k = 0; k < 4; ++k) {
    if (bits_[r * kWords + l.cell[k] / 64] >> (l.cell[k] % 64) & 1) seen += l.weight[k];
  }
  return seen;
}

size_t StaticRoomVisibility::partlyBlockedVertices() const {
  return size_t(std::count_if(blocked_.begin(), blocked_.end(), [](uint16_t b) { return b > 0; }));
}

}  // namespace penumbra::shadow
