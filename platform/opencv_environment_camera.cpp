#include "platform/opencv_environment_camera.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>
#include <utility>

#include "core/error.h"
#include "envmap/fisheye_resampler.h"
#include "platform/environment_response.h"
#include "platform/hardware.h"

namespace penumbra::platform {
namespace {

constexpr int64_t kSecondNs = 1'000'000'000;
constexpr int64_t kHavranPeriodNs = kSecondNs / 21;  // Havran 2005 §3.3: VEM grabbing ~21 Hz
constexpr int64_t kReopenEveryNs = kSecondNs;
constexpr int64_t kSaturationLogEveryNs = 10 * kSecondNs;
constexpr uint64_t kMostFramesSkipped = 8;  // a recording further behind is resynchronised

bool isDevice(const std::string& source) {
  return source.rfind("/dev/", 0) == 0;
}

std::string responseName(const kiosk::EnvironmentCameraSettings& s) {
  if (s.gamma == 0) return "sRGB";
  std::array<char, 32> text{};
  std::snprintf(text.data(), text.size(), "gamma %g", s.gamma);
  return text.data();
}

}  // namespace

struct OpenCvEnvironmentCamera::Impl {
  kiosk::EnvironmentCameraSettings settings;
  EnvironmentLog log;
  bool device = false;
  std::array<float, 256> table{};
  envmap::FisheyeResampler resampler;
  cv::VideoCapture cap;
  cv::Mat frame;
  core::ImageF image;
  int64_t periodNs = kHavranPeriodNs;  // between reads
  int64_t startNs = -1;                // a recording: when its frame 0 was due
  int64_t nextReadNs = 0;              // a device: its next read
  uint64_t framesRead = 0;             // since opened (a recording: the next frame's index)
  uint64_t frames = 0;                 // returned, ever
  uint64_t position = 0;               // frames read since the reader was opened
  uint64_t sequenceLength = 0;         // an image sequence's frames (0: a video, or unknown)
  int64_t nextReopenNs = 0;
  int64_t nextSaturationLogNs = 0;
  bool lostSaid = false;

  Impl(const kiosk::EnvironmentCameraSettings& s, EnvironmentLog l)
      : settings(s),
        log(std::move(l)),
        device(isDevice(s.device)),
        table(inverseResponse(s.gamma, s.exposureScale)),
        resampler(s.lens) {}

  void say(kiosk::LogLevel level, const std::string& text) const {
    if (log) log(level, "environment camera: " + text);
  }

  // Opens the source; the reason when it cannot.
  bool open(std::string& why) {
    cap.release();
    framesRead = 0;
    startNs = -1;
    nextReadNs = 0;
    const bool pattern = settings.device.find('%') != std::string::npos;
    // A missing node or file is answered here, without OpenCV's own warnings on stderr.
    if (!pattern && !std::filesystem::exists(settings.device)) {
      why = device ? "no such device" : "no such file";
      return false;
    }
    if (device) {
      if (!cap.open(settings.device, cv::CAP_V4L2)) {
        why = "cannot be opened with V4L2";
        return false;
      }
      cap.set(cv::CAP_PROP_FRAME_WIDTH, settings.width);
      cap.set(cv::CAP_PROP_FRAME_HEIGHT, settings.height);
      cap.set(cv::CAP_PROP_BUFFERSIZE, 1);  // the newest frame, not a queue of old ones
      const double fps = cap.get(cv::CAP_PROP_FPS);
      const int64_t framePeriod = fps > 0 && fps <= 1000 ? int64_t(1e9 / fps) : kSecondNs / 30;
      periodNs = std::max(kHavranPeriodNs, framePeriod + framePeriod / 2);
    } else {
      if (!cap.open(settings.device, api())) {
        why = pattern ? "no image sequence there" : "cannot be read as a video file";
        return false;
      }
      // An image sequence has no rate of its own (FFmpeg's reader would say 25): Havran's.
      const double fps = pattern ? 0 : cap.get(cv::CAP_PROP_FPS);
      const double count = pattern ? cap.get(cv::CAP_PROP_FRAME_COUNT) : 0;
      sequenceLength = count >= 1 && count < 1e9 ? uint64_t(count) : 0;
      position = 0;
      periodNs = fps > 0 && fps <= 1000 ? int64_t(1e9 / fps) : kHavranPeriodNs;
    }
    return true;
  }

  // A recording's reader: OpenCV's own for an image sequence ("frame_%03d.png": it reads each
  // file when its frame is due), whichever OpenCV finds for a video file.
  int api() const {
    return settings.device.find('%') != std::string::npos ? cv::CAP_IMAGES : cv::CAP_ANY;
  }

