// Start-up with a scene bundle that may be corrupt (issue 6 faults): load the configured
// bundle; if it is refused (scene::BundleError: truncated, bad checksum, inconsistent) or
// holds no usable product (validateProducts), say why and run on the last good bundle
// instead. A bundle that loads is copied over the last good one (write-then-rename, so a
// power cut mid-copy cannot leave a half-written last good bundle).
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

#include "kiosk/status.h"
#include "shadow/scene_bundle.h"

namespace penumbra::kiosk {

struct GuardedBundle {
  shadow::SceneBundle bundle;
  std::filesystem::path loadedFrom;
  bool fellBack = false;  // the configured bundle was refused
  std::string refusal;    // why, when fellBack
};

class NoUsableBundle : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// `lastGood` may be empty (no fallback kept). Logs at `nowNs`. Throws NoUsableBundle naming
// both files and both reasons when neither can be used.
GuardedBundle loadBundleKeepingLastGood(const std::filesystem::path& configured,
                                        const std::filesystem::path& lastGood, KioskLog& log,
                                        int64_t nowNs);

}  // namespace penumbra::kiosk
