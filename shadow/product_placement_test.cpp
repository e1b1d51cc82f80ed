// Product placement: the mesh and proxy moved by the pose (placeMesh), the bounds of the
// placed mesh, and placement redone only when the pose or the model changes.
#include "shadow/product_placement.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

namespace penumbra::shadow {
namespace {

// A box 1 m wide (x), 0.5 m deep (z), 1 m high, standing on y = 0; its proxy one triangle.
std::vector<ProductModel> boxProduct() {
  ProductModel m;
  m.name = "box";
  for (float y : {0.0f, 1.0f}) {
    for (float z : {-0.25f, 0.25f}) {
      for (float x : {-0.5f, 0.5f}) m.mesh.positions.push_back({x, y, z});
    }
  }
  m.mesh.indices = {0, 1, 2, 1, 3, 2, 4, 5, 6, 5, 7, 6, 0, 1, 5, 0, 5, 4};
  m.proxy.positions = {{-0.5f, 0, 0}, {0.5f, 0, 0}, {0, 1, 0}};
  m.proxy.indices = {0, 1, 2};
  return {m, m};
}

TEST(ProductPlacement, MeshAndProxyAreMovedByThePoseAndBounded) {
  const std::vector<ProductModel> products = boxProduct();
  ProductPlacement placement(products);
  const ProductPose pose{0, 2.0f, -1.0f, 90.0f, 0.5f};
  EXPECT_EQ(placement.place(pose), PlacementChange::kNewModel);
  core::Mesh mesh, proxy;
  placeMesh(products[0].mesh, pose, mesh);
  placeMesh(products[0].proxy, pose, proxy);
  EXPECT_EQ(placement.mesh(), mesh);
  EXPECT_EQ(placement.proxy(), proxy);
  // Turned a quarter: the box's 1 m width lies along z, lifted 0.5 m, centred on (2, -1).
  const scene::Aabb& b = placement.bounds();
  EXPECT_NEAR(b.min.x, 1.75, 1e-6);
  EXPECT_NEAR(b.max.x, 2.25, 1e-6);
  EXPECT_NEAR(b.min.y, 0.5, 1e-6);
  EXPECT_NEAR(b.max.y, 1.5, 1e-6);
  EXPECT_NEAR(b.min.z, -1.5, 1e-6);
  EXPECT_NEAR(b.max.z, -0.5, 1e-6);
  for (const core::Vec3& p : placement.mesh().positions) {
    EXPECT_TRUE(p.x >= b.min.x && p.x <= b.max.x && p.z >= b.min.z && p.z <= b.max.z);
  }
  EXPECT_EQ(placement.pose().product, 0u);
}

TEST(ProductPlacement, PlacesAgainOnlyWhenThePoseOrTheModelChanges) {
  std::vector<ProductModel> products = boxProduct();
  ProductPlacement placement(products);
  ProductPose pose{0, 1.0f, 1.0f, 0.0f, 0.0f};
  EXPECT_EQ(placement.place(pose), PlacementChange::kNewModel);
  EXPECT_EQ(placement.place(pose), PlacementChange::kNone);
  pose.yawDegrees = 10.0f;
  EXPECT_EQ(placement.place(pose), PlacementChange::kMoved);
  placement.modelChanged(1);  // not the placed one
  EXPECT_EQ(placement.place(pose), PlacementChange::kNone);
  // The owner replaces the model; the placement sees it once told.
  for (core::Vec3& p : products[0].mesh.positions) p.y *= 2.0f;
  placement.modelChanged(0);
  EXPECT_EQ(placement.place(pose), PlacementChange::kNewModel);
  EXPECT_NEAR(placement.bounds().max.y, 2.0, 1e-6);
  pose.product = 1;
  EXPECT_EQ(placement.place(pose), PlacementChange::kNewModel);
  EXPECT_NEAR(placement.bounds().max.y, 1.0, 1e-6);
}

TEST(ProductPlacement, RefusesUnknownProductsAndPosesThatAreNotFinite) {
  const std::vector<ProductModel> products = boxProduct();
  ProductPlacement placement(products);
  EXPECT_THROW(placement.place({2, 0, 0, 0, 0}), std::invalid_argument);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_THROW(placement.place({0, nan, 0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(placement.place({0, 0, 0, inf, 0}), std::invalid_argument);
  EXPECT_THROW(placement.place({0, 0, 0, 0, -inf}), std::invalid_argument);
  // A refused pose leaves nothing placed.
  EXPECT_EQ(placement.place({0, 0, 0, 0, 0}), PlacementChange::kNewModel);
}

}  // namespace
}  // namespace penumbra::shadow
