// A simulated kiosk session (issue 6 §5): which bundle, how the simulated board costs its
// frames, what the camera films and when it fails, which buttons are pressed when, and the
// start-up faults — everything that decides the displayed frames, in one JSON file
// (docs/kiosk.md, "Session files"). Loading is strict: an unknown key, a wrong type or an
// out-of-range value is refused with a SessionError naming the file and the field.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/clock.h"
#include "core/error.h"
#include "firmware-sim/virtual_camera.h"
#include "firmware-sim/virtual_gpio.h"
#include "kiosk/kiosk_loop.h"
#include "shadow/frame_cost_model.h"

namespace penumbra::firmware_sim {

// Nanoseconds in a millisecond: sessions give times in ms, the clock counts ns.
inline constexpr int64_t kNsPerMs = 1'000'000;

class SessionError : public core::Error {
 public:
  using core::Error::Error;
};

// An extra cost charged to one frame (a page fault storm, a kernel hiccup): the
// controller must drop passes within two frames (Gibson 2003 §8, fast path).
struct Overrun {
  uint32_t frame = 0;  // 1-based kiosk frame number
  int64_t extraNs = 0;
};

// A product model file the shop drops on the board (kiosk/product_files.h): at start-up
// (atNs = 0, before the first frame) or hot-swapped while the kiosk runs.
struct ScriptedProductFile {
  int64_t atNs = 0;
  std::string product;
  std::filesystem::path file;  // resolved against the session file's folder
};

// "environment" (issue 16): live lighting from a simulated fisheye camera playing an EXR
// sequence; the lights' options go to Session::kiosk (kiosk::readLiveLightOptions).
struct EnvironmentScript {
  std::filesystem::path frames;   // a folder of *.exr, resolved against the session's folder
  int64_t periodNs = 47'619'048;  // 21 Hz, Havran 2005's camera
  int64_t stopAtNs = -1;          // the camera hangs from then on; < 0: never
};

struct Session {
  std::filesystem::path file;
  std::filesystem::path bundle;    // resolved against the session file's folder
  std::filesystem::path lastGood;  // empty: none
  uint32_t frames = 600;
  kiosk::KioskOptions kiosk;
  // The simulated board: cost of a frame in virtual time (shadow::CostModel).
  shadow::CostModel::Params cost;
  std::vector<shadow::CostModel::LoadStep> loadSteps;
  std::vector<Overrun> overruns;
  bool cameraPresent = true;
  CameraScript camera;
  // camera.source: footage the simulated camera films instead of the bundle's photograph (an
  // image folder, a glob such as "shots/*.png", or a video file; firmware-sim/footage.h).
  std::filesystem::path cameraSource;
  bool gpioPresent = true;
  std::vector<ScriptedPress> presses;
  bool corruptBundle = false;  // start-up: the configured bundle is a corrupted copy
  std::string corruptProduct;  // start-up: this product's mesh holds a NaN vertex
  std::vector<ScriptedProductFile> productFiles;  // in time order
  std::optional<EnvironmentScript> environment;   // none: the bundle's captured light
};

Session loadSession(const std::filesystem::path& path);

}  // namespace penumbra::firmware_sim
