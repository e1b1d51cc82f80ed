#include "raster/renderer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "core/job_pool.h"
#include "raster/aligned_vector.h"
#include "raster/matrix4d.h"
#include "raster/occluder_setup.h"
#include "raster/receiver_bands.h"
#include "raster/shadow_map.h"
#include "raster/span_kernels.h"
#include "raster/triangle_setup.h"

namespace penumbra::raster {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr size_t kRowAlign = 64;  // pixels; spec §8

struct ObjectTriangle {
  SetupTriangle t;
  SpanPlanes planes;
  uint32_t owner;  // index of the unclipped triangle among all objects' triangles
};

// What one thread needs to run passes (spec §8: each thread sums its passes' amounts).
// Cache-line aligned: a thread writes its counters and map bounds for every shadow-map
// triangle, and the next thread's Worker must not share those lines.
struct alignas(64) Worker {
  ShadowMap shadowMap;
  // S of the current pass, zero between passes: packed whole levels (u8 accumulation) or
  // r, g, b planes of 8.8 levels (fixed8_8). Each is allocated by the first frame that needs
  // it (a kiosk renders one kind only).
  AlignedVector<uint32_t> s;
  AlignedVector<uint16_t> sFine;
  AlignedVector<uint16_t> acc;              // r, g, b planes: sum of this thread's per-pass amounts
  std::vector<int32_t> passBegin, passEnd;  // per row: run of the current pass
  std::vector<int32_t> touchedBegin, touchedEnd;       // per row: union over this frame
  int32_t mapX0 = 0, mapY0 = 0, mapX1 = 0, mapY1 = 0;  // what the last pass wrote
  std::vector<ClipVertex> clip;
  std::vector<std::array<SnappedVertex, 3>> fan;
  SetupTriangle setup;  // a clipped shadow-map triangle being drawn (runPass)
  // The occluder's snapped vertices and set-up triangles when it needs no clipping.
  std::vector<int32_t> mapX, mapY;
  std::vector<float> mapZ;
  std::vector<SetupTriangle> mapTriangles;
  // Per object triangle: 1 when one of this thread's tiles shows a pixel of it.
  std::vector<uint8_t> objectSeen;
  uint64_t mapPixels = 0, passPixels = 0, objectPixels = 0, mapTriangleCount = 0, mapTexels = 0;
};

}  // namespace

struct Renderer::Impl {
  StaticView view;
  RenderOptions options;
  const SpanKernels* kernels;
  const OccluderKernels* occluderKernels;
  core::JobPool pool;
  size_t stride;     // pixels per internal row (spec §8)
  size_t planeSize;  // stride * height
  // The last linear frame's shade table, padded by 3 bytes (SpanKernels::shadeAccumulatedLinear).
  std::vector<uint8_t> shadeTable;
  int32_t width, height, tilesX, tilesY;
  Mat4d windowToWorld;  // C^-1 V^-1 (spec §7)

  // Static cache (spec §6 step 2).
  std::vector<SetupTriangle> staticSubs;
  std::vector<uint32_t> staticSubOwner;      // original triangle index of each sub-triangle
  std::vector<uint32_t> firstSubOfTriangle;  // triangle t -> subs [first[t], first[t+1])
  AlignedVector<float> staticDepth;
  AlignedVector<uint32_t> staticId;
  // Row runs of every static sub-triangle, computed once (spec §4): the camera is fixed.
  // Sub-triangle s has rows [minY, maxY) at spanStart[s]; empty runs have xa >= xb.
  std::vector<uint32_t> spanStart;
  std::vector<std::pair<int32_t, int32_t>> spans;
  std::vector<uint32_t> triangleCoverage;  // pixels of each static triangle's runs
  // Sub-triangle s's rows in bands of kReceiverBandRows from its minY:
  // bands[bandStart[s], bandStart[s + 1]) (raster/receiver_bands.h).
  std::vector<uint32_t> bandStart;
  std::vector<ReceiverBand> bands;
  std::vector<ReceiverBand> subBands;  // per sub-triangle, the union of its bands
  // Per tile row, the pixel columns [first, second) of this frame's tiles with objects
  // (empty when first >= second): there the id buffer is not the static one.
  std::vector<std::pair<int32_t, int32_t>> objectColumns;
  bool touchesObjects(const ReceiverBand& b) const {
    for (int32_t ty = b.y0 / options.tileSize; ty <= b.y1 / options.tileSize; ++ty) {
      const auto [first, second] = objectColumns[size_t(ty)];
      if (first <= b.x1 && second > b.x0) return true;
    }
    return false;
  }
  std::vector<uint32_t> passOrder;  // this frame's passes, longest first
  std::vector<uint64_t> passCost;

