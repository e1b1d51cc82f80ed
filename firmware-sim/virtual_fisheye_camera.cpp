#include "firmware-sim/virtual_fisheye_camera.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "firmware-sim/footage.h"

namespace penumbra::firmware_sim {

namespace {

bool isExrFile(const std::filesystem::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".exr";
}

}  // namespace

ExrSequence loadExrSequence(const std::filesystem::path& source, size_t maxBytes) {
  ExrSequence sequence;
  size_t bytes = 0;
  for (const std::filesystem::path& file : sequenceFiles(source, isExrFile)) {
    const std::string name = file.string();
    const cv::Mat raw = cv::imread(name, cv::IMREAD_UNCHANGED | cv::IMREAD_ANYDEPTH);
    if (raw.empty()) throw FootageError(name + ": not a readable EXR image");
    if (raw.channels() != 1 && raw.channels() != 3)
      throw FootageError(name + ": " + std::to_string(raw.channels()) +
                         " channels; an environment frame has 3 (RGB) or 1 (luminance)");
    cv::Mat rgb;
    raw.convertTo(rgb, CV_32F);
    if (rgb.channels() == 1) cv::merge(std::vector<cv::Mat>{rgb, rgb, rgb}, rgb);
    if (!sequence.frames.empty() && (uint32_t(rgb.cols) != sequence.frames[0].width ||
                                     uint32_t(rgb.rows) != sequence.frames[0].height))
      throw FootageError(name + ": " + std::to_string(rgb.cols) + "x" + std::to_string(rgb.rows) +
                         ", but " + sequence.names[0] + " is " +
                         std::to_string(sequence.frames[0].width) + "x" +
                         std::to_string(sequence.frames[0].height));
    bytes += size_t(rgb.cols) * rgb.rows * 3 * sizeof(float);
    if (bytes > maxBytes)
      throw FootageError(name + ": the sequence is longer than " + std::to_string(maxBytes >> 20) +
                         " MB of float frames; shorten it (it loops)");
    core::ImageF frame(uint32_t(rgb.cols), uint32_t(rgb.rows));
    size_t nonFinite = 0;
    for (int y = 0; y < rgb.rows; ++y) {
      const float* bgr = rgb.ptr<float>(y);
      for (int x = 0; x < rgb.cols; ++x)
        for (int c = 0; c < 3; ++c) {
          float v = bgr[x * 3 + (2 - c)];  // OpenCV's BGR to RGB
          if (!std::isfinite(v)) ++nonFinite;
          if (v < 0) ++sequence.clampedNegative, v = 0;
          frame.pixel(uint32_t(x), uint32_t(y))[c] = v;
        }
    }
    if (nonFinite > 0)
      throw FootageError(name + ": " + std::to_string(nonFinite) + " samples are NaN or infinite");
    sequence.frames.push_back(std::move(frame));
    sequence.names.push_back(name);
  }
  return sequence;
}

VirtualFisheyeCamera::VirtualFisheyeCamera(std::vector<core::ImageF> frames, int64_t periodNs)
    : frames_(std::move(frames)), periodNs_(periodNs) {
  if (frames_.empty()) throw std::invalid_argument("fisheye camera: no frames");
  if (periodNs <= 0) throw std::invalid_argument("fisheye camera: the period must be positive");
  for (const core::ImageF& f : frames_)
    if (f.width != frames_[0].width || f.height != frames_[0].height || !f.hasExpectedSize())
      throw std::invalid_argument("fisheye camera: frames of different sizes");
}

int64_t VirtualFisheyeCamera::frameNumberAt(int64_t nowNs) const {
  return nowNs < 0 ? -1 : nowNs / periodNs_;
}

bool VirtualFisheyeCamera::grab(int64_t nowNs, core::ImageF& out, uint64_t& k) {
  const int64_t newest = frameNumberAt(nowNs);
  if (newest < 0 || newest <= lastGrabbed_) return false;
  lastGrabbed_ = newest;
  k = uint64_t(newest);
  out = frames_[k % frames_.size()];
  return true;
}

std::string VirtualFisheyeCamera::describe() const {
  return "virtual fisheye camera: " + std::to_string(frames_.size()) + " HDR frames of " +
         std::to_string(frames_[0].width) + "x" + std::to_string(frames_[0].height) + " every " +
         std::to_string(periodNs_ / 1000) + " us";
}

}  // namespace penumbra::firmware_sim
