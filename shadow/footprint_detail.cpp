#include "shadow/footprint_detail.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace penumbra::shadow {

YawSphere yawSphere(const core::Mesh& mesh) {
  if (mesh.positions.empty()) return {};
  double lo = mesh.positions[0].y, hi = lo;
  for (const core::Vec3& p : mesh.positions) {
    lo = std::min(lo, double(p.y));
    hi = std::max(hi, double(p.y));
  }
  YawSphere s;
  s.centreY = 0.5 * (lo + hi);
  double farthest = 0;
  for (const core::Vec3& p : mesh.positions) {
    const double dy = double(p.y) - s.centreY;
    farthest = std::max(farthest, double(p.x) * p.x + dy * dy + double(p.z) * p.z);
  }
  s.radius = std::sqrt(farthest);
  return s;
}

double productFootprintPx(const raster::StaticView& view, const YawSphere& sphere,
                          const ProductPose& pose) {
  const auto& m = view.cameraViewProj.m;
  const double c[3] = {pose.x, sphere.centreY + pose.lift, pose.z};
  const double w =
      ((double(m[12]) * c[0] + double(m[13]) * c[1]) + double(m[14]) * c[2]) + double(m[15]);
  if (!(w > sphere.radius)) return std::numeric_limits<double>::infinity();
  const double focal = std::sqrt(double(m[4]) * m[4] + double(m[5]) * m[5] + double(m[6]) * m[6]) *
                       (0.5 * view.height);
  return 2.0 * sphere.radius * focal / w;
}

FootprintDetail::FootprintDetail(const FootprintDetailOptions& options, uint32_t maxPasses,
                                 std::vector<uint32_t> ladder)
    : options_(options), maxPasses_(maxPasses), ladder_(std::move(ladder)), passes_(maxPasses) {
  if (ladder_.empty()) throw std::invalid_argument("FootprintDetail: the map ladder is empty");
  if (maxPasses_ == 0) throw std::invalid_argument("FootprintDetail: maxPasses must be > 0");
}

FootprintDetail::Limits FootprintDetail::next(double footprintPx) {
  if (options_.fullDetailPx == 0 || !(footprintPx < 1e9)) {
    rung_ = 0;
    passes_ = maxPasses_;
    return {passes_, ladder_[0]};
  }
  // The map: k texels per footprint pixel, up at once, down an eighth past the need.
  const double need = double(options_.texelsPerPixel) * footprintPx;
  while (rung_ > 0 && double(ladder_[rung_]) < need) --rung_;
  while (rung_ + 1 < ladder_.size() && double(ladder_[rung_ + 1]) * 7.0 / 8.0 >= need) ++rung_;
  // The passes: in proportion to the footprint below fullDetailPx, still within an eighth.
  const double share = std::min(1.0, footprintPx / double(options_.fullDetailPx));
  const uint32_t floor = std::min(options_.minPasses, maxPasses_);
  const uint32_t target =
      std::clamp(static_cast<uint32_t>(std::ceil(share * maxPasses_)), floor, maxPasses_);
  const uint32_t band = passes_ / 8;
  if (target + band < passes_) {
    passes_ -= std::min(passes_ - target, options_.maxStepPerFrame);
  } else if (target > passes_ + band) {
    passes_ += std::min(target - passes_, options_.maxStepPerFrame);
  }
  return {passes_, ladder_[rung_]};
}

}  // namespace penumbra::shadow
