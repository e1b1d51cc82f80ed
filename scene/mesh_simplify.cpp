#include "scene/mesh_simplify.h"

#include <meshoptimizer.h>

#include <stdexcept>
#include <vector>

namespace penumbra::scene {

namespace {

std::vector<float> toFloat(const std::vector<glm::dvec3>& positions) {
  std::vector<float> out;
  out.reserve(positions.size() * 3);
  for (const glm::dvec3& p : positions) {
    out.insert(out.end(),
               {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)});
  }
  return out;
}

// Keeps only the vertices `indices` reference, in first-use order, and renumbers.
TriangleMesh compact(const std::vector<glm::dvec3>& positions,
                     const std::vector<uint32_t>& indices) {
  constexpr uint32_t kUnused = ~0u;
  std::vector<uint32_t> map(positions.size(), kUnused);
  TriangleMesh out;
  out.indices.reserve(indices.size());
  for (uint32_t i : indices) {
    if (map[i] == kUnused) {
      map[i] = static_cast<uint32_t>(out.positions.size());
      out.positions.push_back(positions[i]);
    }
    out.indices.push_back(map[i]);
  }
  return out;
}

}  // namespace

TriangleMesh weldVertices(const TriangleMesh& mesh) {
  if (mesh.positions.empty()) return {};
  const std::vector<float> fp = toFloat(mesh.positions);
  // Index-free remap over the positions alone: equal float triples share one new index,
  // numbered in order of first appearance.
  std::vector<unsigned int> remap(mesh.positions.size());
  const size_t unique =
      meshopt_generateVertexRemap(remap.data(), nullptr, mesh.positions.size(), fp.data(),
                                  mesh.positions.size(), 3 * sizeof(float));
  std::vector<glm::dvec3> positions(unique);
  for (size_t i = mesh.positions.size(); i-- > 0;) positions[remap[i]] = mesh.positions[i];
  std::vector<uint32_t> indices;
  indices.reserve(mesh.indices.size());
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    const uint32_t a = remap[mesh.indices[3 * t]], b = remap[mesh.indices[3 * t + 1]],
                   c = remap[mesh.indices[3 * t + 2]];
    // A collapsed triangle has no area to cast a shadow and confuses the quadrics.
    if (a == b || b == c || a == c) continue;
    indices.insert(indices.end(), {a, b, c});
  }
  return compact(positions, indices);
}

TriangleMesh simplifyForShadows(const TriangleMesh& mesh, size_t targetTriangles) {
  if (targetTriangles < 4) {
    throw std::invalid_argument("simplifyForShadows: target must be at least 4 triangles");
  }
  TriangleMesh welded = weldVertices(mesh);
  if (welded.triangleCount() <= targetTriangles) return welded;

  const std::vector<float> fp = toFloat(welded.positions);
  const size_t targetIndices = 3 * targetTriangles;
  std::vector<unsigned int> out(welded.indices.size());
  // target_error is relative to the mesh extent; 1 lets the collapse run all the way to
  // the triangle budget, which is the constraint that matters for a shadow proxy.
  size_t count =
      meshopt_simplify(out.data(), welded.indices.data(), welded.indices.size(), fp.data(),
                       welded.positions.size(), 3 * sizeof(float), targetIndices, 1.0f, 0, nullptr);
  out.resize(count);
  if (count > targetIndices) {
    // Borders and seams are never collapsed by meshopt_simplify; clustering has no such
    // limit. Its target is a hint, so shrink it until the result fits.
    std::vector<unsigned int> sloppy(out.size());
    for (size_t goal = targetIndices; goal >= 3; goal = goal * 9 / 10 / 3 * 3) {
      count =
          meshopt_simplifySloppy(sloppy.data(), out.data(), out.size(), fp.data(),
                                 welded.positions.size(), 3 * sizeof(float), goal, 1.0f, nullptr);
      if (count <= targetIndices) break;
    }
    if (count > targetIndices) {
      throw std::runtime_error("simplifyForShadows: cannot reach the triangle target");
    }
    sloppy.resize(count);
    out.swap(sloppy);
  }
  return compact(welded.positions, std::vector<uint32_t>(out.begin(), out.end()));
}

}  // namespace penumbra::scene
