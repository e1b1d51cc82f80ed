// Fixed camera controls and exposure bracketing (issue 6 §1; Gibson & Chalmers 2003 §4).
// The kiosk's camera must film with the exposure, gain and white balance the capture was
// calibrated with: the camera response T() of the bundle maps codes to radiance only for
// that exposure, so auto-exposure and auto-white-balance are off. Bracketing films the room
// at a series of exposure times with everything else fixed, for `penumbra capture`'s HDR
// merge (Debevec & Malik), writing the photographs and the manifest's `exposures` list.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "kiosk/frame_source.h"
#include "kiosk/kiosk_loop.h"
#include "kiosk/status.h"

namespace penumbra::kiosk {

struct CameraControls {
  int32_t exposureUs = 10'000;            // libcamera ExposureTime, microseconds
  float analogueGain = 1.0f;              // AnalogueGain, >= 1
  float redGain = 1.0f, blueGain = 1.0f;  // ColourGains (red, blue), > 0
};

// Empty when usable; else why not ("exposure_us must be in [1, 10000000] (got 0)").
std::string checkControls(const CameraControls& controls);

// A camera whose controls can be fixed (libcamera; the simulated twin in tests).
class ControllableCamera : public FrameSource {
 public:
  // The controls of every request queued from now on. Frames already in flight were captured
  // with the previous ones: a sensor applies a change a few frames later.
  virtual void applyControls(const CameraControls& controls) = 0;
};

struct BracketOptions {
  std::vector<int32_t> exposuresUs;  // at least 2, distinct
  CameraControls base;               // gain and white balance for every shot
  uint32_t width = 0, height = 0;    // the calibrated view
  // The camera's mounting: shots are mirrored as the kiosk mirrors its background, so the
  // capture pipeline calibrates the view the kiosk shows.
  FrameOrientation orientation;
  // Frames newer than the change that are still discarded: sensors apply an exposure 2-3
  // frames after the request that carries it (the pipeline depth).
  uint32_t settleFrames = 3;
  int64_t timeoutNs = 3'000'000'000;  // per exposure
  int64_t pollNs = 2'000'000;         // wait between grabs that brought nothing
};

struct BracketShot {
  int32_t askedUs = 0;
  int32_t appliedUs = 0;  // from the frame's metadata when the camera reports it, else asked
  uint64_t sequence = 0;
  std::vector<uint8_t> rgba;
};

// One frame per exposure, each captured after the settle delay with fixed controls; a frame
// whose metadata shows an exposure more than 10 % off the asked one is still the previous
// setting and is skipped. Restores `base` at the end. Throws std::runtime_error naming the
// exposure for a camera that disconnects, times out or delivers frames of another size.
std::vector<BracketShot> captureBracket(ControllableCamera& camera, Timebase& time,
                                        const BracketOptions& options, KioskLog& log);

// DIR/bracket-N.png (N in the order shot) and DIR/exposures.json, the `exposures` array of
// a capture manifest (docs/capture.md) with each shot's applied time in seconds.
void writeBracket(const std::vector<BracketShot>& shots, uint32_t width, uint32_t height,
                  const std::filesystem::path& dir);

// `stops` exposures one stop apart centred on `centreUs` (odd counts centre exactly), e.g.
// 5 around 8000 µs: 2000, 4000, 8000, 16000, 32000.
std::vector<int32_t> exposureLadder(int32_t centreUs, uint32_t stops);

}  // namespace penumbra::kiosk
