#include "platform/opencv_environment_camera.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>
#include <optional>
#include <utility>
#include <vector>

#include "core/error.h"
#include "envmap/fisheye_resampler.h"
#include "platform/bracket_merge.h"
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
  if (s.response) return "calibrated response " + s.responseFile;
  if (s.gamma == 0) return "sRGB response";
  std::array<char, 32> text{};
  std::snprintf(text.data(), text.size(), "gamma %g response", s.gamma);
  return text.data();
}

std::string bracketName(const std::vector<int64_t>& us) {
  std::string text;
  for (const int64_t t : us) {
    if (!text.empty()) text.push_back('/');
    text.append(std::to_string(t));  // appended: GCC 12's -Wrestrict false positive (bug
  }                                  // 105329) on a literal + temporary string
  return text.append(" us");
}

std::vector<double> millisecondsOf(const std::vector<int64_t>& us) {
  std::vector<double> ms;
  ms.reserve(us.size());
  for (const int64_t t : us) ms.push_back(double(t) / 1000);
  return ms;
}

}  // namespace

struct OpenCvEnvironmentCamera::Impl {
  kiosk::EnvironmentCameraSettings settings;
  EnvironmentLog log;
  bool device = false;
  ChannelTables table{};               // a single frame's: no bracket, or a bracket of one
  std::optional<BracketMerge> merger;  // a bracket of two or more
  envmap::FisheyeResampler resampler;
  cv::VideoCapture cap;
  cv::Mat frame;
  // A bracket: the newest frame of each exposure, and whether it has come since opening.
  std::vector<cv::Mat> shots;
  std::vector<uint8_t> shotTaken;
  size_t exposure = 0;      // a device: the bracket's exposure it was last set to
  uint32_t settleLeft = 0;  // a device: frames still to drop after that change
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
      : settings(s), log(std::move(l)), device(isDevice(s.device)), resampler(s.lens) {
    const ChannelResponse response =
        s.response ? calibratedResponse(*s.response) : curveResponse(s.gamma);
    const std::vector<double> ms = millisecondsOf(s.bracketUs);
    table = radianceTables(response, ms.empty() ? 1.0 : ms.front(), s.exposureScale);
    if (ms.size() >= 2) {
      merger.emplace(response, ms, s.exposureScale);
      shots.resize(ms.size());
      shotTaken.assign(ms.size(), 0);
    }
  }

  bool bracketed() const { return merger.has_value(); }

  // A device: exposure j of the bracket from the next frame the sensor starts, and the
  // frames before it applies it dropped.
  bool setExposure(size_t j) {
    exposure = j;
    settleLeft = settings.settleFrames;
    // OpenCV's V4L2 backend hands CAP_PROP_EXPOSURE to V4L2_CID_EXPOSURE_ABSOLUTE
    // (exposure_time_absolute) unscaled (after rounding to an integer) unless its range
    // normalisation is on, which CAP_PROP_MODE 0 turns off in open(): the unit is the
    // control's, 100 µs. The configuration allows only multiples of 100 µs for a device.
    return cap.set(cv::CAP_PROP_EXPOSURE, double(settings.bracketUs[j]) / 100);
  }

  void say(kiosk::LogLevel level, const std::string& text) const {
    if (log) log(level, "environment camera: " + text);
  }

