#include "core/replace_file.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "core/error.h"
#include "tests/scratch_dir.h"

namespace penumbra::core {
namespace {

std::filesystem::path scratch(const std::string& name) {
  const std::filesystem::path dir = test::scratchPath(name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::string contents(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

size_t entries(const std::filesystem::path& dir) {
  size_t n = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++n;
  return n;
}

TEST(ReplaceFile, WritesAndReplacesLeavingNoTemporary) {
  const std::filesystem::path dir = scratch("replace_file_ok");
  const std::filesystem::path f = dir / "lens.json";
  writeFileReplacing(f, std::string_view("first\n"));
  EXPECT_EQ(contents(f), "first\n");
  writeFileReplacing(f, std::string_view("second, longer\n"));
  EXPECT_EQ(contents(f), "second, longer\n");
  writeFileReplacing(f, std::string_view(""));
  EXPECT_EQ(contents(f), "");
  EXPECT_EQ(entries(dir), 1u);  // the temporaries are gone
}

TEST(ReplaceFile, FailureNamesTheFileAndLeavesNothing) {
  const std::filesystem::path dir = scratch("replace_file_bad");
  // A missing directory: the temporary cannot be created.
  try {
    writeFileReplacing(dir / "no" / "lens.json", std::string_view("x"));
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no/lens.json: cannot write"), std::string::npos)
        << e.what();
  }
  // A directory in the destination's place: the temporary is written, the rename fails and
  // the temporary is removed again.
  std::filesystem::create_directory(dir / "taken");
  try {
    writeFileReplacing(dir / "taken", std::string_view("x"));
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("taken: cannot replace the file"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(entries(dir), 1u);
  EXPECT_TRUE(std::filesystem::is_directory(dir / "taken"));
}

}  // namespace
}  // namespace penumbra::core
