// The environment camera's geometry (Havran et al. 2005 §5.1: "the environment map captured
// using a fisheye lens has to be transformed to the uniform polar coordinates for the
// importance sampling"): OpenCV's fisheye model (cv::fisheye; θ_d = θ (1 + k1 θ² + k2 θ⁴ +
// k3 θ⁶ + k4 θ⁸), image radius f·θ_d: with k = 0 the equidistant lens) and the resampling of its
// images into the hemisphere map of hemisphere_map.h.
//
// Frames: the camera looks along the map's zenith; the map's frame is the camera's (x to the
// image's right, y down the image, z along the optical axis), so azimuth 0 is the image's +x.
//
// The image positions of each map pixel's taps are computed once, by
// cv::fisheye::projectPoints, snapped to 1/256 pixel and turned into a sparse kernel of
// bilinear weights; per frame each map pixel is its kernel's weighted sum in binary32, in a
// fixed order, so frames resample to the same bits everywhere (an ulp of difference in
// OpenCV's projection could only move a snapped position at a tie).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/image.h"
#include "envmap/hemisphere_map.h"

namespace penumbra::envmap {

class FisheyeError : public core::Error {
 public:
  using core::Error::Error;
};

// The intrinsics of cv::fisheye: camera matrix (fx, fy, cx, cy) and distortion k1..k4.
struct FisheyeLens {
  uint32_t width = 0, height = 0;
  double fx = 0, fy = 0, cx = 0, cy = 0;
  std::array<double, 4> k{};

  // An ideal equidistant lens with a 180° field of view whose image circle fills a square
  // image of `size` pixels: f = (size / 2) / (π / 2).
  static FisheyeLens equidistant180(uint32_t size) { return equidistant180(size, size); }
  // The same lens centred in a width × height image, its image circle the shorter side's
  // (header-only: the kiosk's configuration uses it without OpenCV).
  static FisheyeLens equidistant180(uint32_t width, uint32_t height) {
    const uint32_t size = std::min(width, height);
    const double f = (size / 2.0) / (std::numbers::pi / 2);
    return {width, height, f, f, width / 2.0, height / 2.0, {}};
  }
};

class FisheyeResampler {
 public:
  // Throws FisheyeError for a lens of no size or a non-positive focal length, or when a map
  // pixel projects outside the image (a lens that does not see the whole hemisphere).
  FisheyeResampler(const FisheyeLens& lens, uint32_t cols = kEnvmapCols,
                   uint32_t rows = kEnvmapRows, uint32_t supersample = 2);

  // The hemisphere map of one camera image (RGB radiance of the lens's size), into `map`
  // (resized on first use). Throws FisheyeError naming `label` for an image of another size.
  void resample(const core::ImageF& image, HemisphereMap& map,
                const std::string& label = "fisheye frame") const;

 private:
  // Map pixels are resampled kLanes at a time, one kernel step of each per iteration, the
  // kLanes kernels of one length: a lone kernel is a chain of dependent float additions in a
  // loop of unpredictable length, whose latency bounded the resampling. Each pixel's own sum
  // keeps its order, so its bits.
  static constexpr uint32_t kLanes = 4;
  static constexpr uint32_t kPrefetchRows = 8;
  FisheyeLens lens_;
  uint32_t cols_, rows_, taps_;
  std::vector<uint32_t> order_;  // map pixels in the raster order of their first image sample
  // Group g is map pixels groupPixels_[g·kLanes …] with steps [groupSteps_[g],
  // groupSteps_[g + 1]); step s holds lane l's sample at offset_/weight_[s·kLanes + l]: the
  // first sample of its image pixel in core::ImageF's layout, less groupBase_[g], and its
  // weight.
  std::vector<uint32_t> groupPixels_, groupSteps_{0}, groupBase_;
  std::vector<uint16_t> offset_;
  std::vector<float> weight_;
  // The pixels left over (fewer than kLanes of a length, or too far from the others of theirs
  // for 16-bit offsets): restPixels_[q]'s kernel is
  // restIndex_/restWeight_[restOffsets_[q], restOffsets_[q + 1]).
  std::vector<uint32_t> restPixels_, restOffsets_{0}, restIndex_;
  std::vector<float> restWeight_;
  // Per image row, the samples [first, end) that the kernels read (a step reads 4 floats), in
  // core::ImageF's layout; first ≥ end for a row that none reads. Only these are prefetched.
  std::vector<std::pair<uint32_t, uint32_t>> rowSpans_;
};

// A synthetic fisheye photograph of a lat-long environment (lat_long.h) turned by
// `azimuthDegrees` about the zenith: each pixel inside the image circle (θ < 90°) is the
// environment in the direction cv::fisheye::undistortPoints gives for its centre; a 3-pixel
// rim gets the horizon; outside, 0. (Offline: libm and OpenCV's float results allowed.)
core::ImageF renderFisheye(const core::ImageF& latLong, const FisheyeLens& lens,
                           double azimuthDegrees = 0);

}  // namespace penumbra::envmap