  // Frame buffers. depth and id equal the static cache except in tiles that hold object
  // pixels; rgba holds a tile's base colours only while the tile is being drawn.
  AlignedVector<uint8_t> rgba;
  AlignedVector<float> depth;
  AlignedVector<uint32_t> id;
  std::vector<uint8_t> tileHasObject, tileHadObject;
  std::vector<uint32_t> objectTiles;  // tiles with objects now or last frame, costliest first
  std::vector<ObjectTriangle> objectTriangles;
  std::vector<uint32_t> objectFirstSub;  // object triangle g -> [first[g], first[g + 1])
  // Row runs of every object sub-triangle, once per frame when some pass lists object
  // receivers (self-shadowing): every pass then reuses them, as it does the room's.
  std::vector<uint32_t> objectSpanStart;
  std::vector<std::pair<int32_t, int32_t>> objectSpans;
  // The binned object triangles, tile by tile in one array (tile t's are
  // tileObjects[tileObjectStart[t], tileObjectStart[t + 1]), in triangle order). One flat array
  // instead of a vector per tile: per-tile vectors each kept their own largest size, and as a
  // product wandered over the screen they grew tile after tile (heaptrack: 404 of the 441 kB
  // the soak's heap grew from frame 3000 to 12000); the flat one is as large as the most refs
  // of one frame.
  struct TileRef {
    uint32_t tile, object;
    bool full;
  };
  std::vector<TileRef> binned;  // in triangle order, as classified
  std::vector<std::pair<uint32_t, bool>> tileObjects;
  std::vector<uint32_t> tileObjectStart;  // tiles + 1 offsets
  std::vector<uint32_t> binFill;          // the counting sort's write positions
  std::span<const std::pair<uint32_t, bool>> objectsOf(size_t tile) const {
    return {tileObjects.data() + tileObjectStart[tile],
            tileObjects.data() + tileObjectStart[tile + 1]};
  }
  // Per object triangle: shown by some pixel this frame (the workers' objectSeen merged).
  std::vector<uint8_t> objectVisible;
  std::vector<Worker> workers;
  FrameStats stats;

  Impl(const StaticView& v, const RenderOptions& o);
  void buildStaticCache();
  void prepareObjects(const FrameContent& frame);
  void compositeObjects(uint32_t tile, const FrameContent& frame, Worker& w);
  void runPass(const FrameContent& frame, size_t index, Worker& w);
  void probePass(const ShadowPass& pass, const Worker& w, size_t index);
  std::span<const core::Vec3> probes;  // this frame's occlusion probes (may be empty)
  size_t objectProbesFrom = SIZE_MAX;
  std::vector<uint8_t>* probeMasks = nullptr;
  void finishTile(uint32_t tile, const FrameContent& frame, std::span<uint8_t> out);
  void tileRect(uint32_t tile, int32_t& x0, int32_t& y0, int32_t& x1, int32_t& y1) const {
    x0 = static_cast<int32_t>(tile % static_cast<uint32_t>(tilesX)) * options.tileSize;
    y0 = static_cast<int32_t>(tile / static_cast<uint32_t>(tilesX)) * options.tileSize;
    x1 = std::min(x0 + options.tileSize, width);
    y1 = std::min(y0 + options.tileSize, height);
  }
};

Renderer::Impl::Impl(const StaticView& v, const RenderOptions& o)
    : view(v),
      options(o),
      kernels(nullptr),
      occluderKernels(nullptr),
      pool(std::max(1, o.threads)) {
  if (o.threads < 1 || o.threads > 256) throw std::invalid_argument("threads must be in 1..256");
  if (o.tileSize != 16 && o.tileSize != 32 && o.tileSize != 64) {
    throw std::invalid_argument("tile size must be 16, 32 or 64");
  }
  if (!simd::isSupported(o.isa)) {
    throw std::invalid_argument(std::string("SIMD target ") + simd::isaName(o.isa) +
                                " is not supported on this CPU or not compiled in");
  }
  kernels = &spanKernelsFor(o.isa);
  occluderKernels = &occluderKernelsFor(o.isa);
  FrameTrace probe;
  probe.view = v;
  probe.frame.background.resize(size_t{v.width} * v.height * 4);
  validateTrace(probe, "static view");  // also: the camera matrix is invertible
  Mat4d cameraInverse;
  invert(toDouble(v.cameraViewProj), cameraInverse);
  const double hw = v.width / 2.0, hh = v.height / 2.0;
  const Mat4d viewportInverse = {1.0 / hw, 0, 0, -1, 0, -1.0 / hh, 0, 1, 0, 0, 2, -1, 0, 0, 0, 1};
  windowToWorld = multiply(cameraInverse, viewportInverse);
  width = static_cast<int32_t>(v.width);
  height = static_cast<int32_t>(v.height);
  stride = (size_t{v.width} + kRowAlign - 1) / kRowAlign * kRowAlign;
  planeSize = stride * v.height;
  tilesX = (width + o.tileSize - 1) / o.tileSize;
  tilesY = (height + o.tileSize - 1) / o.tileSize;
  const size_t tiles = size_t(tilesX) * size_t(tilesY);
  rgba.assign(planeSize * 4, 0);
  tileHasObject.assign(tiles, 0);
  tileHadObject.assign(tiles, 0);
  tileObjectStart.assign(tiles + 1, 0);
  workers.resize(size_t(pool.threads()));
  for (Worker& w : workers) {
    w.acc.assign(planeSize * 3, 0);
    w.passBegin.assign(v.height, width);
    w.passEnd.assign(v.height, 0);
    w.touchedBegin.assign(v.height, width);
    w.touchedEnd.assign(v.height, 0);
  }
  buildStaticCache();
  depth = staticDepth;
  id = staticId;
}

