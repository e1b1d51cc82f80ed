#include "kiosk/environment_inset.h"

#include <algorithm>
#include <cmath>

#include "scene/portable_trig.h"

namespace penumbra::kiosk {

EnvironmentInset::EnvironmentInset(uint32_t size, uint32_t cols, uint32_t rows)
    : size_(size), cols_(cols), rows_(rows) {
  // Column c spans azimuths [c, c + 1) / cols of a turn. Its lower boundary direction:
  std::vector<double> bx(cols), by(cols);
  for (uint32_t c = 0; c < cols; ++c) {
    scene::sinCosDegrees(360.0 * c / cols, by[c], bx[c]);
  }
  const uint32_t half = cols / 2;  // boundaries 0..half lie in the upper half-plane (y >= 0)
  for (uint32_t y = 0; y < size; ++y) {
    for (uint32_t x = 0; x < size; ++x) {
      const double px = (2.0 * x + 1.0) / size - 1.0, py = (2.0 * y + 1.0) / size - 1.0;
      const double u = px * px + py * py;
      if (!(u < 1.0)) continue;
      const uint32_t row = std::min(rows - 1, static_cast<uint32_t>(u * rows));
      // The last boundary at or before p's azimuth: within a half-plane the sign of
      // cross(b_c, p) falls monotonically from + to − as c passes p, so a binary search on it
      // finds the column (exact comparisons of IEEE products).
      const bool upper = py > 0 || (py == 0 && px > 0);
      uint32_t lo = upper ? 0 : half, hi = upper ? half : cols;  // p in [lo, hi)
      while (hi - lo > 1) {
        const uint32_t mid = lo + (hi - lo) / 2;
        if (bx[mid] * py - by[mid] * px >= 0) {
          lo = mid;
        } else {
          hi = mid;
        }
      }
      inset_.push_back(y * size + x);
      source_.push_back(row * cols + lo);
    }
  }
  disc_ = core::ImageF(static_cast<uint32_t>(source_.size()), 1);
}

void EnvironmentInset::draw(const envmap::HemisphereMap& map,
                            std::span<const envmap::DirectionalLight> lights,
                            const glm::dmat3& toWorld, std::span<uint8_t> rgba, uint32_t width,
                            uint32_t height, int x0, int y0) {
  if (map.cols() != cols_ || map.rows() != rows_) {
    throw envmap::ToneMapError("environment inset: a " + std::to_string(map.cols()) + "x" +
                               std::to_string(map.rows()) + " map, not " + std::to_string(cols_) +
                               "x" + std::to_string(rows_));
  }
  for (size_t i = 0; i < source_.size(); ++i) {
    const float* p = &map.radiance.pixels[3 * size_t(source_[i])];
    std::copy(p, p + 3, &disc_.pixels[3 * i]);
  }
  const core::Image8 shown = tone_.map(disc_, "environment inset");
  const auto put = [&](int x, int y, uint8_t r, uint8_t g, uint8_t b) {
    if (x < 0 || y < 0 || x >= int(width) || y >= int(height)) return;
    uint8_t* q = &rgba[4 * (size_t(y) * width + size_t(x))];
    q[0] = r, q[1] = g, q[2] = b;
  };
  for (size_t i = 0; i < inset_.size(); ++i) {
    const uint8_t* c = &shown.pixels[3 * i];
    put(x0 + int(inset_[i] % size_), y0 + int(inset_[i] / size_), c[0], c[1], c[2]);
  }
  // Each light where the disc shows its direction: hemisphere_map.h's map inverted,
  // r² = 1 − z and (x, y) = d.xy / √(2 − r²).
  const glm::dmat3 toCamera = glm::transpose(toWorld);
  for (const envmap::DirectionalLight& l : lights) {
    const glm::dvec3 d = toCamera * l.direction;
    if (!(d.z >= 0)) continue;
    const double scale = 1.0 / std::sqrt(1.0 + d.z);  // √(2 − r²) = √(1 + z)
    const int cx = x0 + static_cast<int>((d.x * scale + 1.0) * 0.5 * size_);
    const int cy = y0 + static_cast<int>((d.y * scale + 1.0) * 0.5 * size_);
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) put(cx + dx, cy + dy, 255, 220, 0);
  }
}

}  // namespace penumbra::kiosk
