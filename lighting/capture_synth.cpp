#include "lighting/capture_synth.h"
#include "core/random.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "lighting/embree_scene.h"
#include "lighting/exr_io.h"
#include "lighting/light_probe.h"
#include "lighting/patch_radiosity.h"
#include "lighting/precompute.h"
#include "scene/image_io.h"
#include "scene/scene_file.h"
#include "shadow/intensity_transfer.h"

namespace penumbra::lighting {
namespace {

using glm::dvec2;
using glm::dvec3;
using nlohmann::json;

double roundTo(double v, double step) {
  return step > 0 ? std::round(v / step) * step : v;
}

json point(const dvec2& p, double step) {
  return json::array({roundTo(p.x, step), roundTo(p.y, step)});
}

// Nine photos of a 9 x 6 (inner corners) chessboard with 10 cm squares and a one-square
// white border, held 1.4-1.5 m in front (squares ~30 px: cornerSubPix's
// 23 x 23 window must not reach the next corner) of the camera at different tilts, rendered through
// the true camera with 4 x 4 supersampling. Returns the manifest's chessboard object.
json writeChessboards(const std::filesystem::path& dir, const scene::Intrinsics& k) {
  constexpr int kCols = 9, kRows = 6;
  constexpr double kSquare = 0.1;
  const double bw = (kCols + 3) * kSquare, bh = (kRows + 3) * kSquare;  // with the border
  struct BoardPose {
    double rx, ry, rz;
    dvec3 centre;
  };
  // Nine poses spread over the view (the corners of the image constrain the distortion
  // and the principal point), each tilted 20-35 degrees a different way.
  const BoardPose poses[] = {{0, 0, 0, {0, 0, 1.4}},
                             {25, -30, 5, {-0.25, -0.15, 1.4}},
                             {-25, 30, -5, {0.25, -0.15, 1.4}},
                             {25, 30, 10, {-0.25, 0.15, 1.4}},
                             {-25, -30, -10, {0.25, 0.15, 1.4}},
                             {35, 0, 0, {0, -0.15, 1.5}},
                             {-35, 0, 0, {0, 0.15, 1.5}},
                             {0, 35, 0, {-0.3, 0, 1.5}},
                             {0, -35, 0, {0.3, 0, 1.5}}};
  json images = json::array();
  for (size_t n = 0; n < std::size(poses); ++n) {
    const BoardPose& bp = poses[n];
    const double d2r = std::numbers::pi / 180;
    const double a = bp.rx * d2r, b = bp.ry * d2r, g = bp.rz * d2r;
    const glm::dmat3 rx(1, 0, 0, 0, std::cos(a), std::sin(a), 0, -std::sin(a), std::cos(a));
    const glm::dmat3 ry(std::cos(b), 0, -std::sin(b), 0, 1, 0, std::sin(b), 0, std::cos(b));
    const glm::dmat3 rz(std::cos(g), std::sin(g), 0, -std::sin(g), std::cos(g), 0, 0, 0, 1);
    const glm::dmat3 r = rx * ry * rz;  // board -> camera
    const dvec3 normal = r * dvec3(0, 0, 1);
    std::vector<uint8_t> rgba(size_t(k.width) * size_t(k.height) * 4, 255);
    for (int v = 0; v < k.height; ++v) {
      for (int u = 0; u < k.width; ++u) {
        double sum = 0;
        for (int sy = 0; sy < 4; ++sy) {
          for (int sx = 0; sx < 4; ++sx) {
            const dvec3 d((u + (sx + 0.5) / 4 - 0.5 - k.cx) / k.fx,
                          (v + (sy + 0.5) / 4 - 0.5 - k.cy) / k.fy, 1.0);
            const double t = glm::dot(bp.centre, normal) / glm::dot(d, normal);
            const dvec3 local = glm::transpose(r) * (t * d - bp.centre);
            const double bx = local.x + 0.5 * bw, by = local.y + 0.5 * bh;
            double value = 110;  // the wall behind the board
            if (bx >= 0 && by >= 0 && bx < bw && by < bh) {
              const int i = int(std::floor(bx / kSquare)) - 1,
                        j = int(std::floor(by / kSquare)) - 1;
              const bool square = i >= 0 && j >= 0 && i <= kCols && j <= kRows;
              value = square && (i + j) % 2 == 0 ? 25 : 230;
            }
            sum += value;
          }
        }
        const uint8_t c = uint8_t(std::lround(sum / 16));
        uint8_t* px = &rgba[(size_t(v) * size_t(k.width) + size_t(u)) * 4];
        px[0] = px[1] = px[2] = c;
      }
    }
    const std::string name = "chess-" + std::to_string(n) + ".png";
    scene::writePng(dir / name, uint32_t(k.width), uint32_t(k.height), rgba);
    images.push_back(name);
  }
  return {{"images", images}, {"cols", kCols}, {"rows", kRows}, {"square", kSquare}};
}

}  // namespace

SyntheticCapture writeSyntheticCapture(const std::filesystem::path& scenePath,
                                       const std::filesystem::path& dir,
                                       const SyntheticCaptureOptions& o) {
  std::filesystem::create_directories(dir);
  scene::SceneDescription sc = scene::loadSceneFile(scenePath);
  // The truth is the mesh a capture rebuilds, and a capture cuts no shadow boundaries
  // (lighting/capture.cpp: its lights come from the probe, after the mesh).
  sc.room.shadowBoundaryPatchSize = 0;
  SyntheticCapture out;

  // The true camera: the scene file's view, principal point at the centre, square pixels.
  const int w = int(sc.width), h = int(sc.height);
  scene::Intrinsics& k = out.intrinsics;
  k.width = w;
  k.height = h;
  k.fx = k.fy = 0.5 * h / std::tan(0.5 * sc.camera.fovYDegrees * std::numbers::pi / 180);
  k.cx = 0.5 * (w - 1) + o.principalOffsetPx.x;
  k.cy = 0.5 * (h - 1) + o.principalOffsetPx.y;
  const dvec3 forward = glm::normalize(sc.camera.target - sc.camera.eye);
  const dvec3 right = glm::normalize(glm::cross(forward, sc.camera.up));
  const dvec3 down = glm::cross(forward, right);
  out.pose.rotation = glm::transpose(glm::dmat3(right, down, forward));  // rows
  out.pose.translation = -(out.pose.rotation * sc.camera.eye);

  // The truth: the scene file's room lit to convergence.
  PrecomputeOptions po;
  out.mesh = precomputePatchMesh(sc, po);
  const EmbreeScene rays(out.mesh);
  out.radiance = solvePatchRadiance(out.mesh, rays, o.bounces);

  // Photographs: each pixel shows the patch its ray hits (flat per patch), through the
  // known response.
  std::vector<dvec3> pixelRadiance(size_t(w) * size_t(h), dvec3(0.0));
  const dvec3 eye = out.pose.centre();
  const glm::dmat3 camToWorld = glm::transpose(out.pose.rotation);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const dvec3 d = camToWorld * dvec3((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      if (const std::optional<Hit> hit = rays.intersect(eye, d)) {
        pixelRadiance[size_t(v) * size_t(w) + size_t(u)] =
            out.radiance[out.mesh.trianglePatch[hit->triangle]];
      }
    }
  }
  json exposures = json::array();
  for (size_t e = 0; e < o.seconds.size(); ++e) {
    std::vector<uint8_t> rgba(pixelRadiance.size() * 4, 255);
    for (size_t i = 0; i < pixelRadiance.size(); ++i) {
      for (int c = 0; c < 3; ++c) {
        // Sensor noise of +-0.5 code (uniform, seeded by exposure, pixel and channel): it
        // dithers the 8-bit quantisation as a real sensor does, so flat patches still spread
        // over neighbouring codes and the response solve sees every code.
        const uint64_t key = (uint64_t(e) << 40) ^ (uint64_t(i) << 2) ^ uint64_t(c);
        const double noise = double(core::splitmix64(key) >> 11) * 0x1.0p-53 - 0.5;
        const double x = std::min(1.0, o.gains[c] * pixelRadiance[i][c] * o.seconds[e]);
        const double code =
            std::clamp(255 * std::pow(x, 1 / o.gamma) + o.noiseCodes * noise, 0.0, 255.0);
        rgba[4 * i + size_t(c)] = uint8_t(std::lround(code));
      }
    }
    const std::string name = "bracket-" + std::to_string(e) + ".png";
    scene::writePng(dir / name, uint32_t(w), uint32_t(h), rgba);
    exposures.push_back({{"image", name}, {"seconds", o.seconds[e]}});
  }
  // Recovered g is pinned at g(128) = 0: code 128 at dt = 1 means merged radiance 1, i.e.
  // gain_c L = (128 / 255)^gamma. So merged = L gain_c / (128 / 255)^gamma.
  for (int c = 0; c < 3; ++c) out.probeScale[c] = o.gains[c] / std::pow(128.0 / 255.0, o.gamma);

  // The probe: lat-long, ray-cast from a point in the room, in the scene's radiance units.
  LightProbe probe;
  probe.mapping = ProbeMapping::LatLong;
  probe.position = o.probePosition;
  const double a = o.probeYawDegrees * std::numbers::pi / 180;
  probe.rotation = glm::dmat3(std::cos(a), 0, -std::sin(a), 0, 1, 0, std::sin(a), 0, std::cos(a));
  probe.image = core::ImageF(uint32_t(o.probeWidth), uint32_t(o.probeWidth / 2));
  renderProbe(probe, out.mesh, rays, out.radiance);
  writeExr(dir / "probe.exr", probe.image);

  // Vanishing marks (tutorial §3): room lines along x and z, clipped to the view. The
  // origin is the desk's front-left floor corner, so the manifest names its room position.
  auto project = [&](const dvec3& p) { return scene::projectPoint(k, out.pose, p); };
  auto inView = [&](const dvec3& p) {
    const dvec2 q = project(p);
    return out.pose.toCamera(p).z > 0 && q.x >= 0 && q.y >= 0 && q.x <= w - 1 && q.y <= h - 1;
  };
  auto line = [&](const dvec3& a0, const dvec3& a1) {
    int first = -1, last = -1;
    for (int i = 0; i <= 200; ++i) {
      if (!inView(a0 + (a1 - a0) * (i / 200.0))) continue;
      if (first < 0) first = i;
      last = i;
    }
    if (first < 0 || last - first < 20) {
      throw std::runtime_error("synthetic capture: a marked room line is out of view");
    }
    return json::array({point(project(a0 + (a1 - a0) * (first / 200.0)), o.markRoundingPx),
                        point(project(a0 + (a1 - a0) * (last / 200.0)), o.markRoundingPx)});
  };
  const dvec3 origin(4.4, 0.0, 3.4);  // the desk of data/showroom/showroom.json
  json marks = {{"comment", "synthetic: room lines projected through the true camera"},
                {"image", {{"width", w}, {"height", h}}},
                {"vanishing_lines",
                 {{"x", json::array({line(origin, origin + dvec3(1.4, 0, 0)),
                                     line(dvec3(0, 0, 5), dvec3(6, 0, 5))})},
                  {"z", json::array({line(dvec3(6, 0, 0), dvec3(6, 0, 5)),
                                     line(dvec3(6, 3, 0), dvec3(6, 3, 5))})}}},
                {"origin", point(project(origin), o.markRoundingPx)},
                {"axis_points",
                 {{"x",
                   {{"image", point(project(origin + dvec3(1.4, 0, 0)), o.markRoundingPx)},
                    {"distance", 1.4}}},
                  {"y",
                   {{"image", point(project(origin + dvec3(0, 0.75, 0)), o.markRoundingPx)},
                    {"distance", 0.75}}},
                  {"z",
                   {{"image", point(project(origin + dvec3(0, 0, 0.8)), o.markRoundingPx)},
                    {"distance", 0.8}}}}}};
  std::ofstream(dir / "marks.json") << marks.dump(2) << "\n";

  json calibration = {{"vanishing", "marks.json"},
                      {"origin_world", {origin.x, origin.y, origin.z}}};
  if (o.chessboard) {
    calibration = {{"chessboard", writeChessboards(dir, k)}, {"corners", "corners.json"}};
    // Room corners (and the desk's) the camera sees, for the pose (solvePnP).
    json corners = json::array();
    const dvec3 points[] = {{6, 0, 5},        {0, 0, 5},        {6, 3, 5},        {0, 3, 5},
                            {6, 0, 0},        {6, 3, 0},        {4.4, 0, 3.4},    {5.8, 0, 3.4},
                            {4.4, 0.75, 3.4}, {5.8, 0.75, 3.4}, {4.4, 0.75, 4.2}, {4.4, 0, 4.2}};
    for (const dvec3& q : points) {
      if (!inView(q)) continue;
      corners.push_back({{"name", "corner " + std::to_string(corners.size())},
                         {"world", {q.x, q.y, q.z}},
                         {"image", point(project(q), o.markRoundingPx)}});
    }
    std::ofstream(dir / "corners.json") << json{{"corners", corners}}.dump(2) << "\n";
  }
  // Relative to the manifest's folder, which loadCaptureManifest resolves it against, so the
  // capture can be moved or copied together with its scene. std::filesystem::relative
  // resolves symbolic links first: a lexical "../" through a linked folder would name
  // another place than the one the reader reaches.
  const std::filesystem::path sceneFromManifest = std::filesystem::relative(scenePath, dir);
  const json manifest = {{"format", "penumbra-capture"},
                         {"version", 1},
                         {"scene", sceneFromManifest.generic_string()},
                         {"calibration", calibration},
                         {"exposures", exposures},
                         {"live_exposure", {{"index", o.liveIndex}}},
                         {"probe",
                          {{"image", "probe.exr"},
                           {"mapping", "latlong"},
                           {"position", {o.probePosition.x, o.probePosition.y, o.probePosition.z}},
                           {"yaw_deg", o.probeYawDegrees}}}};
  out.manifest = dir / "capture.json";
  std::ofstream f(out.manifest);
  f << manifest.dump(2) << "\n";
  if (!f) throw std::runtime_error(out.manifest.string() + ": cannot write");
  return out;
}

}  // namespace penumbra::lighting
