// Footage for the simulated camera (issue 6 §5: "image sequences or video files through
// OpenCV"): what the camera films instead of the bundle's one photograph of the empty room.
// `camera.source` of a session names an image folder, a glob of images ("shots/*.png",
// wildcards in the file name only) or a video file; the frames are read once, checked,
// brought to the calibrated view's size and kept as RGBA8. The virtual camera shows footage
// frame k mod count as its frame k, with its synthetic changes (drift, person, faults) on top.
//
// Determinism: the frames are whatever this machine's OpenCV decodes (and resizes, when the
// footage is not at the view's size); a session with footage replays identically on one
// build, but its hashes are not part of the cross-ISA golden sessions.
#pragma once

#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include "core/error.h"

namespace penumbra::firmware_sim {

class FootageError : public core::Error {
 public:
  using core::Error::Error;
};

// RGBA8 frames of width × height, in order. Throws FootageError naming the file (or
// pattern) and the problem: missing, nothing matches, an unreadable image or video, no
// frames, a frame of another aspect ratio than the view (±1 %) or of another size than the
// sequence's first, or more than `maxBytes` of frames.
std::vector<std::vector<uint8_t>> loadFootage(const std::filesystem::path& source, uint32_t width,
                                              uint32_t height, size_t maxBytes = size_t{1} << 30);

// The files of a sequence, sorted by name: the files of a folder that `accept` takes, or the
// matches of a glob ("shots/*.exr", wildcards in the file name only). Throws FootageError when
// the folder cannot be listed or nothing is found.
std::vector<std::filesystem::path> sequenceFiles(const std::filesystem::path& source,
                                                 bool (*accept)(const std::filesystem::path&));

}  // namespace penumbra::firmware_sim