void Renderer::Impl::buildStaticCache() {
  const core::Mesh& mesh = view.staticMesh;
  std::vector<ClipVertex> clip(mesh.positions.size());
  for (size_t i = 0; i < clip.size(); ++i) {
    clip[i] = transformPoint(view.cameraViewProj, mesh.positions[i]);
  }
  std::vector<std::array<SnappedVertex, 3>> fan;
  const size_t triangles = mesh.triangleCount();
  firstSubOfTriangle.assign(triangles + 1, 0);
  for (size_t t = 0; t < triangles; ++t) {
    firstSubOfTriangle[t] = static_cast<uint32_t>(staticSubs.size());
    fan.clear();
    clipAndSnapTriangle(
        {clip[mesh.indices[3 * t]], clip[mesh.indices[3 * t + 1]], clip[mesh.indices[3 * t + 2]]},
        view.width, view.height, fan);
    for (const auto& tri : fan) {
      SetupTriangle s;
      if (!setupTriangle(tri, view.width, view.height, s)) continue;
      staticSubs.push_back(s);
      staticSubOwner.push_back(static_cast<uint32_t>(t));
    }
  }
  firstSubOfTriangle[triangles] = static_cast<uint32_t>(staticSubs.size());

  // Depth, ids and runs once, in triangle order (spec §6 step 2).
  staticDepth.assign(planeSize, kInfinity);
  staticId.assign(planeSize, kNoSurface);
  spanStart.assign(staticSubs.size() + 1, 0);
  for (size_t s = 0; s < staticSubs.size(); ++s) {
    const SetupTriangle& t = staticSubs[s];
    spanStart[s] = static_cast<uint32_t>(spans.size());
    spans.resize(spans.size() + size_t(t.maxY - t.minY), {0, 0});
    const SpanPlanes planes{t.depth, {}, t.minX, t.minY};
    forEachRun(t, 0, 0, width, t.maxY, false, [&](int32_t y, int32_t xa, int32_t xb) {
      spans[spanStart[s] + size_t(y - t.minY)] = {xa, xb};
      kernels->depthLess(staticDepth.data() + stride * y, staticId.data() + stride * y, xa, xb, y,
                         planes, staticSubOwner[s]);
    });
  }
  spanStart[staticSubs.size()] = static_cast<uint32_t>(spans.size());
  // Bands once the static depth and ids are final.
  bandStart.assign(staticSubs.size() + 1, 0);
  for (size_t s = 0; s < staticSubs.size(); ++s) {
    bandStart[s] = static_cast<uint32_t>(bands.size());
    appendReceiverBands(staticSubs[s].minY, staticSubs[s].maxY, &spans[spanStart[s]],
                        staticDepth.data(), staticId.data(), stride, staticSubOwner[s], bands);
    ReceiverBand whole;
    for (size_t b = bandStart[s]; b < bands.size(); ++b) whole = unite(whole, bands[b]);
    subBands.push_back(whole);
  }
  bandStart[staticSubs.size()] = static_cast<uint32_t>(bands.size());
  triangleCoverage.assign(triangles, 0);
  for (size_t s = 0; s < staticSubs.size(); ++s) {
    for (uint32_t k = spanStart[s]; k < spanStart[s + 1]; ++k) {
      const auto [xa, xb] = spans[k];
      if (xa < xb) triangleCoverage[staticSubOwner[s]] += static_cast<uint32_t>(xb - xa);
    }
  }
}

