// The environment camera's calibrated response file (kiosk/camera_response_file.h), as the
// kiosk reads it at start when kiosk.json's "environment" names one. Values are mutated
// through the JSON structure (json_mutator.cpp); an accepted file must pass its own checks.
#include <cstdlib>

#include "kiosk/camera_response_file.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace penumbra;
  const auto path = fuzz::writeScratch("response.json", {data, size});
  fuzz::expectOnlyProjectErrors([&] {
    const kiosk::CameraResponseCurves curves =
        kiosk::readCameraResponse(path, core::throwAs<core::Error>);
    if (!kiosk::checkLogExposure(curves.logExposure).empty()) std::abort();
  });
  return 0;
}
