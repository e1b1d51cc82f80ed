#include "envmap/fisheye_resampler.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <utility>

#include "envmap/lat_long.h"

namespace penumbra::envmap {

namespace {

// Four floats in one register (SSE, NEON, or scalar code where there is neither): the r, g, b
// of a pixel side by side, so that a kernel step is one load, one multiply and one add.
using Float4 = float __attribute__((vector_size(16)));
using Int4 = int32_t __attribute__((vector_size(16)));

cv::Matx33d cameraMatrix(const FisheyeLens& lens) {
  return {lens.fx, 0, lens.cx, 0, lens.fy, lens.cy, 0, 0, 1};
}

void checkLens(const FisheyeLens& lens) {
  if (lens.width < 2 || lens.height < 2 || !(lens.fx > 0) || !(lens.fy > 0))
    throw FisheyeError("fisheye lens", "",
                       "needs an image of at least 2 × 2 pixels and positive focal lengths");
}

}  // namespace

FisheyeResampler::FisheyeResampler(const FisheyeLens& lens, uint32_t cols, uint32_t rows,
                                   uint32_t supersample)
    : lens_(lens), cols_(cols), rows_(rows), taps_(supersample * supersample) {
  checkLens(lens);
  if (cols == 0 || rows == 0 || supersample == 0)
    throw FisheyeError("fisheye resampling", "", "cols, rows and supersample must be at least 1");
  // Every tap's direction, then one projectPoints call for all of them.
  std::vector<cv::Point3d> directions;
  directions.reserve(size_t(cols) * rows * taps_);
  for (uint32_t row = 0; row < rows; ++row)
    for (uint32_t col = 0; col < cols; ++col)
      for (uint32_t sy = 0; sy < supersample; ++sy)
        for (uint32_t sx = 0; sx < supersample; ++sx) {
          const glm::dvec3 d = diskToHemisphere(
              {(row + (sy + 0.5) / supersample) / rows, (col + (sx + 0.5) / supersample) / cols});
          directions.emplace_back(d.x, d.y, d.z);
        }
  std::vector<cv::Point2d> image;
  const cv::Vec4d distortion(lens.k[0], lens.k[1], lens.k[2], lens.k[3]);
  cv::fisheye::projectPoints(directions, image, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0),
                             cameraMatrix(lens), distortion);
  // Each map pixel becomes one sparse kernel over the image: the bilinear weights of its taps,
  // multiplied out once here (in binary32, from the snapped positions) and merged where taps
  // share an image pixel (near the zenith all of them do).
  struct Sample {
    uint32_t index;  // first sample of the image pixel in core::ImageF's layout
    float weight;
  };
  std::vector<Sample> samples;
  std::vector<uint32_t> offsets(1, 0);
  const float inverseTaps = 1.0f / float(taps_);
  for (size_t pixel = 0; pixel < size_t(cols) * rows; ++pixel) {
    const size_t begin = samples.size();
    for (uint32_t tap = 0; tap < taps_; ++tap) {
      const size_t i = pixel * taps_ + tap;
      // Pixel centres are at integer + 0.5: positions relative to pixel (0, 0)'s centre. Up to
      // half a pixel beyond the outer centres (the image's edge, where equidistant180 puts the
      // horizon) the edge pixel is used.
      const double x = image[i].x - 0.5, y = image[i].y - 0.5;
      if (!(x >= -0.5 && y >= -0.5 && x <= lens.width - 0.5 && y <= lens.height - 0.5))
        throw FisheyeError("fisheye lens", "",
                           "the direction of map sample " + std::to_string(i) + " projects to (" +
                               std::to_string(image[i].x) + ", " + std::to_string(image[i].y) +
                               "), outside the " + std::to_string(lens.width) + " × " +
                               std::to_string(lens.height) +
                               " image: the lens must see the whole hemisphere");
      // Snapped to 1/256 pixel: an ulp of difference in OpenCV's result moves nothing.
      const int32_t sx = int32_t(std::lround(std::clamp(x, 0.0, lens.width - 1.0) * 256));
      const int32_t sy = int32_t(std::lround(std::clamp(y, 0.0, lens.height - 1.0) * 256));
      const uint32_t x0 = uint32_t(sx >> 8), y0 = uint32_t(sy >> 8);
      const float fx = float(sx & 255) * (1.0f / 256), fy = float(sy & 255) * (1.0f / 256);
      const uint32_t x1 = std::min(x0 + 1, lens.width - 1), y1 = std::min(y0 + 1, lens.height - 1);
      const std::array<std::pair<uint32_t, float>, 4> corners = {
          {{y0 * lens.width + x0, (1 - fx) * (1 - fy) * inverseTaps},
           {y0 * lens.width + x1, fx * (1 - fy) * inverseTaps},
           {y1 * lens.width + x0, (1 - fx) * fy * inverseTaps},
           {y1 * lens.width + x1, fx * fy * inverseTaps}}};
      // Not a structured binding: clang before 16 cannot capture one in the lambda below.
      for (const auto& corner : corners) {
        const uint32_t index = corner.first;
        const float weight = corner.second;
        if (weight == 0) continue;
        auto it = std::find_if(samples.begin() + begin, samples.end(),
                               [&](const Sample& k) { return k.index == index * 3; });
        if (it != samples.end())
          it->weight += weight;
        else
          samples.push_back({index * 3, weight});
      }
    }
    offsets.push_back(uint32_t(samples.size()));
  }
  // Map pixels are visited in the image's raster order of their kernels: the map's rows are
  // rings in the image, and walking them would touch every image row once per ring; this order
  // streams the image once (each pixel's own sum is unchanged, so are the bits).
  order_.resize(size_t(cols) * rows);
  for (uint32_t p = 0; p < order_.size(); ++p) order_[p] = p;
  std::stable_sort(order_.begin(), order_.end(), [&](uint32_t a, uint32_t b) {
    return samples[offsets[a]].index < samples[offsets[b]].index;
  });
  // The kernels stored in that order too, so that they stream as well: kLanes map pixels with
  // kernels of the same length interleaved step by step (see the header). A pixel waits for
  // kLanes − 1 others of its length, most of them its neighbours on its ring; the few left
  // over at the end are summed one at a time, and so is every pixel when a kernel reads the
  // image's last pixel (a step reads 4 floats, one past it).
  const uint32_t lastPixel = (lens.width * lens.height - 1) * 3;
  const bool fourFloatReads = std::none_of(samples.begin(), samples.end(),
                                           [&](const Sample& s) { return s.index == lastPixel; });
  // The image outside the lens's circle (a fifth of a square frame) is never read, and a frame
  // fresh from memory is the resampling's bottleneck: the prefetches skip it.
  rowSpans_.assign(lens.height, {UINT32_MAX, 0});
  for (const Sample& s : samples) {
    auto& [first, end] = rowSpans_[s.index / (lens.width * 3)];
    first = std::min(first, s.index);
    end = std::max(end, s.index + 4);
  }
  // A group's samples are stored as 16-bit offsets from its lowest (a quarter less to read per
  // frame than 32-bit indices); a pixel whose kernel lies too far from those of the others
  // waiting with it (more than 65,535 samples, ~45 image rows) is summed alone.
  std::vector<std::vector<uint32_t>> waiting(1);  // by kernel length; [0]: the ones alone
  for (uint32_t pixel : order_) {
    const uint32_t begin = offsets[pixel], length = offsets[pixel + 1] - begin;
    if (waiting.size() <= length) waiting.resize(length + 1);
    std::vector<uint32_t>& group = waiting[length];
    group.push_back(pixel);
    if (group.size() < kLanes || !fourFloatReads) continue;
    uint32_t lo = UINT32_MAX, hi = 0;
    for (uint32_t lane : group)
      for (uint32_t k = offsets[lane]; k < offsets[lane + 1]; ++k) {
        lo = std::min(lo, samples[k].index);
        hi = std::max(hi, samples[k].index);
      }
    if (hi - lo > UINT16_MAX) {
      waiting[0].push_back(group.front());
      group.erase(group.begin());
      continue;
    }
    for (uint32_t s = 0; s < length; ++s)
      for (uint32_t lane : group) {
        offset_.push_back(uint16_t(samples[offsets[lane] + s].index - lo));
        weight_.push_back(samples[offsets[lane] + s].weight);
      }
    groupPixels_.insert(groupPixels_.end(), group.begin(), group.end());
    groupSteps_.push_back(groupSteps_.back() + length);
    groupBase_.push_back(lo);
    group.clear();
  }
  for (const std::vector<uint32_t>& group : waiting)
    for (uint32_t pixel : group) {
      for (uint32_t k = offsets[pixel]; k < offsets[pixel + 1]; ++k) {
        restIndex_.push_back(samples[k].index);
        restWeight_.push_back(samples[k].weight);
      }
      restPixels_.push_back(pixel);
      restOffsets_.push_back(uint32_t(restIndex_.size()));
    }
}

