// Reading a whole input file with a bound (docs/input-limits.md). Every loader of the
// project reads its files through readRegularFile, so every one refuses the same things the
// same way before it reads a byte:
//
//   trace.json: is a directory
//   trace.json: buffer: /dev/zero: is not a regular file (a device, fifo or socket)
//   kiosk.json: bundle: big.bundle: is 3000000000 bytes, more than the 536870912 a scene
//   bundle may have
//
// Why: a path written by hand can name a directory (which std::ifstream opens and then
// fails on with "basic_filebuf::underflow"), a device such as /dev/zero (read until memory
// runs out) or a fifo (read blocks forever); and a regular file can be far larger than
// anything the reader could hold. Only a regular file whose size is within the kind's
// limit is opened, and no more than that size is read.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace penumbra::core {

// Throws a finished message as the loader's own error type (E derived from core::Error).
using ErrorThrower = void (*)(const std::string& message);
template <class E>
[[noreturn]] void throwAs(const std::string& message) {
  throw E(message);
}

// A regular file's bytes. `maxBytes` is the kind's limit and `kind` names it in the
// message ("a frame trace's sidecar"). `context` is what comes before the path in a message:
// empty for a file named on the command line, `referrer: field: ` for a file another file
// names. Throws through `raise` with `context + path: problem` when the path does not
// exist, is not a regular file, is larger than maxBytes, or cannot be read whole.
std::vector<uint8_t> readRegularFile(const std::filesystem::path& path, uintmax_t maxBytes,
                                     const std::string& kind, ErrorThrower raise,
                                     const std::string& context = {});

// The checks of readRegularFile without the read, for a file another program or library
// reads (a photograph OpenCV decodes): returns its size.
uintmax_t requireRegularFile(const std::filesystem::path& path, uintmax_t maxBytes,
                             const std::string& kind, ErrorThrower raise,
                             const std::string& context = {});

// A path written in a file (`referrer`): relative to the referrer's folder; an absolute
// path stays as it is (the kiosk keeps its last good bundle wherever the board's storage is).
std::filesystem::path resolveAgainst(const std::filesystem::path& referrer,
                                     const std::filesystem::path& written);

}  // namespace penumbra::core
