// Session scripts of the simulated kiosk (firmware-sim/session.h), as `penumbra-sim` reads
// them. Values are mutated through the JSON structure (json_mutator.cpp).
#include "firmware-sim/session.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace penumbra;
  const auto path = fuzz::writeScratch("session.json", {data, size});
  fuzz::expectOnlyProjectErrors([&] { (void)firmware_sim::loadSession(path); });
  return 0;
}
