// The project's geometry vocabulary: what every layer above core/ says a point, a transform
// and a triangle mesh are. Plain aggregates of floats in the layout the rasterizer and the
// frame-trace sidecar use, so a mesh crosses from the scene model to the rasterizer without
// conversion (design §2: core/ is the bottom layer, beside simd/).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace penumbra::core {

// Row-major 4x4: clip = M * (x, y, z, 1), element (r, c) at m[4*r + c].
struct Mat4 {
  std::array<float, 16> m{};
  static constexpr Mat4 identity() {
    Mat4 i;
    i.m[0] = i.m[5] = i.m[10] = i.m[15] = 1.0f;
    return i;
  }
  bool operator==(const Mat4&) const = default;
};

struct Vec3 {
  float x = 0, y = 0, z = 0;
  bool operator==(const Vec3&) const = default;
};

// Indexed triangles, three indices per triangle, either winding (no culling).
struct Mesh {
  std::vector<Vec3> positions;
  std::vector<uint32_t> indices;
  size_t triangleCount() const { return indices.size() / 3; }
  bool operator==(const Mesh&) const = default;
};

}  // namespace penumbra::core
