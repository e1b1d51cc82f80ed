#include "shadow/product_placement.h"

#include "raster/closed_surface.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace penumbra::shadow {

PlacementChange ProductPlacement::place(const ProductPose& pose) {
  if (pose.product == pose_.product && pose.x == pose_.x && pose.z == pose_.z &&
      pose.yawDegrees == pose_.yawDegrees && pose.lift == pose_.lift) {
    return PlacementChange::kNone;
  }
  if (pose.product >= products_.size()) {
    throw std::invalid_argument("product " + std::to_string(pose.product) + " does not exist (" +
                                std::to_string(products_.size()) + " products)");
  }
  if (!std::isfinite(pose.x) || !std::isfinite(pose.z) || !std::isfinite(pose.yawDegrees) ||
      !std::isfinite(pose.lift)) {
    throw std::invalid_argument("product pose is not finite");
  }
  const PlacementChange change =
      pose.product != pose_.product ? PlacementChange::kNewModel : PlacementChange::kMoved;
  const ProductModel& model = products_[pose.product];
  if (change == PlacementChange::kNewModel) {
    proxyClosed_ = raster::isClosedOutwardSurface(model.proxy);
    fineProxyClosed_ = raster::isClosedOutwardSurface(model.fineProxy);
  }
  placeMesh(model.mesh, pose, mesh_);
  placeMesh(model.proxy, pose, proxy_);
  placeMesh(model.fineProxy, pose, fineProxy_);
  normals_ = shadingNormals(model, mesh_, pose);
  bounds_ = scene::Aabb::emptyBox();
  for (const core::Vec3& p : mesh_.positions) bounds_.extend({p.x, p.y, p.z});
  pose_ = pose;
  return change;
}

void ProductPlacement::modelChanged(uint32_t product) {
  if (product == pose_.product) pose_.product = ~0u;  // place() re-places it
}

}  // namespace penumbra::shadow
