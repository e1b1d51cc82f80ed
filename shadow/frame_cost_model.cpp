#include "shadow/frame_cost_model.h"

#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

namespace penumbra::shadow {
namespace {

constexpr int64_t kInt64Max = std::numeric_limits<int64_t>::max();

// a * b for non-negative operands, clamped to INT64_MAX instead of wrapping (a cost model
// fed absurd inputs must give an absurdly large cost, never a negative one).
int64_t mulSat(int64_t a, int64_t b) {
  int64_t out = 0;
  return __builtin_mul_overflow(a, b, &out) ? kInt64Max : out;
}

int64_t addSat(int64_t a, int64_t b) {
  int64_t out = 0;
  return __builtin_add_overflow(a, b, &out) ? kInt64Max : out;
}

}  // namespace

CostModel::CostModel(Params params, std::vector<LoadStep> loadSteps)
    : params_(params), loadSteps_(std::move(loadSteps)) {
  if (params_.fixedNs < 0 || params_.perPassNs < 0 || params_.perTexelPs < 0 ||
      params_.perPixelPs < 0 || params_.perPassVertexPs < 0 || params_.perProductVertexPs < 0 ||
      params_.perShadedVertexPs < 0 || params_.perTransferredVertexPs < 0 ||
      params_.perPassTransferredVertexPs < 0 || params_.perShadowMapTrianglePs < 0) {
    throw std::invalid_argument("CostModel: costs must be >= 0");
  }
  for (size_t i = 0; i < loadSteps_.size(); ++i) {
    if (loadSteps_[i].permille == 0) {
      throw std::invalid_argument("CostModel: load step " + std::to_string(i) +
                                  " has a zero factor");
    }
    if (i > 0 && loadSteps_[i].atNs <= loadSteps_[i - 1].atNs) {
      throw std::invalid_argument("CostModel: load steps must be in strictly increasing time");
    }
  }
}

CostModel::Params CostModel::raspberryPi4() {
  Params p;
  p.fixedNs = 7'166'000;
  p.perPassNs = 2'000;
  p.perTexelPs = 2'141;
  p.perPixelPs = 21'383;
  p.perPassVertexPs = 11'565;
  p.perProductVertexPs = 558'635;
  p.perShadedVertexPs = 2'036'679;
  p.perTransferredVertexPs = 83'992;
  p.perPassTransferredVertexPs = 10'900;
  p.perShadowMapTrianglePs = 191'449;
  return p;
}

uint32_t CostModel::loadPermilleAt(int64_t nowNs) const {
  uint32_t permille = 1000;
  for (const LoadStep& s : loadSteps_) {
    if (s.atNs > nowNs) break;
    permille = s.permille;
  }
  return permille;
}

int64_t CostModel::frameNs(int64_t nowNs, const Workload& work) const {
  // Picoseconds are summed before the single division by 1000, so the rounding happens once
  // and does not depend on how the work is split between terms.
  const int64_t perPassPs =
      addSat(mulSat(params_.perPassNs, 1000),
             addSat(mulSat(params_.perPassVertexPs, work.productVertices),
                    mulSat(params_.perPassTransferredVertexPs, work.transferredVertices)));
  const auto clamped = [](uint64_t n) {
    return n > static_cast<uint64_t>(kInt64Max) ? kInt64Max : static_cast<int64_t>(n);
  };
  const int64_t pixels = clamped(work.shadowedPixels);
  const int64_t productPs =
      addSat(addSat(mulSat(params_.perProductVertexPs, work.productVertices),
                    mulSat(params_.perShadedVertexPs, work.shadedVertices)),
             mulSat(params_.perTransferredVertexPs, work.transferredVertices));
  const int64_t passWorkPs =
      addSat(addSat(mulSat(params_.perPixelPs, pixels),
                    mulSat(params_.perShadowMapTrianglePs, clamped(work.shadowMapTriangles))),
             mulSat(params_.perTexelPs, clamped(work.shadowMapTexels)));
  const int64_t variablePs = addSat(addSat(mulSat(perPassPs, work.passes), passWorkPs), productPs);
  const int64_t variableNs = mulSat(variablePs / 1000, loadPermilleAt(nowNs)) / 1000;
  return addSat(params_.fixedNs, variableNs);
}

}  // namespace penumbra::shadow
