#include "raster/closed_surface.h"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <utility>
#include <vector>

namespace penumbra::raster {

bool isClosedOutwardSurface(const core::Mesh& mesh) {
  const size_t triangles = mesh.triangleCount();
  if (triangles == 0) return false;
  // Directed edges (from, to, triangle), sorted: each must meet its reverse exactly once.
  struct DirectedEdge {
    uint32_t from, to, triangle;
  };
  std::vector<DirectedEdge> edges;
  edges.reserve(3 * triangles);
  for (uint32_t t = 0; t < triangles; ++t) {
    const uint32_t* v = &mesh.indices[3 * size_t(t)];
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) return false;
    if (std::max({v[0], v[1], v[2]}) >= mesh.positions.size()) return false;
    for (int i = 0; i < 3; ++i) edges.push_back({v[i], v[(i + 1) % 3], t});
  }
  const auto key = [](const DirectedEdge& e) { return std::pair(e.from, e.to); };
  std::sort(edges.begin(), edges.end(),
            [&](const DirectedEdge& a, const DirectedEdge& b) { return key(a) < key(b); });
  // Pieces: triangles joined across their shared edges (union-find by smaller root).
  std::vector<uint32_t> root(triangles);
  std::iota(root.begin(), root.end(), 0u);
  const auto find = [&](uint32_t t) {
    while (root[t] != t) t = root[t] = root[root[t]];
    return t;
  };
  for (size_t i = 0; i < edges.size(); ++i) {
    if (i + 1 < edges.size() && key(edges[i + 1]) == key(edges[i])) return false;  // repeated
    const std::pair<uint32_t, uint32_t> reverse(edges[i].to, edges[i].from);
    const auto it = std::lower_bound(
        edges.begin(), edges.end(), reverse,
        [&](const DirectedEdge& e, const std::pair<uint32_t, uint32_t>& k) { return key(e) < k; });
    if (it == edges.end() || key(*it) != reverse) return false;  // a boundary edge
    const uint32_t a = find(edges[i].triangle), b = find(it->triangle);
    if (a != b) root[std::max(a, b)] = std::min(a, b);
  }
  // Six times each piece's signed volume (divergence theorem: sum of a . (b x c)).
  std::vector<double> volume(triangles, 0.0);
  for (uint32_t t = 0; t < triangles; ++t) {
    const uint32_t* v = &mesh.indices[3 * size_t(t)];
    const core::Vec3 &a = mesh.positions[v[0]], &b = mesh.positions[v[1]],
                     &c = mesh.positions[v[2]];
    const double cx = double(b.y) * c.z - double(b.z) * c.y;
    const double cy = double(b.z) * c.x - double(b.x) * c.z;
    const double cz = double(b.x) * c.y - double(b.y) * c.x;
    volume[find(t)] += a.x * cx + a.y * cy + a.z * cz;
  }
  for (uint32_t t = 0; t < triangles; ++t) {
    if (find(t) == t && !(volume[t] > 0.0)) return false;
  }
  return true;
}

}  // namespace penumbra::raster
