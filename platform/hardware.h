// "The hardware is not there" from every real backend (no GPIO chip, no camera, no display),
// one exception type so the board program can fall back per peripheral (docs/kiosk.md).
#pragma once

#include <stdexcept>

namespace penumbra::platform {

class HardwareUnavailable : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace penumbra::platform