void FisheyeResampler::resample(const core::ImageF& image, HemisphereMap& map,
                                const std::string& label) const {
  if (image.width != lens_.width || image.height != lens_.height || !image.hasExpectedSize())
    throw FisheyeError(label, "",
                       std::to_string(image.width) + " × " + std::to_string(image.height) +
                           " image (" + std::to_string(image.pixels.size()) +
                           " samples), but the lens is " + std::to_string(lens_.width) + " × " +
                           std::to_string(lens_.height));
  if (map.radiance.width != cols_ || map.radiance.height != rows_ ||
      !map.radiance.hasExpectedSize())
    map.radiance = core::ImageF(cols_, rows_);
  const float* in = image.pixels.data();
  float* out = map.radiance.pixels.data();
  // The frame is read in raster order, a few rows ahead of the kernels: the hardware
  // prefetcher alone left a cold frame ~0.3 ms slower than a cached one. Only the samples the
  // kernels read (rowSpans_), with locality 2 (prefetcht1): a cold frame took 0.07–0.10 ms
  // longer than a cached one, against 0.09–0.14 with prefetcht0 and 0.10–0.11 with
  // prefetchnta (five runs each, alternating).
  const size_t ahead = size_t(kPrefetchRows) * lens_.width * 3;
  size_t prefetched = 0, prefetchRow = 0;
  const size_t imageRows = rowSpans_.size();
  while (prefetchRow < imageRows && rowSpans_[prefetchRow].first >= rowSpans_[prefetchRow].second)
    ++prefetchRow;
  if (prefetchRow < imageRows) prefetched = rowSpans_[prefetchRow].first;
  for (size_t g = 0; g + 1 < groupSteps_.size(); ++g) {
    const uint16_t* offset = &offset_[size_t(groupSteps_[g]) * kLanes];
    const float* base = in + groupBase_[g];
    const float* weight = &weight_[size_t(groupSteps_[g]) * kLanes];
    const uint32_t steps = groupSteps_[g + 1] - groupSteps_[g];
    for (const size_t target = groupBase_[g] + ahead;
         prefetchRow < imageRows && prefetched < target;) {
      __builtin_prefetch(in + prefetched, 0, 2);
      prefetched += 16;
      if (prefetched >= rowSpans_[prefetchRow].second) {
        // On to the next row that is read (its span starts after this one's end).
        do ++prefetchRow;
        while (prefetchRow < imageRows &&
               rowSpans_[prefetchRow].first >= rowSpans_[prefetchRow].second);
        if (prefetchRow < imageRows)
          prefetched = std::max<size_t>(prefetched, rowSpans_[prefetchRow].first);
      }
    }
    // Per lane r, g, b (and a fourth float, the next image sample, computed and dropped), each
    // summed in its kernel's fixed order, w × p then +: the scalar sum's operations.
    Float4 sum[kLanes] = {};
    static_assert(kLanes == 4);
    for (uint32_t s = 0; s < steps; ++s, offset += kLanes, weight += kLanes) {
      // The step's four weights in one load, each lane's spread over a vector by a shuffle.
      Float4 w;
      std::memcpy(&w, weight, sizeof w);
      Float4 p0, p1, p2, p3;
      std::memcpy(&p0, base + offset[0], sizeof p0);
      std::memcpy(&p1, base + offset[1], sizeof p1);
      std::memcpy(&p2, base + offset[2], sizeof p2);
      std::memcpy(&p3, base + offset[3], sizeof p3);
      sum[0] += __builtin_shufflevector(w, w, 0, 0, 0, 0) * p0;
      sum[1] += __builtin_shufflevector(w, w, 1, 1, 1, 1) * p1;
      sum[2] += __builtin_shufflevector(w, w, 2, 2, 2, 2) * p2;
      sum[3] += __builtin_shufflevector(w, w, 3, 3, 3, 3) * p3;
    }
    for (uint32_t lane = 0; lane < kLanes; ++lane)
      for (int c = 0; c < 3; ++c)
        out[size_t(groupPixels_[g * kLanes + lane]) * 3 + c] = sum[lane][c];
  }
  for (size_t q = 0; q < restPixels_.size(); ++q) {
    float r = 0, g = 0, b = 0;  // summed in the kernel's fixed order
    for (uint32_t k = restOffsets_[q]; k < restOffsets_[q + 1]; ++k) {
      const float* p = in + restIndex_[k];
      const float w = restWeight_[k];
      r += w * p[0];
      g += w * p[1];
      b += w * p[2];
    }
    float* o = &out[size_t(restPixels_[q]) * 3];
    o[0] = r, o[1] = g, o[2] = b;
  }
}

