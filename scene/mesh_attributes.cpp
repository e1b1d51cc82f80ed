#include "scene/mesh_attributes.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <tuple>

#include "scene/portable_trig.h"

namespace penumbra::scene {
namespace {

// Union-find over corners; the smaller index becomes the root, so the sets (and the order
// their sums run in) depend only on the input.
class CornerSets {
 public:
  explicit CornerSets(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }
  uint32_t root(uint32_t c) {
    while (parent_[c] != c) {
      parent_[c] = parent_[parent_[c]];  // path halving
      c = parent_[c];
    }
    return c;
  }
  void join(uint32_t a, uint32_t b) {
    a = root(a);
    b = root(b);
    if (a == b) return;
    if (b < a) std::swap(a, b);
    parent_[b] = a;
  }

 private:
  std::vector<uint32_t> parent_;
};

struct Edge {
  uint32_t lo, hi;              // positions, lo < hi
  uint32_t face;                // the face it belongs to
  uint32_t cornerLo, cornerHi;  // the face's corners at lo and hi
};

uint64_t bits(double v) {
  return std::bit_cast<uint64_t>(v);
}

}  // namespace

glm::dvec3 polygonVectorArea(const PolygonSoup& soup, size_t face) {
  const uint32_t begin = soup.faceStart[face], end = soup.faceStart[face + 1];
  const glm::dvec3& a = soup.positions[soup.cornerPosition[begin]];
  glm::dvec3 sum(0.0);
  for (uint32_t k = begin + 1; k + 1 < end; ++k) {
    sum += glm::cross(soup.positions[soup.cornerPosition[k]] - a,
                      soup.positions[soup.cornerPosition[k + 1]] - a);
  }
  return sum;
}

TriangleMesh buildTriangleMesh(const PolygonSoup& soup, double creaseAngleDegrees) {
  if (!(creaseAngleDegrees >= 0 && creaseAngleDegrees <= 180)) {
    throw std::invalid_argument("buildTriangleMesh: crease angle must be in [0, 180] degrees");
  }
  const size_t faces = soup.faceCount();
  const size_t corners = soup.cornerPosition.size();
  std::vector<uint32_t> cornerFace(corners);
  std::vector<glm::dvec3> faceArea(faces);
  for (size_t f = 0; f < faces; ++f) {
    faceArea[f] = polygonVectorArea(soup, f);
    for (uint32_t k = soup.faceStart[f]; k < soup.faceStart[f + 1]; ++k) {
      cornerFace[k] = static_cast<uint32_t>(f);
    }
  }
  const auto computed = [&](uint32_t corner) { return soup.cornerNormal[corner] == kNoAttribute; };

  // Which computed-normal corners share a normal.
  CornerSets sets(corners);
  if (soup.smoothingGroups) {
    // Same position, same nonzero group.
    std::vector<uint32_t> order;
    for (uint32_t c = 0; c < corners; ++c) {
      if (computed(c) && soup.faceGroup[cornerFace[c]] != 0) order.push_back(c);
    }
    const auto key = [&](uint32_t c) {
      return std::pair(soup.cornerPosition[c], soup.faceGroup[cornerFace[c]]);
    };
    std::sort(order.begin(), order.end(),
              [&](uint32_t a, uint32_t b) { return std::pair(key(a), a) < std::pair(key(b), b); });
    for (size_t i = 1; i < order.size(); ++i) {
      if (key(order[i]) == key(order[i - 1])) sets.join(order[i - 1], order[i]);
    }
  } else {
    // Smooth edges: exactly two faces, normals within the crease angle. The cosine from the
    // portable sine and cosine (scene/portable_trig.h): the same threshold on every machine.
    double s, cosCrease;
    sinCosDegrees(creaseAngleDegrees, s, cosCrease);
    std::vector<Edge> edges;
    edges.reserve(corners);
    for (size_t f = 0; f < faces; ++f) {
      const uint32_t begin = soup.faceStart[f], end = soup.faceStart[f + 1];
      for (uint32_t k = begin; k < end; ++k) {
        const uint32_t next = k + 1 < end ? k + 1 : begin;
        const uint32_t p = soup.cornerPosition[k], q = soup.cornerPosition[next];
        if (p == q) continue;
        edges.push_back(p < q ? Edge{p, q, uint32_t(f), k, next}
                              : Edge{q, p, uint32_t(f), next, k});
      }
    }
    std::sort(edges.begin(), edges.end(), [](const Edge& a, const Edge& b) {
      return std::tie(a.lo, a.hi, a.face, a.cornerLo) < std::tie(b.lo, b.hi, b.face, b.cornerLo);
    });
    for (size_t i = 0; i < edges.size();) {
      size_t j = i + 1;
      while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
      if (j - i == 2 && edges[i].face != edges[i + 1].face) {
        const Edge &a = edges[i], &b = edges[i + 1];
        const glm::dvec3 &na = faceArea[a.face], &nb = faceArea[b.face];
        const double la = glm::length(na), lb = glm::length(nb);
        if (la > 0 && lb > 0 && glm::dot(na, nb) >= cosCrease * la * lb) {
          if (computed(a.cornerLo) && computed(b.cornerLo)) sets.join(a.cornerLo, b.cornerLo);
          if (computed(a.cornerHi) && computed(b.cornerHi)) sets.join(a.cornerHi, b.cornerHi);
        }
      }
      i = j;
    }
  }

  // Each set's normal: its faces' vector areas summed in corner order, normalized.
  std::vector<glm::dvec3> sum(corners, glm::dvec3(0.0));
  for (uint32_t c = 0; c < corners; ++c) {
    if (computed(c)) sum[sets.root(c)] += faceArea[cornerFace[c]];
  }
  std::vector<glm::dvec3> cornerNormal(corners);
  for (uint32_t c = 0; c < corners; ++c) {
    if (!computed(c)) {
      cornerNormal[c] = soup.normals[soup.cornerNormal[c]];
      continue;
    }
    const glm::dvec3& n = sum[sets.root(c)];
    const double length = glm::length(n);
    // A set of zero-area faces only (invisible): any unit normal will do.
    cornerNormal[c] = length > 0 ? n / length : glm::dvec3(0, 1, 0);
  }

  // One vertex per distinct (position, normal bits, attribute), numbered by first corner.
  std::vector<uint32_t> order(corners);
  std::iota(order.begin(), order.end(), 0u);
  const auto key = [&](uint32_t c) {
    const glm::dvec3& n = cornerNormal[c];
    return std::tuple(soup.cornerPosition[c], soup.cornerAttribute[c], bits(n.x), bits(n.y),
                      bits(n.z));
  };
  std::sort(order.begin(), order.end(),
            [&](uint32_t a, uint32_t b) { return std::pair(key(a), a) < std::pair(key(b), b); });
  std::vector<uint32_t> first(corners);  // per corner: the first corner of its vertex
  for (size_t i = 0; i < order.size(); ++i) {
    first[order[i]] = i > 0 && key(order[i]) == key(order[i - 1]) ? first[order[i - 1]] : order[i];
  }
  TriangleMesh mesh;
  std::vector<uint32_t> vertexOf(corners, kNoAttribute);
  const bool colours = !soup.reflectances.empty();
  for (uint32_t c = 0; c < corners; ++c) {
    if (vertexOf[first[c]] == kNoAttribute) {
      vertexOf[first[c]] = static_cast<uint32_t>(mesh.positions.size());
      mesh.positions.push_back(soup.positions[soup.cornerPosition[c]]);
      mesh.normals.push_back(cornerNormal[c]);
      if (colours) mesh.reflectances.push_back(soup.reflectances[soup.cornerAttribute[c]]);
    }
    vertexOf[c] = vertexOf[first[c]];
  }
  for (size_t f = 0; f < faces; ++f) {
    const uint32_t begin = soup.faceStart[f], end = soup.faceStart[f + 1];
    for (uint32_t k = begin + 1; k + 1 < end; ++k) {
      mesh.indices.insert(mesh.indices.end(), {vertexOf[begin], vertexOf[k], vertexOf[k + 1]});
    }
  }
  return mesh;
}

}  // namespace penumbra::scene
