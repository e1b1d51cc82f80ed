// `penumbra-kiosk --check CONFIG` and `penumbra-kiosk --list-cameras` (docs/kiosk.md): what a
// technician runs on a site before starting the service. Neither opens a camera, a GPIO line
// or a window: they read the configuration, the bundle and the product files, and look at
// which devices the kernel has.
#pragma once

#include <filesystem>
#include <ostream>

#include "kiosk/kiosk_config.h"

namespace penumbra::apps {

// The render threads a configuration asks for: `threads`, or with 0 one per core this process
// may run on (its CPU affinity, which systemd's CPUAffinity= narrows).
int kioskThreads(const kiosk::KioskConfig& config);

// Validates everything the kiosk would load and prints what it would use, one line per
// peripheral with the fallback it would take. Throws (exit 1) on any error: the configuration,
// the bundle (missing, corrupt, no usable product) or a product file refused.
void checkKioskConfig(const std::filesystem::path& configPath, std::ostream& out);

// The cameras libcamera lists (where built with it) and the V4L2 devices the kernel has.
void listCameras(std::ostream& out);

}  // namespace penumbra::apps
