// The frame trace: one frame exactly as the rasterizer consumes it (docs/trace-format.md).
//
// A trace is the rasterizer's whole input: the fixed camera and static receiver mesh
// (`StaticView`, cached by the Renderer across frames because the kiosk camera does not
// move) and the per-frame content (`FrameContent`: background photograph, shaded synthetic
// objects, occluder proxies and the shadow passes of Gibson 2003 §7, Fig. 2).
//
// On disk: a JSON file plus one little-endian binary sidecar holding the arrays.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/colour.h"
#include "core/error.h"
#include "core/geometry.h"

namespace penumbra::raster {

// A synthetic object, already shaded: one 8-bit colour per vertex (tone-mapped).
struct ShadedMesh {
  core::Mesh mesh;
  std::vector<core::Rgb8> colours;
  bool operator==(const ShadedMesh&) const = default;
};

// One blending pass (Gibson 2003 Fig. 2, inner loop): a shadow map of an occluder proxy
// seen from one source cluster, and the receiver triangles whose pixels lose
// S * M (intensity transfer times occlusion mask) in 8 bits.
struct ShadowPass {
  core::Mat4 lightViewProj;      // world -> light clip space (perspective from the source)
  uint32_t shadowMapSize = 256;  // square, a multiple of 16, at most 4096
  float depthBias = 0.0f;        // in light window depth ([0, 1]) units
  bool pcf2x2 = false;           // fractional 2x2 mask instead of a binary one
  uint32_t occluder = 0;         // index into FrameContent::occluders
  // Draw only the occluder's triangles that face the light (not facesAwayOnMap): the same
  // map for a closed surface wound counter-clockwise from outside (raster/closed_surface.h),
  // half the triangles.
  bool cullBackFaces = false;
  std::vector<uint32_t> receiverTriangles;  // indices into StaticView::staticMesh triangles
  // Intensity transfers S in 8.8 levels (core::Rgb16), 3 per receiver triangle, in corner
  // order. With u8 accumulation each pixel's S is rounded to whole levels (spec §5).
  std::vector<core::Rgb16> receiverS;
  // Self-shadowing (Gibson 2003 §7.2): triangles of the synthetic objects that receive this
  // pass too — indices into all objects' triangles counted in order — with S per corner,
  // and the bias for them (the proxy only approximates the object's own surface).
  std::vector<uint32_t> objectTriangles;
  std::vector<core::Rgb16> objectS;
  float objectDepthBias = 0.0f;
  // Area-light penumbrae (docs/pipeline-spec.md §7): with penumbraScale > 0 each receiver
  // pixel behind every occluder texel takes the share of the map's occluder texels in a box
  // of half-width penumbraScale * (d - b) texels around its lookup, b the mean depth of the
  // occluder texels found around it, the penumbra a light of the cluster's extent casts,
  // instead of the 2x2 PCF. Needs pcf2x2 and a map of at most kMaxAreaPenumbraMapSize
  // texels a side.
  float penumbraScale = 0.0f;  // texels of half-width per unit of window depth
  bool operator==(const ShadowPass&) const = default;
};

// The largest map an area-penumbra pass may use: its coverage sums, weighted in 1/64
// texel, then stay below 2^31 (spec §7).
inline constexpr uint32_t kMaxAreaPenumbraMapSize = 512;
// And the lookup's other constants: box corners in 1/kPenumbraSubtexels texel, the box's
// half-width at most kMaxPenumbraHalfWidth texels, the 2x2 PCF up to kMinPenumbraHalfWidth.
inline constexpr int32_t kPenumbraSubtexels = 64;
inline constexpr float kMaxPenumbraHalfWidth = 32.0f;
inline constexpr float kMinPenumbraHalfWidth = 0.5f;
// The blocker search sums written depths in 1/kDepthQuantum over cells of kBlockerCell
// texels a side (ShadowMap::sumBlockers).
inline constexpr float kDepthQuantum = 65536.0f;
inline constexpr int32_t kBlockerCell = 2;

struct StaticView {
  uint32_t width = 0, height = 0;
  core::Mat4 cameraViewProj;  // world -> camera clip space
  core::Mesh staticMesh;      // the patch mesh of the real room, drawn into depth and id only
  bool operator==(const StaticView&) const = default;
};

// How a frame sums its passes' amounts (docs/pipeline-spec.md §8). kU8: each pass's
// round(S·M/255) is a whole level, summed (Gibson 2003 Fig. 2's 8-bit blending). kFixed8_8:
// each pass adds S·M/255 rounded to 1/256 level, the sum is rounded to whole levels once per
// pixel, so many faint passes do not accumulate one rounding each (Gibson 2003 §10;
// docs/failure-regimes.md). Both use the same 16-bit sum planes.
// How a frame's passes are summed and applied (docs/pipeline-spec.md §8): kU8, the paper's
// 8-bit subtraction per pass; kFixed8_8, 8.8 S subtracted once per pixel; kLinear, S as the
// share of the pixel's light each pass's sources carry, the pixel's light scaled once
// through the frame's shade table (FrameContent::shadeTable).
enum class Accumulation : uint8_t { kU8, kFixed8_8, kLinear };

// kLinear's shade table: kShadeCodes base codes by kShadeSteps occluded shares q / 510.
inline constexpr size_t kShadeSteps = 511;
inline constexpr size_t kShadeCodes = 256;

// "u8" / "fixed8_8" (the trace field's values).
const char* accumulationName(Accumulation a);
// The Accumulation named `name`; throws TraceError naming `where` otherwise.
Accumulation parseAccumulation(const std::string& name, const std::string& where);

struct FrameContent {
  std::vector<uint8_t> background;  // RGBA8, width*height*4, row 0 at the top
  std::vector<ShadedMesh> objects;
  std::vector<core::Mesh> occluders;  // simplified proxies (Gibson 2003 §7.2: 100-500 triangles)
  std::vector<ShadowPass> passes;     // applied in this order
  Accumulation accumulation = Accumulation::kU8;
  // kLinear only (else empty): shadeTable[c * kShadeSteps + q] is the code of a pixel of
  // code c whose light is occluded by the share q / 510: the camera response T applied to
  // T^-1(c) (1 - q / 510) (spec §8).
  std::vector<uint8_t> shadeTable;
  bool operator==(const FrameContent&) const = default;
};

struct FrameTrace {
  StaticView view;
  FrameContent frame;
  bool operator==(const FrameTrace&) const = default;
};

// Every failure to read or validate a trace: the message names the file and the field.
class TraceError : public core::Error {
 public:
  using core::Error::Error;
};

// Limits a valid trace respects (docs/trace-format.md §Limits, docs/input-limits.md), each
// with its reason. Together they bound what a hostile trace can make the loader and the
// renderer allocate.
// Snapped coordinates stay below 2^22 only up to this side (docs/pipeline-spec.md §3).
inline constexpr uint32_t kMaxImageSide = 4096;
inline constexpr uint32_t kMaxShadowMapSize = 4096;
// Each pass subtracts at most 255 per channel and the renderer sums them in 16 bits (spec
// §8): 257 * 255 = 65535.
inline constexpr size_t kMaxPasses = 257;
// The renderer keeps a setup triangle (~150 bytes) and a span list per static and object
// triangle: 2^22 of each is ~1.3 GB at most, the memory of the board. A showroom's patch
// mesh has a few thousand triangles, a product model (after scene/mesh_simplify) at most
// a few hundred thousand. (The 32-bit id buffer of raster/span_kernels.h would allow 2^31.)
inline constexpr size_t kMaxStaticTriangles = size_t{1} << 22;
inline constexpr size_t kMaxObjectTriangles = size_t{1} << 22;
// Occluder proxies have 100-500 triangles (Gibson 2003 §7.2); all of them together at most:
inline constexpr size_t kMaxOccluderTriangles = size_t{1} << 20;
// The binary sidecar, and all views of it together (views may overlap): a 4096 x 4096
// background is 64 MiB and the triangle limits above need ~200 MiB more; 1 GiB leaves room
// and stops /dev/zero-like files long before memory runs out.
inline constexpr uint64_t kMaxSidecarBytes = uint64_t{1} << 30;

// Checks sizes, indices and finiteness; throws TraceError naming `where` and the field.
void validateTrace(const FrameTrace& trace, const std::string& where);

// Checks the per-frame part against a view of `width` x `height` with `staticTriangles`
// static triangles; throws TraceError naming `where` and the field.
void validateFrame(const FrameContent& frame, uint32_t width, uint32_t height,
                   size_t staticTriangles, const std::string& where);

// Reads `path` (JSON) and its binary sidecar; validates. Throws TraceError. `maxBytes` bounds
// the sidecar and, separately, all views together (kMaxSidecarBytes; tests pass less to
// reach the views' bound without a gigabyte of memory).
FrameTrace loadTrace(const std::filesystem::path& path, uint64_t maxBytes = kMaxSidecarBytes);

// Writes `path` (JSON) and `<stem>.bin` beside it. Throws TraceError on I/O failure.
void saveTrace(const FrameTrace& trace, const std::filesystem::path& path);

}  // namespace penumbra::raster
