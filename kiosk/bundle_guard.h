// Start-up with a scene bundle that may be corrupt or may crash the renderer (issue 6 and
// issue 18 faults). The configured bundle is loaded; it is refused when scene::BundleError
// says so (truncated, bad checksum, inconsistent, not a regular file), when it holds no
// usable product (validateProducts), or when the previous run was trying this very file and
// stopped before it had rendered kFramesBeforeLastGood frames (a crash or a render error:
// its trial mark is still there). A refused bundle is said in one log line and the kiosk
// runs on the last good bundle instead.
//
// A bundle becomes the last good one only after it has rendered: the kiosk calls
// noteFrameRendered() after every frame, and the kFramesBeforeLastGood-th copies it over the
// last good file (write-then-rename, so a power cut mid-copy cannot leave a half-written
// last good bundle) and removes the trial mark. Until then the last good file is untouched,
// so a bundle that loads but crashes can never replace the fallback.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "kiosk/status.h"
#include "shadow/scene_bundle.h"

namespace penumbra::kiosk {

// One second of frames at the kiosk's 30 fps: every product has been drawn with its shadow
// passes, the static cache and the compositor's buffers have been built — what a bad bundle
// crashes on happens in the first frame.
inline constexpr uint32_t kFramesBeforeLastGood = 30;

struct GuardedBundle {
  shadow::SceneBundle bundle;
  std::filesystem::path loadedFrom;
  bool fellBack = false;  // the configured bundle was refused
  std::string refusal;    // why, when fellBack
  // Where the bundle is kept once it has rendered; empty when it needs no keeping (it is the
  // last good one already, or none is configured).
  std::filesystem::path keepAs;
  uint32_t framesRendered = 0;
  bool kept = false;  // copied over the last good one
};

class NoUsableBundle : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// `lastGood` may be empty (no fallback kept). Logs at `nowNs`. Throws NoUsableBundle naming
// both files and both reasons when neither can be used. With a last good file, writes the
// trial mark `lastGood + ".trial"` naming the configured bundle before returning it.
GuardedBundle loadBundleKeepingLastGood(const std::filesystem::path& configured,
                                        const std::filesystem::path& lastGood, KioskLog& log,
                                        int64_t nowNs);

// Call after each frame rendered without error. On the kFramesBeforeLastGood-th frame of a
// bundle that is not the last good one yet, copies it there and removes the trial mark
// (a failed copy is logged as a warning; the kiosk keeps running).
void noteFrameRendered(GuardedBundle& guarded, KioskLog& log, int64_t nowNs);

}  // namespace penumbra::kiosk