void Renderer::Impl::prepareObjects(const FrameContent& frame) {
  objectTriangles.clear();
  objectFirstSub.clear();
  std::vector<ClipVertex> clip;
  std::vector<std::array<SnappedVertex, 3>> fan;
  for (const ShadedMesh& object : frame.objects) {
    const core::Mesh& mesh = object.mesh;
    clip.resize(mesh.positions.size());
    for (size_t i = 0; i < clip.size(); ++i) {
      clip[i] = transformPoint(view.cameraViewProj, mesh.positions[i]);
    }
    for (size_t t = 0; t < mesh.triangleCount(); ++t) {
      const uint32_t* idx = &mesh.indices[3 * t];
      const uint32_t owner = static_cast<uint32_t>(objectFirstSub.size());
      objectFirstSub.push_back(static_cast<uint32_t>(objectTriangles.size()));
      fan.clear();
      clipAndSnapTriangle({clip[idx[0]], clip[idx[1]], clip[idx[2]]}, view.width, view.height, fan);
      const core::Rgb8 c0 = object.colours[idx[0]], c1 = object.colours[idx[1]],
                       c2 = object.colours[idx[2]];
      for (const auto& tri : fan) {
        ObjectTriangle o;
        if (!setupTriangle(tri, view.width, view.height, o.t)) continue;
        o.planes.depth = o.t.depth;
        o.planes.rgb[0] = attributePlane(o.t, {c0.r, c1.r, c2.r});
        o.planes.rgb[1] = attributePlane(o.t, {c0.g, c1.g, c2.g});
        o.planes.rgb[2] = attributePlane(o.t, {c0.b, c1.b, c2.b});
        o.planes.ox = o.t.minX;
        o.planes.oy = o.t.minY;
        o.owner = owner;
        objectTriangles.push_back(o);
      }
    }
  }
  objectFirstSub.push_back(static_cast<uint32_t>(objectTriangles.size()));
  objectSpanStart.clear();
  objectSpans.clear();
  const bool selfShadowing =
      std::any_of(frame.passes.begin(), frame.passes.end(),
                  [](const ShadowPass& p) { return !p.objectTriangles.empty(); });
  if (selfShadowing) {
    for (const ObjectTriangle& o : objectTriangles) {
      objectSpanStart.push_back(static_cast<uint32_t>(objectSpans.size()));
      const size_t first = objectSpans.size();
      objectSpans.resize(first + size_t(o.t.maxY - o.t.minY), {0, 0});
      forEachRun(o.t, 0, 0, width, height, false, [&](int32_t y, int32_t xa, int32_t xb) {
        objectSpans[first + size_t(y - o.t.minY)] = {xa, xb};
      });
    }
  }
  // Binning with trivial reject / accept (spec §4), in triangle order.
  const int32_t ts = options.tileSize;
  std::fill(tileHasObject.begin(), tileHasObject.end(), 0);
  binned.clear();
  for (size_t o = 0; o < objectTriangles.size(); ++o) {
    const SetupTriangle& t = objectTriangles[o].t;
    for (int32_t ty = t.minY / ts; ty <= (t.maxY - 1) / ts; ++ty) {
      for (int32_t tx = t.minX / ts; tx <= (t.maxX - 1) / ts; ++tx) {
        const int32_t x0 = tx * ts, y0 = ty * ts;
        const TileCoverage c =
            classifyTile(t, x0, y0, std::min(x0 + ts, width), std::min(y0 + ts, height));
        if (c == TileCoverage::kNone) continue;
        const size_t tile = size_t(ty) * size_t(tilesX) + size_t(tx);
        binned.push_back(
            {static_cast<uint32_t>(tile), static_cast<uint32_t>(o), c == TileCoverage::kFull});
        tileHasObject[tile] = 1;
      }
    }
  }
  // A counting sort by tile, stable: each tile's triangles stay in triangle order, which the
  // depth test's ties depend on (spec §4).
  std::fill(tileObjectStart.begin(), tileObjectStart.end(), 0);
  for (const TileRef& r : binned) ++tileObjectStart[r.tile + 1];
  for (size_t t = 1; t < tileObjectStart.size(); ++t) tileObjectStart[t] += tileObjectStart[t - 1];
  tileObjects.resize(binned.size());
  binFill.assign(tileObjectStart.begin(), tileObjectStart.end() - 1);
  for (const TileRef& r : binned) tileObjects[binFill[r.tile]++] = {r.object, r.full};
}

// Spec §6 step 3 for one tile; also undoes the previous frame's object in it.
void Renderer::Impl::compositeObjects(uint32_t tile, const FrameContent& frame, Worker& w) {
  if (!tileHasObject[tile] && !tileHadObject[tile]) return;
  int32_t x0, y0, x1, y1;
  tileRect(tile, x0, y0, x1, y1);
  // The tile owns the row padding right of the image (spec §8).
  const int32_t ownedX1 = x1 == width ? static_cast<int32_t>(stride) : x1;
  for (int32_t y = y0; y < y1; ++y) {
    const size_t row = stride * size_t(y);
    std::memcpy(&depth[row + x0], &staticDepth[row + x0], sizeof(float) * size_t(ownedX1 - x0));
    std::memcpy(&id[row + x0], &staticId[row + x0], sizeof(uint32_t) * size_t(ownedX1 - x0));
  }
  if (!tileHasObject[tile]) return;
  for (int32_t y = y0; y < y1; ++y) {
    std::memcpy(&rgba[4 * (stride * size_t(y) + size_t(x0))],
                &frame.background[4 * (size_t(width) * size_t(y) + size_t(x0))],
                4 * size_t(x1 - x0));
  }
  for (const auto& [index, full] : objectsOf(tile)) {
    const ObjectTriangle& o = objectTriangles[index];
    forEachRun(o.t, x0, y0, x1, y1, full, [&](int32_t y, int32_t xa, int32_t xb) {
      const size_t row = stride * size_t(y);
      w.objectPixels += kernels->colourLess(&rgba[4 * row], &depth[row], &id[row], xa, xb, y,
                                            o.planes, kObjectBase + o.owner);
    });
  }
  // Which object triangles the tile shows, now that its ids are final (runPass skips the
  // others).
  for (int32_t y = y0; y < y1; ++y) {
    const uint32_t* ids = &id[stride * size_t(y)];
    for (int32_t x = x0; x < x1; ++x) {
      // Static ids and kNoSurface wrap past the object count.
      const uint32_t g = ids[x] - kObjectBase;
      if (g < w.objectSeen.size()) w.objectSeen[g] = 1;
    }
  }
}

