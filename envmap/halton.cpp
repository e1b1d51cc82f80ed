#include "envmap/halton.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace penumbra::envmap {

double radicalInverse(uint64_t index, uint32_t base) {
  // Base 0 divides by zero and base 1 never ends (index / 1 == index).
  if (base < 2) throw std::invalid_argument("radicalInverse: base must be at least 2");
  const double inverseBase = 1.0 / base;
  double scale = inverseBase, value = 0;
  while (index > 0) {
    value += double(index % base) * scale;
    index /= base;
    scale *= inverseBase;
  }
  return value;
}

glm::dvec2 haltonPoint(uint64_t index) {
  return {radicalInverse(index, 2), radicalInverse(index, 3)};
}

namespace {

// Lloyd's relaxation, one step (Havran 2005 §3.2, after Hiller, Deussen & Keller 2001),
// discretised: grid cell centres are given to their nearest point and each point moves to the
// mean of its cells. A bucket grid of the points bounds the nearest-point search: rings of
// buckets are searched outwards until no unsearched bucket can hold a nearer point.
std::vector<glm::dvec2> lloydStep(const std::vector<glm::dvec2>& points, uint32_t gridPerPoint) {
  const size_t n = points.size();
  const uint32_t buckets = std::max<uint32_t>(1, uint32_t(std::ceil(std::sqrt(double(n)))));
  std::vector<std::vector<uint32_t>> bucket(size_t(buckets) * buckets);
  auto bucketOf = [&](double x) { return std::min<uint32_t>(buckets - 1, uint32_t(x * buckets)); };
  for (uint32_t i = 0; i < n; ++i)
    bucket[size_t(bucketOf(points[i].y)) * buckets + bucketOf(points[i].x)].push_back(i);

  const uint32_t grid = buckets * gridPerPoint;
  std::vector<glm::dvec2> sum(n, glm::dvec2(0.0));
  std::vector<uint64_t> cells(n, 0);
  const double bucketSize = 1.0 / buckets;
  for (uint32_t gy = 0; gy < grid; ++gy) {
    const double y = (gy + 0.5) / grid;
    for (uint32_t gx = 0; gx < grid; ++gx) {
      const double x = (gx + 0.5) / grid;
      const int bx = int(bucketOf(x)), by = int(bucketOf(y));
      double best = std::numeric_limits<double>::infinity();
      uint32_t bestIndex = 0;
      for (int ring = 0; ring <= int(buckets); ++ring) {
        // Every point in ring `ring` or beyond is at least (ring − 1) buckets away.
        const double reach = (ring - 1) * bucketSize;
        if (ring > 1 && reach * reach > best) break;
        for (int qy = by - ring; qy <= by + ring; ++qy) {
          for (int qx = bx - ring; qx <= bx + ring; ++qx) {
            if (std::max(std::abs(qx - bx), std::abs(qy - by)) != ring) continue;
            if (qx < 0 || qy < 0 || qx >= int(buckets) || qy >= int(buckets)) continue;
            for (uint32_t i : bucket[size_t(qy) * buckets + qx]) {
              const double dx = points[i].x - x, dy = points[i].y - y;
              const double d = dx * dx + dy * dy;
              if (d < best || (d == best && i < bestIndex)) {
                best = d;
                bestIndex = i;
              }
            }
          }
        }
      }
      sum[bestIndex] += glm::dvec2(x, y);
      ++cells[bestIndex];
    }
  }
  std::vector<glm::dvec2> relaxed(points);
  for (size_t i = 0; i < n; ++i)
    if (cells[i] > 0) relaxed[i] = sum[i] / double(cells[i]);
  return relaxed;
}

}  // namespace

SamplePattern::SamplePattern(uint32_t count, bool relaxed, uint32_t gridPerPoint) {
  if (count == 0) throw std::invalid_argument("SamplePattern: the light count must be at least 1");
  if (gridPerPoint == 0)
    throw std::invalid_argument("SamplePattern: gridPerPoint must be at least 1");
  points_.reserve(count);
  for (uint32_t i = 1; i <= count; ++i) points_.push_back(haltonPoint(i));
  if (relaxed) points_ = lloydStep(points_, gridPerPoint);
}

}  // namespace penumbra::envmap
