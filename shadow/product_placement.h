// Product placement (design §1, per frame step 2): the product's display mesh and its shadow
// proxy (Gibson 2003 §7.2) moved from product space to the pose in the room, and the world
// bounding box of the placed mesh — the box the shaft traversal (§6.1) tests and the light
// frusta (§7.2) enclose, and the normals the product is shaded with. Placement is redone only
// when the pose or the model changes.
// Cost: one placeMesh() of the mesh and of each proxy and one placeNormals() when it moves;
// nothing otherwise.
#pragma once

#include <cstdint>
#include <vector>

#include "raster/frame_trace.h"
#include "scene/patch_mesh.h"
#include "shadow/scene_bundle.h"

namespace penumbra::shadow {

// What place() did.
enum class PlacementChange {
  kNone,      // the same pose of the same model: nothing to do
  kMoved,     // the same model, a new pose
  kNewModel,  // another product, or its model was replaced (modelChanged)
};

class ProductPlacement {
 public:
  // `products` (the bundle's) must outlive the placement.
  explicit ProductPlacement(const std::vector<ProductModel>& products) : products_(products) {}

  // Places the product of `pose` unless it already stands there. Throws
  // std::invalid_argument for an unknown product or a pose that is not finite.
  PlacementChange place(const ProductPose& pose);
  // Product `product`'s model was replaced: when it is the placed one, the next place()
  // places it afresh and reports kNewModel.
  void modelChanged(uint32_t product);

  const ProductPose& pose() const { return pose_; }
  const core::Mesh& mesh() const { return mesh_; }  // world space
  // Per mesh vertex, world space: the model's normals turned by the yaw, or area-weighted
  // face-normal sums for a model without them (shadingNormals).
  const std::vector<glm::vec3>& normals() const { return normals_; }
  const core::Mesh& proxy() const { return proxy_; }          // world space
  const core::Mesh& fineProxy() const { return fineProxy_; }  // world space; may be empty
  // Whether the proxy and the fine proxy are closed surfaces wound counter-clockwise from
  // outside (raster::isClosedOutwardSurface; placing turns and moves, so it keeps that).
  bool proxyClosed() const { return proxyClosed_; }
  bool fineProxyClosed() const { return fineProxyClosed_; }
  const scene::Aabb& bounds() const { return bounds_; }  // of mesh()

 private:
  const std::vector<ProductModel>& products_;
  ProductPose pose_{~0u, 0, 0, 0};
  core::Mesh mesh_, proxy_, fineProxy_;
  bool proxyClosed_ = false, fineProxyClosed_ = false;
  std::vector<glm::vec3> normals_;
  scene::Aabb bounds_;
};

}  // namespace penumbra::shadow
