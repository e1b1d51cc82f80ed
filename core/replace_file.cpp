#include "core/replace_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

#include "core/error.h"

namespace penumbra::core {

namespace {

[[noreturn]] void fail(const std::filesystem::path& path, const std::string& step, int error) {
  throw Error(path.string(), "", step + ": " + std::strerror(error));
}

// Writes all of `bytes` to `fd`; returns 0 or the errno of the failing write.
int writeAll(int fd, std::span<const uint8_t> bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    done += size_t(n);
  }
  return 0;
}

}  // namespace

void writeFileReplacing(const std::filesystem::path& path, std::span<const uint8_t> bytes) {
  if (path.filename().empty()) throw Error(path.string(), "", "not a file name");
  const std::filesystem::path dir = path.parent_path().empty() ? "." : path.parent_path();
  // A hidden name of this process and call: two writers of one destination never share a
  // temporary, and a left-over one (a power cut) is recognisable. O_EXCL: never an existing
  // file; mode 0666 so that the umask, not this code, decides the result's permissions (as
  // for any file the user's tools create; mkstemp would make it 0600).
  static std::atomic<uint64_t> counter{0};
  std::filesystem::path temporary;
  int fd = -1;
  for (int attempt = 0; fd < 0 && attempt < 100; ++attempt) {
    // Appended, not "." + std::string: GCC 12 warns (-Wrestrict, a false positive, GCC bug
    // 105329) on a literal + temporary string.
    std::string name(".");
    name.append(path.filename().string())
        .append(".tmp-")
        .append(std::to_string(::getpid()))
        .append("-")
        .append(std::to_string(counter.fetch_add(1)));
    temporary = dir / name;
    fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST)
      fail(path, "cannot write (creating " + temporary.string() + ")", errno);
  }
  if (fd < 0) fail(path, "cannot write (no free temporary name)", EEXIST);
  int error = writeAll(fd, bytes);
  std::string step = "cannot write";
  // fsync before rename: otherwise a crash right after the rename can leave the new name
  // pointing at a file whose data never reached the disk (an empty file on ext4).
  if (error == 0 && ::fsync(fd) != 0) {
    error = errno;
    step = "cannot flush to disk";
  }
  if (::close(fd) != 0 && error == 0) {
    error = errno;
    step = "cannot write (close)";
  }
  if (error == 0 && ::rename(temporary.c_str(), path.c_str()) != 0) {
    error = errno;
    step = "cannot replace the file";
  }
  if (error != 0) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    fail(path, step, error);
  }
  // The rename itself is durable once the directory is flushed. The file is complete and in
  // place already, so a directory that cannot be opened or flushed (some file systems refuse
  // fsync on a directory) is not an error.
  const int dirFd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dirFd >= 0) {
    (void)::fsync(dirFd);
    ::close(dirFd);
  }
}

void writeFileReplacing(const std::filesystem::path& path, std::string_view text) {
  writeFileReplacing(
      path, std::span<const uint8_t>(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
}

}  // namespace penumbra::core
