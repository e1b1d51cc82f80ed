// PENUMBRA_TEST_WORKLOAD=small: the asan and tsan test presets (CMakePresets.json;
// tests/check_lib.sh for the scripts). A sanitizer looks for memory errors and races, not for
// other bytes or other numbers, so the heaviest tests cover their code paths on a part of
// their grid there; the release and aarch64 stages run all of it.
#pragma once

#include <cstdlib>
#include <string_view>

namespace penumbra::testing {

inline bool smallTestWorkload() {
  const char* workload = std::getenv("PENUMBRA_TEST_WORKLOAD");
  return workload != nullptr && std::string_view(workload) == "small";
}

}  // namespace penumbra::testing
