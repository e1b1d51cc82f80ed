#include "core/regular_file.h"

#include <fstream>
#include <system_error>

#include "core/error.h"

namespace penumbra::core {

namespace {

[[noreturn]] void fail(const std::filesystem::path& path, ErrorThrower raise,
                       const std::string& context, const std::string& problem) {
  const std::string message = context + path.string() + ": " + problem;
  raise(message);
  throw Error(message);  // a thrower that returns still ends the read
}

}  // namespace

uintmax_t requireRegularFile(const std::filesystem::path& path, uintmax_t maxBytes,
                             const std::string& kind, ErrorThrower raise,
                             const std::string& context) {
  // status() follows symbolic links: a link to /dev/zero is a device.
  std::error_code ec;
  const std::filesystem::file_status status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status)) {
    fail(path, raise, context, "cannot open file (no such file)");
  }
  if (std::filesystem::is_directory(status)) fail(path, raise, context, "is a directory");
  if (!std::filesystem::is_regular_file(status)) {
    fail(path, raise, context, "is not a regular file (a device, fifo or socket)");
  }
  const uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec) fail(path, raise, context, "cannot read its size: " + ec.message());
  if (size > maxBytes) {
    fail(path, raise, context,
         "is " + std::to_string(size) + " bytes, more than the " + std::to_string(maxBytes) + " " +
             kind + " may have");
  }
  return size;
}

std::vector<uint8_t> readRegularFile(const std::filesystem::path& path, uintmax_t maxBytes,
                                     const std::string& kind, ErrorThrower raise,
                                     const std::string& context) {
  const uintmax_t size = requireRegularFile(path, maxBytes, kind, raise, context);
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, raise, context, "cannot open file");
  // Exactly the size checked: a file that grows meanwhile is read up to it, one that shrinks
  // is a read error.
  std::vector<uint8_t> bytes(static_cast<size_t>(size));
  in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size));
  if (static_cast<uintmax_t>(in.gcount()) != size) {
    fail(path, raise, context, "read error (the file changed?)");
  }
  return bytes;
}

std::filesystem::path resolveAgainst(const std::filesystem::path& referrer,
                                     const std::filesystem::path& written) {
  return referrer.parent_path() / written;  // operator/ keeps an absolute `written` as is
}

}  // namespace penumbra::core
