// Ray casting against the static room (Gibson 2003 §5: "point-to-patch visibility obtained
// using ray-casting"), as a thin RAII wrapper over an Embree 3 device and scene holding a
// PatchMesh's triangles.
//
// Determinism (docs/design.md §3): a query's answer depends only on the ray and the
// triangles — the watertight triangle test is per triangle and robust-mode box tests are
// conservative, so the BVH's shape changes only the visiting order. An occlusion query
// ("any hit") is therefore order-independent. A nearest-hit query can tie between two
// triangles at the same t (a ray through a shared edge), and which one wins follows the
// BVH; the device is built with one build thread by default so the BVH itself, and hence
// the winner, is the same on every run. Queries may be issued from any number of threads
// at once.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <span>

#include <glm/glm.hpp>

#include "scene/patch_mesh.h"

// Embree's handles, forward-declared so users of this header need not include Embree.
typedef struct RTCDeviceTy* RTCDevice;
typedef struct RTCSceneTy* RTCScene;

namespace penumbra::lighting {

struct EmbreeSceneOptions {
  // RTC_SCENE_FLAG_ROBUST: no ray slips through a shared edge. Shadow rays towards patch
  // samples pass close to mesh edges all the time, so this stays on unless measured.
  bool robust = true;
  // Embree's build threads. One keeps the BVH — and so nearest-hit tie breaks — identical
  // across runs and machines; rooms of a few thousand triangles build in microseconds.
  unsigned buildThreads = 1;
  // Metres cut from both ends of an occlusion segment, so the surfaces the segment starts
  // and ends on do not count as blockers.
  double segmentEpsilon = 1e-4;
};

struct Hit {
  uint32_t triangle = 0;  // index into PatchMesh triangles (indices / 3)
  double t = 0;           // ray parameter, distance when the direction is unit length
  // Barycentric coordinates of the hit (Embree's): the point is (1 - u - v) p0 + u p1 + v p2.
  double u = 0, v = 0;
};

struct Segment {
  glm::dvec3 origin{0.0}, target{0.0};
};

class EmbreeScene {
 public:
  // Builds and commits the scene from the mesh's positions (rounded to float once) and
  // triangles. Throws std::runtime_error when Embree fails, std::invalid_argument for an
  // index out of range.
  explicit EmbreeScene(const scene::PatchMesh& mesh, const EmbreeSceneOptions& options = {});
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;
  EmbreeScene(EmbreeScene&& other) noexcept;
  EmbreeScene& operator=(EmbreeScene&& other) noexcept;

  // True when a triangle crosses the segment from `origin` to `target`, each end pulled
  // in by options.segmentEpsilon. A segment no longer than twice that is never occluded.
  bool occluded(const glm::dvec3& origin, const glm::dvec3& target) const;
  // occluded() for each segment; `out` must have the same length (1 = occluded).
  // Throws std::invalid_argument on a length mismatch.
  void occluded(std::span<const Segment> segments, std::span<uint8_t> out) const;
  // Nearest triangle hit with t in [tMin, tMax]; `dir` need not be unit length.
  std::optional<Hit> intersect(const glm::dvec3& origin, const glm::dvec3& dir, double tMin = 0,
                               double tMax = std::numeric_limits<double>::infinity()) const;

  size_t triangleCount() const { return triangleCount_; }
  const EmbreeSceneOptions& options() const { return options_; }

 private:
  void release() noexcept;

  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
  size_t triangleCount_ = 0;
  EmbreeSceneOptions options_;
};

}  // namespace penumbra::lighting
