#include "scene/mesh_simplify.h"

#include <meshoptimizer.h>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <vector>

#include "scene/hole_capping.h"

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

// The point of triangle abc closest to p, by the Voronoi regions of its vertices, edges
// and face (Ericson, Real-Time Collision Detection, 2005, §5.1.5).
glm::dvec3 closestPointOnTriangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                  const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
    return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
  }
  const double scale = 1 / (va + vb + vc);
  return a + ab * (vb * scale) + ac * (vc * scale);
}

}  // namespace

double medianDistanceOutside(const TriangleMesh& model, const TriangleMesh& proxy) {
  if (model.positions.empty() || proxy.triangleCount() == 0) return 0;
  std::vector<double> distances;
  distances.reserve(model.positions.size());
  for (const glm::dvec3& p : model.positions) {
    double best = std::numeric_limits<double>::infinity(), signedBest = 0;
    for (size_t t = 0; t < proxy.triangleCount(); ++t) {
      const glm::dvec3& a = proxy.positions[proxy.indices[3 * t]];
      const glm::dvec3& b = proxy.positions[proxy.indices[3 * t + 1]];
      const glm::dvec3& c = proxy.positions[proxy.indices[3 * t + 2]];
      const glm::dvec3 q = closestPointOnTriangle(p, a, b, c);
      const double d = glm::length(p - q);
      // Strictly closer: the first triangle in index order wins a tie, so the sign at a
      // shared edge does not depend on anything but the proxy.
      if (d < best) {
        best = d;
        signedBest = glm::dot(p - q, glm::cross(b - a, c - a)) >= 0 ? d : -d;
      }
    }
    distances.push_back(signedBest);
  }
  const auto middle = distances.begin() + static_cast<std::ptrdiff_t>(distances.size() / 2);
  std::nth_element(distances.begin(), middle, distances.end());
  return *middle;
}

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

TriangleMesh simplifyForShadows(const TriangleMesh& mesh, size_t targetTriangles, bool solid) {
  if (targetTriangles < 4) {
    throw std::invalid_argument("simplifyForShadows: target must be at least 4 triangles");
  }
  TriangleMesh welded = weldVertices(mesh);
  if (solid) capHoles(welded);  // unchanged when its boundary is not simple loops
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
  TriangleMesh proxy = compact(welded.positions, std::vector<uint32_t>(out.begin(), out.end()));

  // A proxy on the model's own vertices lies inside a convex stretch of it (every chord
  // of a convex curve is inside), so its shadow is slightly small: the bunny's contact
  // band measured 1.3-2.0 levels too light at 50 passes (docs/accuracy.md). Pushing each
  // vertex out along its area-weighted normal by the median outward distance of the
  // model's vertices puts as much of the model outside the proxy as inside: an unbiased
  // silhouette. Only outward: a proxy already biased outward (median <= 0) is kept.
  const double offset = medianDistanceOutside(welded, proxy);
  if (offset > 0) {
    std::vector<glm::dvec3> normals(proxy.positions.size(), glm::dvec3(0));
    for (size_t t = 0; t < proxy.triangleCount(); ++t) {
      const uint32_t* v = &proxy.indices[3 * t];
      const glm::dvec3 n = glm::cross(proxy.positions[v[1]] - proxy.positions[v[0]],
                                      proxy.positions[v[2]] - proxy.positions[v[0]]);
      for (int k = 0; k < 3; ++k) normals[v[k]] += n;
    }
    for (size_t i = 0; i < normals.size(); ++i) {
      const double length = glm::length(normals[i]);
      if (length > 0) proxy.positions[i] += normals[i] * (offset / length);
    }
  }
  return proxy;
}

}  // namespace penumbra::scene
