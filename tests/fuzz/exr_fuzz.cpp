// OpenEXR images (lighting/exr_io.h): the light probes of `penumbra capture`.
#include "lighting/exr_io.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace penumbra;
  const auto path = fuzz::writeScratch("probe.exr", {data, size});
  fuzz::expectOnlyProjectErrors([&] { (void)lighting::readExr(path); });
  return 0;
}