  // Opens the source; the reason when it cannot.
  bool open(std::string& why) {
    cap.release();
    framesRead = 0;
    startNs = -1;
    nextReadNs = 0;
    std::fill(shotTaken.begin(), shotTaken.end(), uint8_t{0});  // frames of before are stale
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
      // A bracket needs the exposure in our hands: V4L2_CID_EXPOSURE_AUTO =
      // V4L2_EXPOSURE_MANUAL (1), in V4L2's own values (CAP_PROP_MODE 0: OpenCV's
      // OPENCV_VIDEOIO_V4L_RANGE_NORMALIZED scaling off, whatever the environment says).
      if (!settings.bracketUs.empty()) {
        cap.set(cv::CAP_PROP_MODE, 0);
        if (!cap.set(cv::CAP_PROP_AUTO_EXPOSURE, 1)) {
          why = "does not take a manual exposure (V4L2 auto_exposure)";
          cap.release();
          return false;
        }
        if (!setExposure(0)) {
          why = "refused the exposure of " + std::to_string(settings.bracketUs[0]) + " us";
          cap.release();
          return false;
        }
      }
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

  // Throws core::Error naming the frame when it is not what the lens and the tables are for.
  void check(const cv::Mat& f, const std::string& label) const {
    if (f.type() != CV_8UC3) {
      throw core::Error(
          label, "", "not an 8-bit 3-channel image (OpenCV type " + std::to_string(f.type()) + ")");
    }
    if (uint32_t(f.cols) != settings.width || uint32_t(f.rows) != settings.height) {
      throw core::Error(label, "",
                        std::to_string(f.cols) + "x" + std::to_string(f.rows) +
                            ", the lens is for " + std::to_string(settings.width) + "x" +
                            std::to_string(settings.height));
    }
  }

  // The frame just read becomes exposure j's newest (its buffer is swapped, not copied: the
  // next read reuses the one it replaces).
  void keep(size_t j) {
    std::swap(frame, shots[j]);
    shotTaken[j] = 1;
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
  const std::string label = m.settings.device + " frame " + std::to_string(m.frames);
  if (m.device) {
    if (nowNs < m.nextReadNs) return kiosk::GrabStatus::kNoFrame;
    if (!m.next(true)) return m.lost(nowNs, "no frame (read failed)");
    m.nextReadNs = nowNs + m.periodNs;
    if (!m.settings.bracketUs.empty()) {
      // Shot before the sensor applied the exposure it was set to: dropped.
      if (m.settleLeft > 0) {
        --m.settleLeft;
        return kiosk::GrabStatus::kNoFrame;
      }
      if (m.bracketed()) {
        m.check(m.frame, label);
        m.keep(m.exposure);
        const size_t following = (m.exposure + 1) % m.shots.size();
        if (!m.setExposure(following)) {
          return m.lost(nowNs, "refused the exposure of " +
                                   std::to_string(m.settings.bracketUs[following]) + " us");
        }
      }
    }
  } else {
    // Frame k of a recording is due at startNs + k·period: the newest one due is decoded, the
    // ones before it only grabbed — or, in a bracket, decoded too: each is the newest of its
    // exposure.
    if (m.startNs < 0) m.startNs = nowNs;
    if (nowNs < m.startNs) return kiosk::GrabStatus::kNoFrame;  // a clock that went back
    uint64_t due = uint64_t((nowNs - m.startNs) / m.periodNs);
    if (due < m.framesRead) return kiosk::GrabStatus::kNoFrame;
    if (due - m.framesRead > kMostFramesSkipped) {
      m.startNs = nowNs - int64_t(m.framesRead) * m.periodNs;
      due = m.framesRead;
    }
    for (; m.framesRead <= due; ++m.framesRead) {
      const bool newest = m.framesRead == due;
      if (!m.next(newest || m.bracketed()))
        return m.lost(nowNs, "no frame (the recording cannot be read)");
      if (m.bracketed()) {
        m.check(m.frame, label);
        m.keep((m.position - 1) % m.shots.size());  // frame i was shot with bracket[i % n]
      }
    }
  }
  size_t saturated = 0;
  if (m.bracketed()) {
    if (std::find(m.shotTaken.begin(), m.shotTaken.end(), 0) != m.shotTaken.end())
      return kiosk::GrabStatus::kNoFrame;  // not every exposure yet
    std::vector<const uint8_t*> frames;
    std::vector<size_t> strides;
    for (const cv::Mat& shot : m.shots) {
      frames.push_back(shot.ptr<uint8_t>(0));
      strides.push_back(shot.step[0]);
    }
    saturated = m.merger->merge(frames, strides, m.settings.width, m.settings.height, m.image);
  } else {
    m.check(m.frame, label);
    saturated = linearise(m.frame.ptr<uint8_t>(0), m.frame.step[0], m.settings.width,
                          m.settings.height, m.table, m.image);
  }
  m.resampler.resample(m.image, map, label);
  ++m.frames;
  if (saturated > 0 && nowNs >= m.nextSaturationLogNs) {
    const std::string of =
        std::to_string(saturated) + " of " + std::to_string(m.image.pixelCount()) + " pixels ";
    m.say(kiosk::LogLevel::kWarning,
          m.bracketed()
              ? of + "saturated in every exposure (a channel at 255 even in the shortest, " +
                    std::to_string(m.settings.bracketUs.front()) +
                    " us): their light is under-reported; a shorter exposure would hold it"
              : of + "saturated (a channel >= " + std::to_string(kSaturatedValue) +
                    "): a clipped lamp under-reports its power (one 8-bit exposure, not HDR: "
                    "see bracket_us)");
    m.nextSaturationLogNs = nowNs + kSaturationLogEveryNs;
  }
  return kiosk::GrabStatus::kFrame;
}

std::string OpenCvEnvironmentCamera::describe() const {
  const kiosk::EnvironmentCameraSettings& s = impl_->settings;
  std::string text = "fisheye " + std::string(impl_->device ? "V4L2 camera " : "recording ") +
                     s.device + " via OpenCV, " + std::to_string(s.width) + "x" +
                     std::to_string(s.height) + ", " +
                     (s.equidistant180 ? "equidistant 180° lens" : "calibrated fisheye lens") +
                     ", " + responseName(s);
  if (impl_->bracketed()) {
    text += ", HDR from the exposure bracket " + bracketName(s.bracketUs);
  } else if (!s.bracketUs.empty()) {
    text += ", exposure " + bracketName(s.bracketUs);
  }
  if (impl_->device && !s.bracketUs.empty())
    text += " (" + std::to_string(s.settleFrames) + " frames dropped after each change)";
  return text;
}

}  // namespace penumbra::platform