  // The source's next frame (skip: grabbed, not decoded into `frame`). A recording starts
  // again at its end.
  bool next(bool decode) {
    const auto step = [&] {
      ++position;
      return decode ? cap.read(frame) && !frame.empty() : cap.grab();
    };
    // An image sequence's end is known (its reader counted the files): started again without
    // asking for the file after the last, which OpenCV would warn about on stderr.
    if (sequenceLength == 0 || position < sequenceLength) {
      if (step()) return true;
      if (device) return false;
    }
    cap.release();
    position = 0;
    return cap.open(settings.device, api()) && step();
  }

  kiosk::GrabStatus lost(int64_t nowNs, const std::string& why) {
    cap.release();
    nextReopenNs = nowNs + kReopenEveryNs;
    if (!lostSaid)
      say(kiosk::LogLevel::kWarning, settings.device + ": " + why + "; reopening every second");
    lostSaid = true;
    return kiosk::GrabStatus::kDisconnected;
  }
};

OpenCvEnvironmentCamera::OpenCvEnvironmentCamera(const kiosk::EnvironmentCameraSettings& settings,
                                                 EnvironmentLog log)
    : impl_(std::make_unique<Impl>(settings, std::move(log))) {
  std::string why;
  if (!impl_->open(why)) {
    throw HardwareUnavailable("environment camera: cannot open " + settings.device + ": " + why);
  }
}

OpenCvEnvironmentCamera::~OpenCvEnvironmentCamera() = default;

kiosk::GrabStatus OpenCvEnvironmentCamera::grab(int64_t nowNs, envmap::HemisphereMap& map) {
  Impl& m = *impl_;
  if (!m.cap.isOpened()) {
    if (nowNs < m.nextReopenNs) return kiosk::GrabStatus::kDisconnected;
    std::string why;
    if (!m.open(why)) return m.lost(nowNs, why);
    m.say(kiosk::LogLevel::kInfo, m.settings.device + ": open again");
    m.lostSaid = false;
  }
  if (m.device) {
    if (nowNs < m.nextReadNs) return kiosk::GrabStatus::kNoFrame;
    if (!m.next(true)) return m.lost(nowNs, "no frame (read failed)");
    m.nextReadNs = nowNs + m.periodNs;
  } else {
    // Frame k of a recording is due at startNs + k·period: the newest one due is decoded, the
    // ones before it only grabbed.
    if (m.startNs < 0) m.startNs = nowNs;
    if (nowNs < m.startNs) return kiosk::GrabStatus::kNoFrame;  // a clock that went back
    uint64_t due = uint64_t((nowNs - m.startNs) / m.periodNs);
    if (due < m.framesRead) return kiosk::GrabStatus::kNoFrame;
    if (due - m.framesRead > kMostFramesSkipped) {
      m.startNs = nowNs - int64_t(m.framesRead) * m.periodNs;
      due = m.framesRead;
    }
    for (; m.framesRead < due; ++m.framesRead) {
      if (!m.next(false)) return m.lost(nowNs, "no frame (the recording cannot be read)");
    }
    if (!m.next(true)) return m.lost(nowNs, "no frame (the recording cannot be read)");
    ++m.framesRead;
  }
  const cv::Mat& f = m.frame;
  const std::string label = m.settings.device + " frame " + std::to_string(m.frames);
  if (f.type() != CV_8UC3) {
    throw core::Error(
        label, "", "not an 8-bit 3-channel image (OpenCV type " + std::to_string(f.type()) + ")");
  }
  if (uint32_t(f.cols) != m.settings.width || uint32_t(f.rows) != m.settings.height) {
    throw core::Error(label, "",
                      std::to_string(f.cols) + "x" + std::to_string(f.rows) + ", the lens is for " +
                          std::to_string(m.settings.width) + "x" +
                          std::to_string(m.settings.height));
  }
  const size_t saturated = linearise(f.ptr<uint8_t>(0), f.step[0], m.settings.width,
                                     m.settings.height, m.table, m.image);
  m.resampler.resample(m.image, map, label);
  ++m.frames;
  if (saturated > 0 && nowNs >= m.nextSaturationLogNs) {
    m.say(kiosk::LogLevel::kWarning,
          std::to_string(saturated) + " of " + std::to_string(m.image.pixelCount()) +
              " pixels saturated (a channel >= " + std::to_string(kSaturatedValue) +
              "): a clipped lamp under-reports its power (one 8-bit exposure, not HDR)");
    m.nextSaturationLogNs = nowNs + kSaturationLogEveryNs;
  }
  return kiosk::GrabStatus::kFrame;
}

std::string OpenCvEnvironmentCamera::describe() const {
  const kiosk::EnvironmentCameraSettings& s = impl_->settings;
  return "fisheye " + std::string(impl_->device ? "V4L2 camera " : "recording ") + s.device +
         " via OpenCV, " + std::to_string(s.width) + "x" + std::to_string(s.height) + ", " +
         (s.equidistant180 ? "equidistant 180° lens" : "calibrated fisheye lens") + ", " +
         responseName(s) + " response";
}

}  // namespace penumbra::platform