// One pass on one thread (spec §6 steps 1 and 4, §7): its shadow map, then S of every
// receiver run, then one sweep that adds round(S * M / 255) to this thread's sums.
void Renderer::Impl::runPass(const FrameContent& frame, size_t index, Worker& w) {
  const ShadowPass& pass = frame.passes[index];
  const uint32_t size = pass.shadowMapSize;
  const int32_t isize = static_cast<int32_t>(size);
  w.mapTexels += uint64_t{size} * size;

  // The map is +inf outside the rectangle the previous pass on this thread wrote, so only
  // that rectangle needs clearing (and the whole map when the size changes).
  if (w.shadowMap.size() != isize) {
    w.shadowMap.reset(isize);
  } else {
    w.shadowMap.clear(w.mapX0, w.mapY0, w.mapX1, w.mapY1);
  }
  w.mapX0 = w.mapY0 = isize;
  w.mapX1 = w.mapY1 = 0;
  const core::Mesh& occluder = frame.occluders[pass.occluder];
  auto draw = [&](const SetupTriangle& t) {
    ++w.mapTriangleCount;
    w.mapPixels +=
        kernels->depthTriangle(w.shadowMap.origin(), nullptr, size_t(w.shadowMap.stride()), t, 0);
    w.shadowMap.markWritten(t.minX, t.minY, t.maxX, t.maxY);
    w.mapX0 = std::min(w.mapX0, t.minX);
    w.mapY0 = std::min(w.mapY0, t.minY);
    w.mapX1 = std::max(w.mapX1, t.maxX);
    w.mapY1 = std::max(w.mapY1, t.maxY);
  };
  // Usually the light frustum encloses the whole occluder (Gibson 2003 §7.2): then every
  // triangle is drawn unclipped and each vertex snaps once, exactly as clipAndSnapTriangle
  // would snap it (the corner weights do not matter for depth), several vertices and
  // triangles per vector (raster/occluder_setup.h).
  const size_t vertices = occluder.positions.size();
  const size_t padded = (vertices + kOccluderBatch - 1) / kOccluderBatch * kOccluderBatch;
  w.mapX.resize(padded);
  w.mapY.resize(padded);
  w.mapZ.resize(padded);
  if (occluderKernels->snapInside(pass.lightViewProj, occluder.positions.data(), vertices, size,
                                  w.mapX.data(), w.mapY.data(), w.mapZ.data())) {
    w.mapTriangles.resize(occluder.triangleCount());
    const size_t accepted = occluderKernels->setupTriangles(
        w.mapX.data(), w.mapY.data(), w.mapZ.data(), occluder.indices.data(),
        occluder.triangleCount(), size, pass.cullBackFaces, w.mapTriangles.data());
    for (size_t t = 0; t < accepted; ++t) draw(w.mapTriangles[t]);
  } else {
    w.clip.resize(vertices);
    for (size_t i = 0; i < vertices; ++i) {
      w.clip[i] = transformPoint(pass.lightViewProj, occluder.positions[i]);
    }
    for (size_t t = 0; t < occluder.triangleCount(); ++t) {
      const uint32_t* idx = &occluder.indices[3 * t];
      w.fan.clear();
      clipAndSnapTriangle({w.clip[idx[0]], w.clip[idx[1]], w.clip[idx[2]]}, size, size, w.fan);
      for (const auto& tri : w.fan) {
        if (pass.cullBackFaces && facesAwayOnMap(tri)) continue;
        if (setupTriangle(tri, size, size, w.setup)) draw(w.setup);
      }
    }
  }

  ShadowLookup lookup{};
  const double half = size / 2.0;
  const Mat4d toTexel = {half, 0, 0, half, 0, -half, 0, half, 0, 0, 0.5, 0.5, 0, 0, 0, 1};
  const Mat4d p = multiply(multiply(toTexel, toDouble(pass.lightViewProj)), windowToWorld);
  for (int i = 0; i < 16; ++i) lookup.p[i] = static_cast<float>(p[i]);
  if (!probes.empty()) probePass(pass, w, index);
  lookup.map = w.shadowMap.origin();
  lookup.size = isize;
  lookup.stride = w.shadowMap.stride();
  lookup.bias = pass.depthBias;
  lookup.pcf2x2 = pass.pcf2x2;
  lookup.blocks = w.shadowMap.blocks();
  lookup.blocksPerRow = w.shadowMap.blocksPerRow();
  w.shadowMap.sumBlocks();
  const bool areaPenumbra = pass.penumbraScale > 0;
  if (areaPenumbra) {
    w.shadowMap.sumCoverage(w.mapX0, w.mapY0, w.mapX1, w.mapY1);
    // The room's receivers only: the scale goes back to 0 for objects.
    setAreaPenumbra(lookup, w.shadowMap, pass.penumbraScale);
  }
  // An area-penumbra pass's boxes reach past the 2x2 footprint (LightFootprint widens it by
  // each band's widest box); a box meeting no written texel gives W = 0 as well.
  const LightFootprint footprint(lookup, w.shadowMap);
  // A band without a matching pixel adds nothing; one whose footprint meets no written texel
  // adds nothing either (W = 0, receiver_bands.h), and outside the tiles with objects its
  // pixels match exactly as they did in the static cache, so its count is the band's own.
  auto skipped = [&](const ReceiverBand& band) {
    return band.matched == 0 || (!touchesObjects(band) && footprint.unwritten(band));
  };

  const bool fine = frame.accumulation != Accumulation::kU8;
  // S of one (sub-)triangle's runs into the scratch, remembering which rows the sweep must
  // visit (the kernel widens passBegin / passEnd of the rows it matched; rows of the
  // triangle without a match keep an empty run, which the sweep passes over).
  int32_t rowLo = height, rowHi = 0;
  // Rows [y0, y1) of a (sub-)triangle, runs[0] being row y0's.
  auto addRuns = [&](int32_t y0, int32_t y1, const std::pair<int32_t, int32_t>* runs,
                     const SpanPlanes& planes, uint32_t triangleId) {
    const uint32_t matched =
        fine ? kernels->interpolateRunsFine(w.sFine.data(), planeSize, id.data(), stride, y0, y1,
                                            runs, planes, triangleId, w.passBegin.data(),
                                            w.passEnd.data())
             : kernels->interpolateRuns(w.s.data(), id.data(), stride, y0, y1, runs, planes,
                                        triangleId, w.passBegin.data(), w.passEnd.data());
    if (matched == 0) return;
    w.passPixels += matched;
    rowLo = std::min(rowLo, y0);
    rowHi = std::max(rowHi, y1);
  };
  // The mask sweep over those rows (spec §6 step 4), then the scratch is clean again.
  auto sweep = [&](float bias) {
    if (rowLo >= rowHi) return;
    lookup.bias = bias;
    if (fine) {
      kernels->accumulateRowsFine(depth.data(), w.sFine.data(), w.acc.data(), planeSize, stride,
                                  rowLo, rowHi, &w.passBegin[rowLo], &w.passEnd[rowLo], lookup);
    } else {
      kernels->accumulateRows(depth.data(), w.s.data(), w.acc.data(), planeSize, stride, rowLo,
                              rowHi, &w.passBegin[rowLo], &w.passEnd[rowLo], lookup);
    }
    for (int32_t y = rowLo; y < rowHi; ++y) {
      w.touchedBegin[y] = std::min(w.touchedBegin[y], w.passBegin[y]);
      w.touchedEnd[y] = std::max(w.touchedEnd[y], w.passEnd[y]);
      w.passBegin[y] = width;
      w.passEnd[y] = 0;
    }
    rowLo = height;
    rowHi = 0;
  };
  auto planesOf = [](const SetupTriangle& st, core::Rgb16 s0, core::Rgb16 s1, core::Rgb16 s2) {
    return SpanPlanes{
        st.depth,
        {attributePlaneFine(st, {s0.r, s1.r, s2.r}), attributePlaneFine(st, {s0.g, s1.g, s2.g}),
         attributePlaneFine(st, {s0.b, s1.b, s2.b})},
        st.minX,
        st.minY};
  };

  // The room's receivers: runs cached with the static depth, drawn by bands unless skipped
  // (first as a whole sub-triangle, then band by band).
  for (size_t k = 0; k < pass.receiverTriangles.size(); ++k) {
    const uint32_t t = pass.receiverTriangles[k];
    const core::Rgb16* s = &pass.receiverS[3 * k];
    for (uint32_t sub = firstSubOfTriangle[t]; sub < firstSubOfTriangle[t + 1]; ++sub) {
      const SetupTriangle& st = staticSubs[sub];
      if (skipped(subBands[sub])) {
        w.passPixels += subBands[sub].matched;
        continue;
      }
      const std::pair<int32_t, int32_t>* runs = &spans[spanStart[sub]];
      SpanPlanes planes;
      bool planned = false;
      // Consecutive drawn bands go to the kernel in one call: rows [from, to).
      int32_t from = st.minY, to = st.minY;
      auto flush = [&] {
        if (from >= to) return;
        if (!planned) planes = planesOf(st, s[0], s[1], s[2]);
        planned = true;
        addRuns(from, to, runs + (from - st.minY), planes, t);
      };
      for (uint32_t b = bandStart[sub]; b < bandStart[sub + 1]; ++b) {
        const ReceiverBand& band = bands[b];
        const int32_t y0 = st.minY + static_cast<int32_t>(b - bandStart[sub]) * kReceiverBandRows;
        const int32_t y1 = std::min(st.maxY, y0 + kReceiverBandRows);
        // One band is the whole sub-triangle, which was not skipped.
        if (bandStart[sub + 1] - bandStart[sub] == 1 || !skipped(band)) {
          if (from >= to) from = y0;
          to = y1;
          continue;
        }
        w.passPixels += band.matched;
        flush();
        from = to = y1;
      }
      flush();
    }
  }
  sweep(pass.depthBias);
  lookup.penumbraScale = 0;  // object triangles keep the 2x2 PCF (spec §7)

  // The objects' own receivers (self-shadowing, Gibson 2003 §7.2), with their own bias. Their
  // pixels hold object ids, so they never meet the room's runs: the two sweeps are disjoint.
  for (size_t k = 0; k < pass.objectTriangles.size(); ++k) {
    const uint32_t g = pass.objectTriangles[k];
    // A triangle no pixel shows (the product's far side, or hidden by its near side) holds
    // no id in the id buffer, so interpolateRuns would match none of its runs: leaving it out
    // changes no byte.
    if (!objectVisible[g]) continue;
    const core::Rgb16* s = &pass.objectS[3 * k];
    for (uint32_t sub = objectFirstSub[g]; sub < objectFirstSub[g + 1]; ++sub) {
      const SetupTriangle& st = objectTriangles[sub].t;
      addRuns(st.minY, st.maxY, &objectSpans[objectSpanStart[sub]], planesOf(st, s[0], s[1], s[2]),
              kObjectBase + g);
    }
  }
  sweep(pass.objectDepthBias);
}

