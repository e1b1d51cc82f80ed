#include "core/regular_file.h"

#include <sys/stat.h>

#include <fstream>

#include <gtest/gtest.h>

#include "core/error.h"

namespace penumbra::core {
namespace {

class LoaderError : public Error {
 public:
  using Error::Error;
};

std::filesystem::path scratch() {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "regular_file";
  std::filesystem::create_directories(dir);
  return dir;
}

// The message readRegularFile throws as LoaderError, or "read N bytes".
std::string outcome(const std::filesystem::path& p, uintmax_t maxBytes,
                    const std::string& context = {}) {
  try {
    return "read " +
           std::to_string(
               readRegularFile(p, maxBytes, "a test file", throwAs<LoaderError>, context).size()) +
           " bytes";
  } catch (const LoaderError& e) {
    return e.what();
  }
}

TEST(RegularFile, ReadsARegularFileWithinItsLimit) {
  const std::filesystem::path f = scratch() / "ten.bin";
  std::ofstream(f, std::ios::binary) << "0123456789";
  EXPECT_EQ(outcome(f, 10), "read 10 bytes");
  EXPECT_EQ(outcome(f, 9), f.string() + ": is 10 bytes, more than the 9 a test file may have");
}

// Each kind of path that is not a readable regular file gets its own message, before a byte
// is read: /dev/zero would otherwise be read until memory runs out, a fifo would block.
TEST(RegularFile, RefusesWhatIsNotARegularFile) {
  const std::filesystem::path dir = scratch();
  EXPECT_EQ(outcome(dir, 100), dir.string() + ": is a directory");
  EXPECT_EQ(outcome("/dev/zero", 100),
            "/dev/zero: is not a regular file (a device, fifo or socket)");
  const std::filesystem::path fifo = dir / "fifo";
  std::filesystem::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(outcome(fifo, 100),
            fifo.string() + ": is not a regular file (a device, fifo or socket)");
  const std::filesystem::path link = dir / "zero-link";
  std::filesystem::remove(link);
  std::filesystem::create_symlink("/dev/zero", link);
  EXPECT_EQ(outcome(link, 100),
            link.string() + ": is not a regular file (a device, fifo or socket)");
  EXPECT_EQ(outcome(dir / "absent", 100),
            (dir / "absent").string() + ": cannot open file (no such file)");
}

TEST(RegularFile, AFileNamedInAnotherFileIsReportedUnderItsField) {
  EXPECT_EQ(outcome("/dev/zero", 100, "trace.json: buffer: "),
            "trace.json: buffer: /dev/zero: is not a regular file (a device, fifo or socket)");
}

TEST(RegularFile, PathsResolveAgainstTheReferringFilesFolder) {
  EXPECT_EQ(resolveAgainst("data/traces/tiny.json", "tiny.bin"), "data/traces/tiny.bin");
  EXPECT_EQ(resolveAgainst("tiny.json", "tiny.bin"), "tiny.bin");
  EXPECT_EQ(resolveAgainst("data/kiosk.json", "/var/lib/last.bundle"), "/var/lib/last.bundle");
}

}  // namespace
}  // namespace penumbra::core
