#include "scene/hole_capping.h"

#include <algorithm>
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace penumbra::scene {

std::optional<size_t> capHoles(TriangleMesh& mesh) {
  // Directed edges, with a count: an edge used twice in one direction is not a surface.
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> directed;
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    const uint32_t* v = &mesh.indices[3 * t];
    for (int i = 0; i < 3; ++i) {
      if (++directed[{v[i], v[(i + 1) % 3]}] > 1) return std::nullopt;
    }
  }
  // The boundary: each boundary vertex must start exactly one boundary edge.
  std::map<uint32_t, uint32_t> next;
  for (const auto& [edge, count] : directed) {
    if (directed.count({edge.second, edge.first}) != 0) continue;
    if (!next.emplace(edge.first, edge.second).second) return std::nullopt;
  }
  std::vector<uint32_t> indices = mesh.indices;
  std::vector<glm::dvec3> positions = mesh.positions;
  size_t loops = 0;
  while (!next.empty()) {
    // Walk one loop from its smallest vertex (the map's order: deterministic).
    const uint32_t start = next.begin()->first;
    std::vector<uint32_t> loop;
    for (uint32_t v = start;;) {
      const auto it = next.find(v);
      if (it == next.end()) return std::nullopt;  // runs into a vertex already used
      loop.push_back(v);
      v = it->second;
      next.erase(it);
      if (v == start) break;
    }
    glm::dvec3 centre(0.0);
    for (const uint32_t v : loop) centre += positions[v];
    centre /= double(loop.size());
    const auto c = static_cast<uint32_t>(positions.size());
    positions.push_back(centre);
    for (size_t i = 0; i < loop.size(); ++i) {
      const uint32_t a = loop[i], b = loop[(i + 1) % loop.size()];
      indices.insert(indices.end(), {b, a, c});
    }
    ++loops;
  }
  mesh.positions = std::move(positions);
  mesh.indices = std::move(indices);
  mesh.normals.clear();
  mesh.reflectances.clear();
  return loops;
}

}  // namespace penumbra::scene
