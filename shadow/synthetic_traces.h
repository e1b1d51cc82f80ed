// The synthetic frame traces the rasterizer is tested and benchmarked on (data/traces,
// docs/trace-format.md), built from procedural geometry only; penumbra-synth-trace writes
// them to files.
//
// Each lit scene ("tiny", "pcf", "showroom") runs the whole pre-process of Gibson 2003 on a
// synthetic room: patch mesh (§4), point-to-patch radiance transfers (shadow/
// patch_transfer.h) times ray-cast visibility (§5), source selection by transfer to the
// object, one light frustum per source fitted to the occluder (§7.2), conservative receiver
// sets, intensity transfers by Fig. 4 (§7.1.1), and a ray-cast "photograph" of the empty
// room as the background (§7: the image the shadows are composited into). "edges" is not a
// physical scene but the rasterizer's edge cases (near-plane crossings, slivers, zero-area
// and off-screen triangles) under three point lights. Everything is deterministic: fixed
// seeds, no clocks; the same key gives the same bytes. Cost: the showroom casts 2 x 2 rays
// per pixel against every emitter (a few seconds); the others are milliseconds.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "raster/frame_trace.h"

namespace penumbra::shadow {

struct SyntheticTrace {
  std::string name;  // the file stem under data/traces ("showroom-50" for "showroom")
  raster::FrameTrace trace;
  size_t receiverTriangles = 0;  // over all passes
};

// The keys synthesizeTrace accepts, in the order penumbra-synth-trace writes them.
std::vector<std::string> syntheticTraceKeys();

// Throws std::invalid_argument for a key not in syntheticTraceKeys().
SyntheticTrace synthesizeTrace(const std::string& key);

}  // namespace penumbra::shadow
