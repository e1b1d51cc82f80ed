// What every libFuzzer target of tests/fuzz shares: the loaders under test read files, so
// an input is written to a scratch folder of this process first; and the oracle: a loader
// may refuse an input only with the project's one error type (core::Error, core/error.h).
// Any other exception (a library's own, std::bad_alloc, std::out_of_range, ...) escapes
// the target, libFuzzer reports it as a crash and keeps the input: a message without file
// and field is a bug too (issue 18 "Limits by design").
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>

#include "core/error.h"

namespace penumbra::fuzz {

// This process's scratch folder (removed at exit): `$TMPDIR/penumbra-fuzz-<pid>`, and the
// process's working directory from its first input on. Two targets running in parallel, or
// libFuzzer's fork-mode workers, never share files. Inputs are named relative to it, so no
// message a loader builds contains the checkout's path, $TMPDIR or the pid: the lengths of
// those strings change loop counts in instrumented code, hence libFuzzer's features, and
// CI's fixed campaign (.ci/fuzz --ci) would explore differently in another folder (stop 21's
// CI found a scene_file input that the same campaign under /work did not reach).
// .ci/fuzz passes libFuzzer absolute corpus and artifact paths, so changing directory does
// not move them.
inline const std::filesystem::path& scratchDir() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path d =
        std::filesystem::temp_directory_path() / ("penumbra-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    std::filesystem::current_path(d);
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(scratchDir(), ignored);
    });
    return d;
  }();
  return dir;
}

// Writes `bytes` to `name` in the scratch folder and returns `name` (relative to the
// scratch folder, the working directory).
inline std::filesystem::path writeScratch(const std::string& name, std::span<const uint8_t> bytes) {
  const std::filesystem::path path = scratchDir() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  return name;
}

// A symbolic link `name` in the scratch folder to `target`, returned as `name`: a data
// folder reached by a path of fixed length.
inline std::filesystem::path linkIntoScratch(const std::string& name,
                                             const std::filesystem::path& target) {
  const std::filesystem::path link = scratchDir() / name;
  std::error_code ignored;
  std::filesystem::remove(link, ignored);
  std::filesystem::create_directory_symlink(target, link);
  return name;
}

// The JSON targets' input (tests/fuzz/json_mutator.cpp): JSON text, then optionally a NUL
// byte and a binary tail (a sidecar file).
struct TextAndTail {
  std::span<const uint8_t> text, tail;
};
inline TextAndTail splitAtNul(const uint8_t* data, size_t size) {
  const std::span<const uint8_t> all(data, size);
  for (size_t i = 0; i < size; ++i) {
    if (data[i] == 0) return {all.first(i), all.subspan(i + 1)};
  }
  return {all, {}};
}

// Runs `load`; a core::Error is the expected refusal of a bad input, anything else escapes.
template <class Load>
void expectOnlyProjectErrors(Load&& load) {
  try {
    load();
  } catch (const core::Error&) {
  }
}

}  // namespace penumbra::fuzz
