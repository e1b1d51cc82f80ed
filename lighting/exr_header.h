// The OpenEXR header, walked by our own code before OpenEXR opens the file. OpenEXR sizes
// its buffers from the header as it opens a file: `Imf::InputFile`'s constructor allocates
// line buffers of (lines per chunk) x (bytes per line) and, for a tiled file, tile buffers,
// before a caller can look at the data window. A 437-byte file announcing 16,777,210 x 6
// half-float pixels made it ask for 2.17 GB (found by the `exr` fuzz target;
// docs/fuzzing.md). So the limits of docs/input-limits.md are checked here, on bytes we
// read ourselves, and only a file that passes goes to OpenEXR.
//
// File layout: OpenEXR's "OpenEXR File Layout" document (magic, version flags, then
// attributes `name\0 type\0 int32 size, value`, ended by an empty name; little-endian).
// Plain C++, built without OpenEXR.
#pragma once

#include <cstdint>
#include <filesystem>

namespace penumbra::lighting {

// The most pixels an HDR image may have: 32 Mpx, an 8192 x 4096 lat-long probe (400 MB of
// float RGB; docs/input-limits.md). A 400-byte file can announce 65536 x 65536 pixels, 51 GB.
inline constexpr int64_t kMaxExrPixels = int64_t{1} << 25;

// The most bytes one chunk (a block of scan lines, or a tile) may take uncompressed, over
// all channels at full resolution: OpenEXR holds a few such buffers at once (line buffer,
// compressor input and output). 64 MiB leaves room for any real probe: an 8192-wide float
// RGBA image compressed with DWAB (256 lines a chunk) needs 32 MiB.
inline constexpr int64_t kMaxExrChunkBytes = int64_t{1} << 26;

// The most chunks (scan-line blocks or tiles over all levels) a file may have: OpenEXR
// reads one 8-byte offset for each before any pixel. An 8192 x 4096 probe in 16 x 16 tiles
// with mipmaps has 174,763.
inline constexpr int64_t kMaxExrChunks = int64_t{1} << 20;

// What the header says about the storage OpenEXR will set up for the file.
struct ExrLayout {
  int64_t width = 0, height = 0;  // of the data window
  int channels = 0;
  int64_t bytesPerPixel = 0;  // over all channels, as if none were subsampled (an upper bound)
  int compression = 0;        // OpenEXR's Compression enum value
  bool tiled = false;
  int64_t tileWidth = 0, tileHeight = 0;  // tiled files
  int levelMode = 0;                      // tiled files: 0 one level, 1 mipmaps, 2 ripmaps
  int64_t linesPerChunk = 0;              // scan-line files
  int64_t chunkBytes = 0;                 // the largest buffer of uncompressed pixels
  int64_t chunks = 0;                     // an upper bound for tiled files with levels
};

// Reads and checks `path`'s header: magic number; a single-part, flat (not deep) image;
// every attribute's size within the file, and the sizes an attribute holds inside it (a
// preview image's pixel count, a string vector's strings) within that size; the data window
// within kMaxExrPixels; channel types and sampling; a known compression;
// chunkBytes within kMaxExrChunkBytes and chunks within kMaxExrChunks. Throws HdrError
// `file: byte N: problem` or `file: field: problem`.
ExrLayout readExrLayout(const std::filesystem::path& path);

}  // namespace penumbra::lighting
