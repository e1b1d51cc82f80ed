#include "scene/photo_io.h"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "scene/camera_intrinsics.h"

namespace penumbra::scene {

core::Image8 readPhotoRgb8(const std::filesystem::path& path) {
  const std::string name = path.filename().string();
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw CalibrationError(name + ": no such file (" + path.string() + ")");
  }
  const cv::Mat raw = cv::imread(path.string(), cv::IMREAD_UNCHANGED);
  if (raw.empty()) throw CalibrationError(name + ": cannot decode the image");
  if (raw.depth() != CV_8U) {
    throw CalibrationError(name + ": not 8 bits per channel; bracketed exposures must be 8-bit");
  }
  cv::Mat rgb;
  switch (raw.channels()) {
    case 1:
      cv::cvtColor(raw, rgb, cv::COLOR_GRAY2RGB);
      break;
    case 3:
      cv::cvtColor(raw, rgb, cv::COLOR_BGR2RGB);
      break;
    case 4:
      cv::cvtColor(raw, rgb, cv::COLOR_BGRA2RGB);
      break;
    default:
      throw CalibrationError(name + ": unsupported channel count");
  }
  core::Image8 out(uint32_t(rgb.cols), uint32_t(rgb.rows), 3, name);
  for (int y = 0; y < rgb.rows; ++y) {
    const uint8_t* row = rgb.ptr<uint8_t>(y);
    std::copy(row, row + size_t(rgb.cols) * 3,
              out.pixels.begin() + ptrdiff_t(size_t(y) * rgb.cols * 3));
  }
  return out;
}

}  // namespace penumbra::scene
