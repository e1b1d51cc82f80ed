// The bundled showroom (data/showroom/showroom.bundle), for the tests that run the per-frame
// pipeline on the real scene: loaded once per test binary.
#pragma once

#include "shadow/scene_bundle.h"
#include "tests/test_data.h"

namespace penumbra::testing {

inline const shadow::SceneBundle& showroomBundle() {
  static const shadow::SceneBundle bundle =
      shadow::loadBundle(dataDir() / "showroom" / "showroom.bundle");
  return bundle;
}

}  // namespace penumbra::testing
