// Occlusion feedback: shares of blocked light and per-source occlusion recorded from the
// renderer's masks, and the per-cluster shares read back from them (docs/fig3.md).
#include "shadow/occlusion_feedback.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace penumbra::shadow {
namespace {

// Two clusters over three sources: k0 = {0, 2}, k1 = {1}.
ClusterSelection twoClusters() {
  ClusterSelection s;
  s.clusters = {SourceCluster{0, 0, 0, 2, 0, 0}, SourceCluster{1, 1, 2, 1, 0, 0}};
  s.sources = {0, 2, 1};
  return s;
}

const glm::dvec3 kGrey{1.0, 1.0, 1.0};  // transferWeight 1 (the weights sum to one)

struct Frame {
  ClusterSelection selection = twoClusters();
  std::vector<uint32_t> passCluster{0, 1};
  std::vector<uint32_t> receiverVertices{2, 0};  // probe 0 is vertex 2, probe 1 vertex 0
  // Probe 0: k0 weight 1, k1 weight 3; probe 1: k0 nothing, k1 weight 2.
  std::vector<glm::dvec3> receiverTransfers{kGrey, 3.0 * kGrey, glm::dvec3(0.0), 2.0 * kGrey};
  std::vector<glm::dvec3> productTransfers{kGrey, kGrey};
  ObservedFrame observed() const {
    return {passCluster, &selection, receiverVertices, receiverTransfers, productTransfers, 1};
  }
};

std::vector<double> sharesOf(const OcclusionFeedback& feedback, size_t first, size_t clusters,
                             float fallback) {
  std::vector<double> q(clusters);
  feedback.clusterShares(first, fallback, q);
  return q;
}

TEST(OcclusionFeedback, NothingIsMeasuredBeforeTheFirstObservation) {
  OcclusionFeedback feedback(3, 3, true);
  feedback.productPlaced(2);
  for (uint32_t rv = 0; rv < 3; ++rv) EXPECT_LT(feedback.receiverShare(rv), 0.0f);
  EXPECT_LT(feedback.productShare(1), 0.0f);
  feedback.beginShares(2);
  feedback.addReceiverSource(1, 0, kGrey, 0);
  const std::vector<double> q = sharesOf(feedback, 0, 2, 0.375f);
  EXPECT_EQ(q[0], 0.375);  // unseen sources: the fallback
  EXPECT_EQ(q[1], 0.375);
}

TEST(OcclusionFeedback, SharesAreTransferWeightedOverThePasses) {
  OcclusionFeedback feedback(3, 3, true);
  feedback.productPlaced(1);
  const Frame f;
  // Probe 0: pass 0 occluded, pass 1 not; probe 1: both; the product vertex: neither.
  const std::vector<uint8_t> masks{255, 0, 255, 255, 0, 0};
  feedback.observe(masks, f.observed());
  EXPECT_EQ(feedback.receiverShare(2), 0.25f);  // 1 / (1 + 3)
  EXPECT_EQ(feedback.receiverShare(0), 1.0f);   // 2 / 2 (k0 brings nothing)
  EXPECT_LT(feedback.receiverShare(1), 0.0f);   // not a probe this frame
  EXPECT_EQ(feedback.productShare(0), 0.0f);
}

TEST(OcclusionFeedback, ClusterSharesComeFromTheSourcesSeenAtTheVertex) {
  OcclusionFeedback feedback(3, 3, true);
  feedback.productPlaced(1);
  const Frame f;
  feedback.observe(std::vector<uint8_t>{255, 0, 255, 255, 0, 0}, f.observed());
  // At vertex 2, sources 0 and 2 (k0's pass) were seen occluded, source 1 (k1's) not. A
  // later frame clusters them differently: {0, 1} and {2}.
  feedback.beginShares(2);
  feedback.addReceiverSource(2, 0, kGrey, 0);
  feedback.addReceiverSource(2, 1, 3.0 * kGrey, 0);
  feedback.addReceiverSource(2, 2, kGrey, 1);
  std::vector<double> q = sharesOf(feedback, 0, 2, feedback.receiverShare(2));
  EXPECT_EQ(q[0], 0.25);  // weight 1 of 4 seen occluded
  EXPECT_EQ(q[1], 1.0);
  // The product vertex saw every source unoccluded.
  feedback.beginShares(2);
  feedback.addProductSource(0, 0, kGrey, 0);
  feedback.addProductSource(0, 1, kGrey, 1);
  q = sharesOf(feedback, 0, 2, feedback.productShare(0));
  EXPECT_EQ(q[0], 0.0);
  EXPECT_EQ(q[1], 0.0);
  // Without per-cluster shares, every cluster takes the vertex's one share.
  OcclusionFeedback single(3, 3, false);
  single.productPlaced(1);
  single.observe(std::vector<uint8_t>{255, 0, 255, 255, 0, 0}, f.observed());
  single.beginShares(2);
  single.addReceiverSource(2, 1, kGrey, 1);
  q = sharesOf(single, 0, 2, single.receiverShare(2));
  EXPECT_EQ(q[0], 0.25);
  EXPECT_EQ(q[1], 0.25);
}

TEST(OcclusionFeedback, SourcesWithoutAPassAreNotSeen) {
  OcclusionFeedback feedback(3, 3, true);
  feedback.productPlaced(1);
  Frame f;
  f.passCluster = {1};  // k0 had no pass (its light was inside the product)
  feedback.observe(std::vector<uint8_t>{255, 0, 0}, f.observed());
  EXPECT_EQ(feedback.receiverShare(2), 1.0f);  // only k1's weight counts
  feedback.beginShares(2);
  feedback.addReceiverSource(2, 0, kGrey, 0);  // source 0: unseen
  feedback.addReceiverSource(2, 1, kGrey, 1);  // source 1: seen occluded
  const std::vector<double> q = sharesOf(feedback, 0, 2, 0.5f);
  EXPECT_EQ(q[0], 0.5);
  EXPECT_EQ(q[1], 1.0);
}

TEST(OcclusionFeedback, MasksThatDoNotMatchTheFrameAreRefused) {
  OcclusionFeedback feedback(3, 3, true);
  feedback.productPlaced(1);
  const Frame f;
  EXPECT_THROW(feedback.observe(std::vector<uint8_t>(5, 0), f.observed()), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::shadow
