#include "platform/opencv_camera.h"

#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>

namespace penumbra::platform {

struct OpenCvCamera::Impl {
  std::string device;
  uint32_t width = 0, height = 0;
  cv::VideoCapture cap;
  cv::Mat frame;
  uint64_t sequence = 0;
};

OpenCvCamera::OpenCvCamera(std::string device, uint32_t width, uint32_t height)
    : impl_(std::make_unique<Impl>()) {
  impl_->device = std::move(device);
  impl_->width = width;
  impl_->height = height;
  if (!open()) {
    throw HardwareUnavailable(
        "camera: cannot open " + impl_->device +
        (std::filesystem::exists(impl_->device) ? " with V4L2" : ": no such device"));
  }
}

OpenCvCamera::~OpenCvCamera() = default;

bool OpenCvCamera::open() {
  // A missing device node is answered here, without OpenCV's own warnings on stderr.
  if (!std::filesystem::exists(impl_->device)) return false;
  if (!impl_->cap.open(impl_->device, cv::CAP_V4L2)) return false;
  impl_->cap.set(cv::CAP_PROP_FRAME_WIDTH, impl_->width);
  impl_->cap.set(cv::CAP_PROP_FRAME_HEIGHT, impl_->height);
  impl_->cap.set(cv::CAP_PROP_BUFFERSIZE, 1);  // the newest frame, not a queue of old ones
  return true;
}

kiosk::GrabStatus OpenCvCamera::grab(int64_t nowNs, kiosk::CameraFrame& out) {
  // read() waits for the next frame: at most one camera period.
  if (!impl_->cap.isOpened() || !impl_->cap.read(impl_->frame) || impl_->frame.empty()) {
    impl_->cap.release();
    return kiosk::GrabStatus::kDisconnected;
  }
  const cv::Mat& f = impl_->frame;
  if (f.type() != CV_8UC3) return kiosk::GrabStatus::kNoFrame;
  out.width = static_cast<uint32_t>(f.cols);
  out.height = static_cast<uint32_t>(f.rows);
  out.stride = out.width * 3;
  out.format = kiosk::PixelFormat::kBgr8;
  out.sequence = ++impl_->sequence;
  out.captureNs = nowNs;  // V4L2 timestamps are not exposed reliably through VideoCapture
  out.data.resize(size_t{out.stride} * out.height);
  for (int y = 0; y < f.rows; ++y) {
    std::copy_n(f.ptr<uint8_t>(y), out.stride, out.data.data() + size_t{out.stride} * size_t(y));
  }
  return kiosk::GrabStatus::kFrame;
}

bool OpenCvCamera::reopen(int64_t nowNs) {
  (void)nowNs;
  return open();
}

std::string OpenCvCamera::describe() const {
  return "V4L2 webcam " + impl_->device + " via OpenCV, " + std::to_string(impl_->width) + "x" +
         std::to_string(impl_->height) + " BGR8";
}

}  // namespace penumbra::platform
