#include "firmware-sim/footage.h"

#include <fnmatch.h>

#include <algorithm>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <string>

namespace penumbra::firmware_sim {
namespace {

namespace fs = std::filesystem;

bool isImageFile(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  for (const char* e :
       {".png", ".jpg", ".jpeg", ".bmp", ".tif", ".tiff", ".ppm", ".pgm", ".webp"}) {
    if (ext == e) return true;
  }
  return false;
}

// Appends `frame` (BGR8 from OpenCV) as RGBA8 of the view's size.
class FrameSink {
 public:
  FrameSink(uint32_t width, uint32_t height, size_t maxBytes)
      : width_(width), height_(height), maxBytes_(maxBytes) {}

  void add(const cv::Mat& bgr, const std::string& name) {
    if (bgr.empty()) throw FootageError(name + ": not a readable image");
    if (first_.empty()) {
      first_ = name;
      size_ = bgr.size();
      // The footage must show the calibrated camera's view: same aspect ratio (the view's
      // geometry, not only its pixel count), then resized.
      const int64_t a = int64_t{bgr.cols} * height_, b = int64_t{bgr.rows} * width_;
      if (std::llabs(a - b) * 100 > b) {
        throw FootageError(name + ": " + std::to_string(bgr.cols) + "x" + std::to_string(bgr.rows) +
                           " does not have the aspect ratio of the " + std::to_string(width_) +
                           "x" + std::to_string(height_) + " view");
      }
    } else if (bgr.size() != size_) {
      throw FootageError(name + ": " + std::to_string(bgr.cols) + "x" + std::to_string(bgr.rows) +
                         ", but " + first_ + " is " + std::to_string(size_.width) + "x" +
                         std::to_string(size_.height));
    }
    if ((frames_.size() + 1) * width_ * height_ * 4 > maxBytes_) {
      throw FootageError(name + ": footage longer than " + std::to_string(maxBytes_ >> 20) +
                         " MB of frames at " + std::to_string(width_) + "x" +
                         std::to_string(height_) + "; shorten it (it loops)");
    }
    cv::Mat sized = bgr;
    if (bgr.cols != static_cast<int>(width_) || bgr.rows != static_cast<int>(height_)) {
      cv::resize(bgr, sized, cv::Size(static_cast<int>(width_), static_cast<int>(height_)), 0, 0,
                 cv::INTER_AREA);
    }
    std::vector<uint8_t> rgba(size_t{width_} * height_ * 4);
    cv::Mat out(static_cast<int>(height_), static_cast<int>(width_), CV_8UC4, rgba.data());
    cv::cvtColor(sized, out, cv::COLOR_BGR2RGBA);
    frames_.push_back(std::move(rgba));
  }

  std::vector<std::vector<uint8_t>> take() { return std::move(frames_); }

 private:
  uint32_t width_, height_;
  size_t maxBytes_;
  std::string first_;
  cv::Size size_;
  std::vector<std::vector<uint8_t>> frames_;
};

}  // namespace

std::vector<fs::path> sequenceFiles(const fs::path& source, bool (*accept)(const fs::path&)) {
  const std::string pattern = source.filename().string();
  const bool glob = pattern.find_first_of("*?[") != std::string::npos;
  const fs::path dir = glob ? source.parent_path() : source;
  std::error_code ec;
  std::vector<fs::path> files;
  for (const fs::directory_entry& e : fs::directory_iterator(dir.empty() ? "." : dir, ec)) {
    if (!e.is_regular_file()) continue;
    const std::string name = e.path().filename().string();
    if (glob ? ::fnmatch(pattern.c_str(), name.c_str(), 0) == 0 : accept(e.path())) {
      files.push_back(e.path());
    }
  }
  if (ec) throw FootageError(dir.string() + ": cannot list (" + ec.message() + ")");
  if (files.empty()) {
    throw FootageError(source.string() +
                       (glob ? ": no file matches" : ": no images in the folder"));
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<std::vector<uint8_t>> loadFootage(const fs::path& source, uint32_t width,
                                              uint32_t height, size_t maxBytes) {
  FrameSink sink(width, height, maxBytes);
  const bool glob = source.filename().string().find_first_of("*?[") != std::string::npos;
  if (glob || fs::is_directory(source)) {
    for (const fs::path& f : sequenceFiles(source, isImageFile))
      sink.add(cv::imread(f.string()), f.string());
    return sink.take();
  }
  if (!fs::exists(source)) throw FootageError(source.string() + ": no such file");
  if (isImageFile(source)) {
    sink.add(cv::imread(source.string()), source.string());
    return sink.take();
  }
  // FFmpeg only: the same decoder on every machine, and no fallback through GStreamer, whose
  // plugin scan (libusb among others) leaks at exit under LeakSanitizer when a file is bad.
  cv::VideoCapture video(source.string(), cv::CAP_FFMPEG);
  if (!video.isOpened()) {
    throw FootageError(source.string() + ": OpenCV (FFmpeg) cannot open it as a video");
  }
  cv::Mat frame;
  uint64_t k = 0;
  while (video.read(frame) && !frame.empty()) {
    sink.add(frame, source.string() + " frame " + std::to_string(k++));
  }
  std::vector<std::vector<uint8_t>> frames = sink.take();
  if (frames.empty()) throw FootageError(source.string() + ": no decodable frames");
  return frames;
}

}  // namespace penumbra::firmware_sim
