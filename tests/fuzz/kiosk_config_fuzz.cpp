// The kiosk's configuration file (kiosk/kiosk_config.h), as `penumbra-kiosk` reads it at
// start. Values are mutated through the JSON structure (json_mutator.cpp).
#include "kiosk/kiosk_config.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace penumbra;
  const auto path = fuzz::writeScratch("kiosk.json", {data, size});
  fuzz::expectOnlyProjectErrors([&] { (void)kiosk::loadKioskConfig(path); });
  return 0;
}
