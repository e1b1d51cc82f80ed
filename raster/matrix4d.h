// binary64 4x4 matrices: the camera's inverse and the per-pass shadow lookup matrix of the
// renderer (docs/pipeline-spec.md §7), and the check on load that a trace's camera matrix
// can be inverted (raster/frame_trace.cpp). Fixed order of operations everywhere.
#pragma once

#include <array>
#include <cmath>

#include "core/geometry.h"

namespace penumbra::raster {

using Mat4d = std::array<double, 16>;

inline Mat4d toDouble(const core::Mat4& m) {
  Mat4d d;
  for (int i = 0; i < 16; ++i) d[i] = m.m[i];
  return d;
}

inline Mat4d multiply(const Mat4d& a, const Mat4d& b) {
  Mat4d r;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) {
      r[4 * i + j] = ((a[4 * i] * b[j] + a[4 * i + 1] * b[4 + j]) + a[4 * i + 2] * b[8 + j]) +
                     a[4 * i + 3] * b[12 + j];
    }
  }
  return r;
}

// Inverse by cofactor expansion (fixed order of operations); false if singular.
inline bool invert(const Mat4d& m, Mat4d& inv) {
  auto at = [&](int r, int c) { return m[4 * r + c]; };
  auto minor3 = [&](int r0, int r1, int r2, int c0, int c1, int c2) {
    return at(r0, c0) * (at(r1, c1) * at(r2, c2) - at(r1, c2) * at(r2, c1)) -
           at(r0, c1) * (at(r1, c0) * at(r2, c2) - at(r1, c2) * at(r2, c0)) +
           at(r0, c2) * (at(r1, c0) * at(r2, c1) - at(r1, c1) * at(r2, c0));
  };
  Mat4d cof;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      int rows[3], cols[3];
      for (int i = 0, k = 0; i < 4; ++i) {
        if (i != r) rows[k++] = i;
      }
      for (int i = 0, k = 0; i < 4; ++i) {
        if (i != c) cols[k++] = i;
      }
      const double minor = minor3(rows[0], rows[1], rows[2], cols[0], cols[1], cols[2]);
      cof[4 * r + c] = ((r + c) % 2 == 0) ? minor : -minor;
    }
  }
  const double det = ((m[0] * cof[0] + m[1] * cof[1]) + m[2] * cof[2]) + m[3] * cof[3];
  if (!(det != 0.0) || !std::isfinite(det)) return false;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) inv[4 * r + c] = cof[4 * c + r] / det;  // adjugate / det
  }
  return true;
}

}  // namespace penumbra::raster