// Occlusion at the probes for one pass: each probe's light clip position from world space
// (spec §2, §7 binary test, fixed order), written to its own slots only.
void Renderer::Impl::probePass(const ShadowPass& pass, const Worker& w, size_t index) {
  const size_t passes = probeMasks->size() / probes.size();
  const float half = static_cast<float>(pass.shadowMapSize) * 0.5f;
  const float size = static_cast<float>(pass.shadowMapSize);
  for (size_t p = 0; p < probes.size(); ++p) {
    const ClipVertex c = transformPoint(pass.lightViewProj, probes[p]);
    uint8_t m = 0;
    if (c.w > 0.0f) {
      const float u = (c.x / c.w) * half + half;
      const float v = -(c.y / c.w) * half + half;
      const float d = (c.z / c.w) * 0.5f + 0.5f;
      if (u >= 0.0f && u < size && v >= 0.0f && v < size) {
        const float texel = w.shadowMap.origin()[static_cast<ptrdiff_t>(v) * w.shadowMap.stride() +
                                                 static_cast<ptrdiff_t>(u)];
        const float bias = p >= objectProbesFrom ? pass.objectDepthBias : pass.depthBias;
        m = d > texel + bias ? 255 : 0;
      }
    }
    (*probeMasks)[p * passes + index] = m;
  }
}

