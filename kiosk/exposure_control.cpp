#include "kiosk/exposure_control.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "scene/image_io.h"

namespace penumbra::kiosk {

std::string checkControls(const CameraControls& c) {
  auto range = [](const char* name, double v, double lo, double hi) -> std::string {
    if (std::isfinite(v) && v >= lo && v <= hi) return {};
    std::ostringstream s;
    s << std::setprecision(9) << name << " must be in [" << lo << ", " << hi << "] (got " << v
      << ")";
    return s.str();
  };
  for (const std::string& why : {range("exposure_us", c.exposureUs, 1, 10'000'000),
                                 range("analogue_gain", c.analogueGain, 1, 64),
                                 range("colour_gains[0]", c.redGain, 0.01, 32),
                                 range("colour_gains[1]", c.blueGain, 0.01, 32)}) {
    if (!why.empty()) return why;
  }
  return {};
}

std::vector<BracketShot> captureBracket(ControllableCamera& camera, Timebase& time,
                                        const BracketOptions& o, KioskLog& log) {
  if (o.exposuresUs.size() < 2) throw std::invalid_argument("bracket: at least 2 exposures");
  std::vector<BracketShot> shots;
  CameraFrame frame;
  uint64_t newest = 0;  // the newest sequence seen so far
  for (const int32_t asked : o.exposuresUs) {
    CameraControls c = o.base;
    c.exposureUs = asked;
    if (const std::string why = checkControls(c); !why.empty()) {
      throw std::invalid_argument("bracket: " + why);
    }
    camera.applyControls(c);
    const uint64_t changedAfter = newest;
    const int64_t deadline = time.nowNanoseconds() + o.timeoutNs;
    const std::string what = "bracket: exposure " + std::to_string(asked) + " us";
    for (;;) {
      const int64_t now = time.nowNanoseconds();
      if (now > deadline) {
        throw std::runtime_error(what + ": no settled frame within " +
                                 std::to_string(o.timeoutNs / 1'000'000) + " ms");
      }
      const GrabStatus st = camera.grab(now, frame);
      if (st == GrabStatus::kDisconnected) throw std::runtime_error(what + ": camera disconnected");
      if (st == GrabStatus::kNoFrame) {
        time.sleepUntil(now + o.pollNs);
        continue;
      }
      newest = std::max(newest, frame.sequence);
      if (frame.sequence <= changedAfter + o.settleFrames) continue;  // still settling
      // Metadata a stop away from the request: the sensor has not switched yet.
      if (frame.exposureUs != 0 && std::abs(frame.exposureUs - asked) * 10 > asked) continue;
      BracketShot shot;
      shot.askedUs = asked;
      shot.appliedUs = frame.exposureUs != 0 ? frame.exposureUs : asked;
      shot.sequence = frame.sequence;
      std::string why;
      if (!toRgba(frame, o.width, o.height, shot.rgba, why, o.orientation))
        throw std::runtime_error(what + ": " + why);
      std::string line = what;
      line.append(": frame ").append(std::to_string(frame.sequence));
      line.append(", applied ").append(std::to_string(shot.appliedUs)).append(" us");
      log.write(now, LogLevel::kInfo, line);
      shots.push_back(std::move(shot));
      break;
    }
  }
  camera.applyControls(o.base);
  return shots;
}

void writeBracket(const std::vector<BracketShot>& shots, uint32_t width, uint32_t height,
                  const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  std::ofstream manifest(dir / "exposures.json");
  if (!manifest) throw std::runtime_error((dir / "exposures.json").string() + ": cannot write");
  manifest << "{\"exposures\": [\n";
  for (size_t i = 0; i < shots.size(); ++i) {
    const std::string name = "bracket-" + std::to_string(i) + ".png";
    scene::writePng(dir / name, width, height, shots[i].rgba);
    manifest << "  {\"image\": \"" << name << "\", \"seconds\": " << std::setprecision(9)
             << shots[i].appliedUs * 1e-6 << "}" << (i + 1 < shots.size() ? "," : "") << "\n";
  }
  manifest << "]}\n";
  if (!manifest) throw std::runtime_error((dir / "exposures.json").string() + ": write failed");
}

std::vector<int32_t> exposureLadder(int32_t centreUs, uint32_t stops) {
  std::vector<int32_t> out;
  const int64_t first = -static_cast<int64_t>(stops / 2);
  for (int64_t s = first; s < first + static_cast<int64_t>(stops); ++s) {
    const int64_t us = s < 0 ? centreUs >> -s : static_cast<int64_t>(centreUs) << s;
    out.push_back(static_cast<int32_t>(std::clamp<int64_t>(us, 1, 10'000'000)));
  }
  return out;
}

}  // namespace penumbra::kiosk