core::ImageF renderFisheye(const core::ImageF& latLong, const FisheyeLens& lens,
                           double azimuthDegrees) {
  checkLens(lens);
  std::vector<cv::Point2d> pixels, normalised;
  for (uint32_t y = 0; y < lens.height; ++y)
    for (uint32_t x = 0; x < lens.width; ++x) pixels.emplace_back(x + 0.5, y + 0.5);
  const cv::Vec4d distortion(lens.k[0], lens.k[1], lens.k[2], lens.k[3]);
  cv::fisheye::undistortPoints(pixels, normalised, cameraMatrix(lens), distortion);
  core::ImageF out(lens.width, lens.height);
  const double turn = azimuthDegrees * std::numbers::pi / 180;
  for (size_t i = 0; i < pixels.size(); ++i) {
    // θ_d of the OpenCV model (with k = 0 it is θ). At and beyond 90° the camera sees the
    // horizon and below, which undistortPoints (a pinhole-plane result) cannot represent.
    // The last pixels inside the circle (within 3 pixels of 90°) get the horizon's radiance,
    // so that bilinear lookups at the map's last row do not reach into black.
    const double xd = (pixels[i].x - lens.cx) / lens.fx, yd = (pixels[i].y - lens.cy) / lens.fy;
    const double r = std::sqrt(xd * xd + yd * yd);
    if (r >= std::numbers::pi / 2 + 3 / std::min(lens.fx, lens.fy)) continue;
    const glm::dvec3 d = r < std::numbers::pi / 2 * 0.999
                             ? glm::normalize(glm::dvec3(normalised[i].x, normalised[i].y, 1.0))
                             : glm::dvec3(xd / r, yd / r, 0.0);
    const double c = std::cos(-turn), s = std::sin(-turn);
    const glm::dvec3 turned(c * d.x - s * d.y, s * d.x + c * d.y, d.z);
    const glm::dvec3 radiance = sampleLatLong(latLong, turned);
    for (int ch = 0; ch < 3; ++ch) out.pixels[i * 3 + ch] = float(radiance[ch]);
  }
  return out;
}

}  // namespace penumbra::envmap