// The tile's base colours (background, or objects over it) minus the summed pass amounts,
// clamped once (spec §8), written to the output.
void Renderer::Impl::finishTile(uint32_t tile, const FrameContent& frame, std::span<uint8_t> out) {
  int32_t x0, y0, x1, y1;
  tileRect(tile, x0, y0, x1, y1);
  auto rowTouched = [&](int32_t y) {
    for (const Worker& w : workers) {
      if (w.touchedBegin[y] < x1 && w.touchedEnd[y] > x0) return true;
    }
    return false;
  };
  bool touched = false;
  for (int32_t y = y0; y < y1 && !touched; ++y) touched = rowTouched(y);
  const size_t rowBytes = 4 * size_t(x1 - x0);
  if (!touched && !tileHasObject[tile]) {
    for (int32_t y = y0; y < y1; ++y) {
      const size_t offset = 4 * (size_t(width) * size_t(y) + size_t(x0));
      std::memcpy(&out[offset], &frame.background[offset], rowBytes);
    }
    return;
  }
  // Without objects the base is the background, and the sums are subtracted in place in the
  // output (one copy instead of two through rgba) when the tile's rows end on a 16-pixel
  // boundary: the kernel rewrites whole vectors, which must not reach the next output row.
  const bool inOutput = !tileHasObject[tile] && x1 % 16 == 0;
  const auto subtract = frame.accumulation == Accumulation::kFixed8_8
                            ? kernels->subtractAccumulatedFixed8_8
                            : kernels->subtractAccumulated;
  const bool linear = frame.accumulation == Accumulation::kLinear;
  std::array<uint16_t*, 256> acc;
  for (int32_t y = y0; y < y1; ++y) {
    const size_t row = stride * size_t(y);
    const size_t outRow = 4 * size_t(width) * size_t(y);
    uint8_t* base = inOutput ? &out[outRow] : &rgba[4 * row];
    if (!tileHasObject[tile]) {
      std::memcpy(base + 4 * x0, &frame.background[outRow + 4 * size_t(x0)], rowBytes);
    }
    // A worker's sums are zero outside the runs its passes swept, so only the workers whose
    // runs reach this row of the tile are summed, and only over the union of those runs:
    // the same totals, a fraction of the 16-bit planes read and cleared.
    int count = 0;
    int32_t xa = x1, xb = x0;
    for (Worker& w : workers) {
      if (w.touchedBegin[y] >= x1 || w.touchedEnd[y] <= x0) continue;
      acc[size_t(count++)] = w.acc.data() + row;
      xa = std::min(xa, std::max(x0, w.touchedBegin[y]));
      xb = std::max(xb, std::min(x1, w.touchedEnd[y]));
    }
    if (count > 0 && linear) {
      kernels->shadeAccumulatedLinear(base, base, acc.data(), count, planeSize, xa, xb,
                                      shadeTable.data());
    } else if (count > 0) {
      subtract(base, base, acc.data(), count, planeSize, xa, xb);
    }
    if (!inOutput) std::memcpy(&out[outRow + 4 * size_t(x0)], base + 4 * x0, rowBytes);
  }
}

Renderer::Renderer(const StaticView& view, const RenderOptions& options)
    : impl_(std::make_unique<Impl>(view, options)) {}

Renderer::~Renderer() = default;

const FrameStats& Renderer::lastStats() const {
  return impl_->stats;
}
const StaticView& Renderer::view() const {
  return impl_->view;
}
core::JobPool& Renderer::pool() {
  return impl_->pool;
}

void Renderer::render(const FrameContent& frame, std::span<uint8_t> rgbaOut,
                      std::span<const core::Vec3> probes, std::vector<uint8_t>& masks,
                      size_t objectProbesFrom) {
  masks.assign(probes.size() * frame.passes.size(), 0);
  impl_->probes = probes;
  impl_->objectProbesFrom = objectProbesFrom;
  impl_->probeMasks = &masks;
  try {
    render(frame, rgbaOut);
  } catch (...) {
    impl_->probes = {};
    throw;
  }
  impl_->probes = {};
  impl_->probeMasks = nullptr;
}

