// Capture manifests (lighting/capture.h), as `penumbra capture` reads them. Values are
// mutated through the JSON structure (json_mutator.cpp).
#include "lighting/capture.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace penumbra;
  const auto path = fuzz::writeScratch("capture.json", {data, size});
  fuzz::expectOnlyProjectErrors([&] { (void)lighting::loadCaptureManifest(path); });
  return 0;
}
