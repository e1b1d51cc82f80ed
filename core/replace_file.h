// Writing an output file so that no reader ever sees half of it: the bytes go to a temporary
// file in the same directory, are flushed to the disk (fsync), and the temporary is renamed
// over the destination (rename(2) replaces a name atomically within one file system, hence
// the same directory). An error at any step removes the temporary and throws core::Error
// naming the destination (`lens.json: cannot write: No space left on device`): a failed run
// leaves either the old file or none, never a partial one.
//
// Cost: one extra fsync of the file and one of its directory; meant for results (calibrations,
// reports), not for streams of frames.
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>

namespace penumbra::core {

void writeFileReplacing(const std::filesystem::path& path, std::span<const uint8_t> bytes);
void writeFileReplacing(const std::filesystem::path& path, std::string_view text);

}  // namespace penumbra::core