void Renderer::render(const FrameContent& frame, std::span<uint8_t> rgbaOut) {
  Impl& r = *impl_;
  const auto start = Clock::now();
  if (rgbaOut.size() != size_t{r.view.width} * r.view.height * 4) {
    throw std::invalid_argument("render: output buffer has the wrong size");
  }
  validateFrame(frame, r.view.width, r.view.height, r.view.staticMesh.triangleCount(), "frame");

  r.stats = FrameStats{};
  const bool fine = frame.accumulation != Accumulation::kU8;
  if (frame.accumulation == Accumulation::kLinear &&
      (r.shadeTable.size() != frame.shadeTable.size() + 3 ||
       !std::equal(frame.shadeTable.begin(), frame.shadeTable.end(), r.shadeTable.begin()))) {
    // The kernels fetch 4 bytes per entry: 3 bytes of padding after the last.
    r.shadeTable.assign(frame.shadeTable.size() + 3, 0);
    std::copy(frame.shadeTable.begin(), frame.shadeTable.end(), r.shadeTable.begin());
  }
  for (Worker& w : r.workers) {
    w.mapPixels = w.passPixels = w.objectPixels = w.mapTriangleCount = w.mapTexels = 0;
    if (fine && w.sFine.empty()) w.sFine.assign(r.planeSize * 3, 0);
    if (!fine && w.s.empty()) w.s.assign(r.planeSize, 0);
  }
  const size_t tiles = size_t(r.tilesX) * size_t(r.tilesY);
  r.prepareObjects(frame);
  // Tiles are short jobs: each thread claims ~1/16 of its share at a time (JobPool).
  const size_t tileGrain = std::max<size_t>(1, tiles / (16 * r.workers.size()));
  // Only the tiles that hold objects now or did last frame have work, unevenly (one tile of
  // the showroom's chair holds 197 of its 734 binned triangles): they are claimed one at a
  // time, the most triangles first, so the threads finish together.
  r.objectTiles.clear();
  for (uint32_t tile = 0; tile < tiles; ++tile) {
    if (r.tileHasObject[tile] || r.tileHadObject[tile]) r.objectTiles.push_back(tile);
  }
  std::stable_sort(r.objectTiles.begin(), r.objectTiles.end(), [&](uint32_t a, uint32_t b) {
    return r.objectsOf(a).size() > r.objectsOf(b).size();
  });
  const size_t objectCount = r.objectFirstSub.size() - 1;
  r.objectColumns.assign(size_t(r.tilesY), {r.width, 0});
  for (uint32_t tile = 0; tile < tiles; ++tile) {
    if (!r.tileHasObject[tile]) continue;
    int32_t x0, y0, x1, y1;
    r.tileRect(tile, x0, y0, x1, y1);
    auto& [first, second] = r.objectColumns[size_t(y0 / r.options.tileSize)];
    first = std::min(first, x0);
    second = std::max(second, x1);
  }
  for (Worker& w : r.workers) w.objectSeen.assign(objectCount, 0);
  r.pool.parallelFor(r.objectTiles.size(), [&](size_t k, int worker) {
    r.compositeObjects(r.objectTiles[k], frame, r.workers[size_t(worker)]);
  });
  r.objectVisible.assign(objectCount, 0);
  for (const Worker& w : r.workers) {
    for (size_t g = 0; g < objectCount; ++g) r.objectVisible[g] |= w.objectSeen[g];
  }
  r.stats.msObjects = msSince(start);
  const auto passesStart = Clock::now();
  // Longest passes first (by their receivers' covered pixels), so that the workers finish
  // together instead of one running a long pass alone at the end. The order cannot change
  // a byte: each pass adds into its thread's sums, and sums commute (spec §8).
  r.passOrder.resize(frame.passes.size());
  r.passCost.resize(frame.passes.size());
  for (size_t i = 0; i < frame.passes.size(); ++i) {
    r.passOrder[i] = static_cast<uint32_t>(i);
    uint64_t cost = 0;
    for (uint32_t t : frame.passes[i].receiverTriangles) cost += r.triangleCoverage[t];
    r.passCost[i] = cost + 64 * frame.passes[i].objectTriangles.size();
  }
  std::stable_sort(r.passOrder.begin(), r.passOrder.end(),
                   [&](uint32_t a, uint32_t b) { return r.passCost[a] > r.passCost[b]; });
  r.pool.parallelFor(frame.passes.size(), [&](size_t i, int worker) {
    r.runPass(frame, r.passOrder[i], r.workers[size_t(worker)]);
  });
  r.stats.msPasses = msSince(passesStart);
  const auto finishStart = Clock::now();
  r.pool.parallelFor(
      tiles, [&](size_t tile, int) { r.finishTile(static_cast<uint32_t>(tile), frame, rgbaOut); },
      tileGrain);
  r.stats.msFinish = msSince(finishStart);
  for (Worker& w : r.workers) {
    std::fill(w.touchedBegin.begin(), w.touchedBegin.end(), r.width);
    std::fill(w.touchedEnd.begin(), w.touchedEnd.end(), 0);
    r.stats.shadowMapPixels += w.mapPixels;
    r.stats.shadowMapTriangles += w.mapTriangleCount;
    r.stats.shadowMapTexels += w.mapTexels;
    r.stats.passPixels += w.passPixels;
    r.stats.objectPixels += w.objectPixels;
  }
  r.tileHadObject = r.tileHasObject;
  r.stats.msTotal = msSince(start);
}

std::vector<uint8_t> renderTrace(const FrameTrace& trace, const RenderOptions& options) {
  Renderer renderer(trace.view, options);
  std::vector<uint8_t> out(size_t{trace.view.width} * trace.view.height * 4);
  renderer.render(trace.frame, out);
  return out;
}

}  // namespace penumbra::raster
