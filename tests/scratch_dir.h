// A scratch path private to one running test. ctest runs every GoogleTest case as its own
// process, two at a time, and several checkouts may test on one machine at once: a fixed
// name under /tmp lets one test's TearDown delete another's files (seen in CI:
// "cannot remove: Directory not empty"). The process id and the test's name keep them apart.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace penumbra::test {

inline std::filesystem::path scratchPath(const std::string& tag) {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  return std::filesystem::temp_directory_path() /
         ("penumbra-" + tag + "-" + std::to_string(::getpid()) + "-" +
          (info ? std::string(info->test_suite_name()) + "." + info->name() : std::string()));
}

}  // namespace penumbra::test
