// Parametrizing a test over every SIMD target this CPU runs (the scalar reference first).
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "simd/targets.h"

namespace penumbra::testing {

inline std::string isaTestName(const ::testing::TestParamInfo<simd::Isa>& param) {
  return simd::isaName(param.param);
}

}  // namespace penumbra::testing
