#include "lighting/capture.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

#include "core/colour.h"
#include "core/json_reader.h"
#include "core/regular_file.h"
#include "lighting/camera_response.h"
#include "lighting/embree_scene.h"
#include "lighting/exr_io.h"
#include "lighting/hdr_merge.h"
#include "scene/camera_calibration.h"
#include "scene/photo_io.h"
#include "scene/room_pose.h"
#include "scene/vanishing_points.h"
#include "shadow/intensity_transfer.h"

namespace penumbra::lighting {
namespace {

using core::JsonValue;
namespace fs = std::filesystem;

// --- manifest ------------------------------------------------------------------------

// Photographs and probe images are decoded by OpenCV and OpenEXR, which read whatever they
// are given: a file named by the manifest must be a regular file of at most this size
// (docs/input-limits.md). A 50-megapixel 16-bit RGB TIFF is 300 MB; a float EXR probe of
// 8192 x 4096 is 400 MB.
constexpr uintmax_t kMaxCaptureInputBytes = uintmax_t{512} << 20;

// A file named by the manifest: relative names are relative to the manifest's folder; it
// must be a regular file within kMaxCaptureInputBytes (`manifest: field: path: problem`).
fs::path filePath(const JsonValue& v, const fs::path& manifest) {
  const fs::path p = v.nonEmptyString();
  fs::path resolved = p.is_absolute() ? p : fs::absolute(manifest).parent_path() / p;
  core::requireRegularFile(resolved, kMaxCaptureInputBytes, "a capture input",
                           core::throwAs<CaptureError>,
                           manifest.string() + ": " + v.field() + ": ");
  return resolved;
}

double positive(const JsonValue& v) {
  const double d = v.number();
  if (!(d > 0)) v.fail("must be > 0");
  return d;
}

glm::dvec3 vec3(const JsonValue& v) {
  const std::vector<double> c = v.numbers(3);
  return {c[0], c[1], c[2]};
}

int integer(const JsonValue& v, int lo, int hi) {
  return static_cast<int>(v.integer(lo, hi));
}

// "calibration": vanishing-point marks, or chessboard photographs plus room corners.
void readCalibration(const JsonValue& cal, const fs::path& file, CaptureManifest& m) {
  cal.object({"vanishing", "origin_world", "chessboard", "corners"});
  if (cal.has("vanishing") == cal.has("chessboard")) {
    cal.fail("exactly one of \"vanishing\" and \"chessboard\" is needed");
  }
  if (cal.has("vanishing")) {
    m.vanishingMarks = filePath(cal["vanishing"], file);
    if (cal.has("origin_world")) m.vanishingOriginWorld = vec3(cal["origin_world"]);
  } else {
    if (cal.has("origin_world")) cal["origin_world"].fail("only with \"vanishing\"");
    const JsonValue cb = cal["chessboard"].object({"images", "cols", "rows", "square"});
    const JsonValue images = cb["images"];
    if (!images.json().is_array() || images.json().size() < 3) {
      images.fail("must list at least 3 photos");
    }
    for (const JsonValue& image : images.array()) {
      m.chessboardPhotos.push_back(filePath(image, file));
    }
    m.chessboardCols = integer(cb["cols"], 2, 100);
    m.chessboardRows = integer(cb["rows"], 2, 100);
    if (cb.has("square")) m.chessboardSquare = positive(cb["square"]);
    if (!cal.has("corners")) {
      throw CaptureError(file.string(), "calibration.corners",
                         "required with \"chessboard\" (the pose comes from them)");
    }
  }
  if (cal.has("corners")) m.corners = filePath(cal["corners"], file);
}

// "probe": the light probe's image, mapping, position and orientation in the room.
void readProbe(const JsonValue& pr, const fs::path& file, CaptureManifest& m) {
  pr.object({"image", "mapping", "fisheye_fov_deg", "position", "yaw_deg", "pitch_deg",
             "saturation", "scale"});
  m.probeImage = filePath(pr["image"], file);
  m.probeMapping = pr["mapping"].oneOf<ProbeMapping>({{"latlong", ProbeMapping::LatLong},
                                                      {"mirror_ball", ProbeMapping::MirrorBall},
                                                      {"fisheye", ProbeMapping::Fisheye}});
  if (const auto fov = pr.find("fisheye_fov_deg")) {
    if (m.probeMapping != ProbeMapping::Fisheye) fov->fail("only for fisheye");
    m.probeFisheyeFovDegrees = positive(*fov);
    if (m.probeFisheyeFovDegrees > 360) fov->fail("must be <= 360");
  }
  m.probePosition = vec3(pr["position"]);
  if (pr.has("yaw_deg")) m.probeYawDegrees = pr["yaw_deg"].number();
  if (pr.has("pitch_deg")) m.probePitchDegrees = pr["pitch_deg"].number();
  if (pr.has("saturation")) m.probeSaturation = float(positive(pr["saturation"]));
  if (const auto scale = pr.find("scale")) {
    if (scale->json() != "fit") {
      const glm::dvec3 s = vec3(*scale);
      if (!(s.x > 0 && s.y > 0 && s.z > 0)) scale->fail("must be > 0 (or \"fit\")");
      m.probeScale = s;
    }
  }
}

// Probe frame -> room: Ry(yaw) Rx(pitch) (columns: probe axes in the room).
glm::dmat3 probeRotation(double yawDegrees, double pitchDegrees) {
  const double a = yawDegrees * std::numbers::pi / 180, b = pitchDegrees * std::numbers::pi / 180;
  const glm::dmat3 ry(std::cos(a), 0, -std::sin(a), 0, 1, 0, std::sin(a), 0, std::cos(a));
  const glm::dmat3 rx(1, 0, 0, 0, std::cos(b), std::sin(b), 0, -std::sin(b), std::cos(b));
  return ry * rx;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(std::llround(q * double(v.size() - 1))))];
}

// --- the stages of runCapture --------------------------------------------------------

// The bracket of photographs, all of one size.
std::vector<Exposure> readBracket(const CaptureManifest& m, const std::string& src) {
  std::vector<Exposure> bracket;
  for (const CaptureManifest::Photo& p : m.exposures) {
    core::Image8 photo = scene::readPhotoRgb8(p.file);
    if (!bracket.empty() &&
        (photo.width != bracket[0].image.width || photo.height != bracket[0].image.height)) {
      throw CaptureError(src + ": exposures: " + p.file.string() + " is " +
                         std::to_string(photo.width) + "x" + std::to_string(photo.height) +
                         ", the first photograph " + std::to_string(bracket[0].image.width) + "x" +
                         std::to_string(bracket[0].image.height));
    }
    bracket.push_back({p.file.filename().string(), p.seconds, std::move(photo)});
  }
  return bracket;
}

// Intrinsics and pose (Gibson & Chalmers 2003 §3) into s.intrinsics and s.pose; the scene's
// camera and image size become the calibrated ones.
void calibrateCamera(const CaptureManifest& m, int width, int height, const std::string& src,
                     scene::SceneDescription& scene, CaptureSummary& s) {
  scene::Intrinsics intr;
  scene::Pose pose;
  if (!m.vanishingMarks.empty()) {
    const scene::VanishingCalibration vc =
        scene::calibrateFromVanishingPoints(scene::loadVanishingMarks(m.vanishingMarks));
    intr = vc.intrinsics;
    // The marks' frame has its origin at the marked point: x_cam = R (x_room - o) + t.
    pose.rotation = vc.pose.rotation;
    pose.translation = vc.pose.translation - vc.pose.rotation * m.vanishingOriginWorld;
    s.calibrationMethod = "vanishing points";
    s.reprojectionErrorPx = s.intrinsicsErrorPx = vc.rmsPx;
  } else {
    const scene::ChessboardCalibration cc = scene::calibrateFromChessboards(
        m.chessboardPhotos, {m.chessboardCols, m.chessboardRows}, m.chessboardSquare);
    for (const scene::ChessboardImage& im : cc.images) {
      if (!im.used) s.warnings.push_back("chessboard: " + im.problem);
    }
    intr = cc.intrinsics;
    s.calibrationMethod = "chessboard";
    s.reprojectionErrorPx = s.intrinsicsErrorPx = cc.rmsPx;
  }
  if (!m.corners.empty()) {
    const scene::PoseFit fit =
        scene::fitPose(intr, scene::loadCornerMarks(m.corners), m.corners.string());
    pose = fit.pose;
    s.calibrationMethod += " + room corners";
    s.reprojectionErrorPx = fit.rmsPx;
  }
  if (intr.width != width || intr.height != height) {
    throw CaptureError(src + ": calibration: the calibrated image is " +
                       std::to_string(intr.width) + "x" + std::to_string(intr.height) +
                       ", the photographs " + std::to_string(width) + "x" + std::to_string(height));
  }
  s.intrinsics = intr;
  s.pose = pose;
  scene.camera =
      scene::toCamera(intr, pose, scene.camera.zNear, scene.camera.zFar, &s.principalOffsetPx);
  scene.width = uint32_t(width);
  scene.height = uint32_t(height);
  // toCamera's frustum is symmetric; an off-centre principal point becomes an off-axis
  // frustum instead (scene::Camera::principalNdc), so the renderer puts every room point on
  // the pixel the calibrated camera does. The principal point sits at window position
  // (cx + 0.5, cy + 0.5) (scene/camera_intrinsics.h).
  scene.camera.principalNdc = {(intr.cx + 0.5) / (0.5 * width) - 1.0,
                               1.0 - (intr.cy + 0.5) / (0.5 * height)};
  // Lens distortion is not modelled: how far it moves the image corner tells whether that
  // matters.
  if (intr.hasDistortion()) {
    const glm::dvec3 corner((0 - intr.cx) / intr.fx, (0 - intr.cy) / intr.fy, 1.0);
    const double shift = glm::length(intr.project(corner));
    if (shift > 0.5) {
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "lens distortion moves the image corner by %.1f px and is not modelled: "
                    "the photographs are used as taken, overlays assume a pinhole",
                    shift);
      s.warnings.push_back(buf);
    }
  }
}

// The camera response into s.response (§4) and T() at the live exposure.
shadow::ToneCurve recoverToneCurve(const CaptureManifest& m, const std::vector<Exposure>& bracket,
                                   CaptureSummary& s) {
  s.response = recoverResponse(bracket);
  const CameraResponse& response = s.response;
  for (const std::string& w : response.warnings) s.warnings.push_back("response: " + w);
  // g(128) = 0 per channel leaves each channel in its own units. The bundle stores one T()
  // (the grey curve, g averaged over channels), so each channel is rescaled to the grey
  // curve's units: the factor that best maps g_c onto g_grey over the well-exposed codes.
  std::array<double, 256> grey{};
  for (int z = 0; z < 256; ++z) {
    grey[size_t(z)] = (response.logExposure[0][size_t(z)] + response.logExposure[1][size_t(z)] +
                       response.logExposure[2][size_t(z)]) /
                      3;
  }
  for (int c = 0; c < 3; ++c) {
    double sum = 0;
    for (int z = 32; z <= 223; ++z)
      sum += grey[size_t(z)] - response.logExposure[size_t(c)][size_t(z)];
    s.channelToGrey[c] = std::exp(sum / 192);
  }
  const double live = m.liveIndex ? m.exposures[size_t(*m.liveIndex)].seconds : *m.liveSeconds;
  s.liveSeconds = live;
  // T() at the live exposure: code z records radiance exp(g(z)) / dt (merged units).
  std::vector<shadow::ToneCurve::Sample> samples;
  for (const ToneSample& t : response.greyToneSamples()) {
    samples.push_back({t.radiance / live, t.value});
  }
  return shadow::ToneCurve::fromSamples(samples);
}

struct HdrPhotos {
  MergeResult merged;               // radiance in the grey curve's units
  std::vector<uint8_t> background;  // the kiosk's live view, RGBA8
};

HdrPhotos mergeHdr(const CaptureManifest& m, const std::vector<Exposure>& bracket,
                   const shadow::ToneCurve& tone, int width, int height, CaptureSummary& s) {
  const CameraResponse& response = s.response;
  MergeResult merged = mergeExposures(bracket, response);
  for (size_t i = 0; i < merged.radiance.pixels.size(); ++i) {
    merged.radiance.pixels[i] =
        float(double(merged.radiance.pixels[i]) * s.channelToGrey[int(i % 3)]);
  }
  s.clippedBright = merged.clippedBright;
  s.clippedDark = merged.clippedDark;
  if (merged.minRadiance > 0 && merged.maxRadiance > 0) {
    s.dynamicRangeStops = std::log2(merged.maxRadiance / merged.minRadiance);
  }
  if (merged.clippedBright) {
    s.warnings.push_back(std::to_string(merged.clippedBright) +
                         " pixels clipped bright in every exposure (radiance is a lower bound): "
                         "add a shorter exposure");
  }
  // The kiosk's live view: the photograph itself, or the HDR through T() at that time.
  std::vector<uint8_t> background(size_t(width) * size_t(height) * 4, 255);
  for (size_t i = 0; i < size_t(width) * size_t(height); ++i) {
    for (size_t c = 0; c < 3; ++c) {
      background[4 * i + c] = m.liveIndex ? bracket[size_t(*m.liveIndex)].image.pixels[3 * i + c]
                                          : tone(double(merged.radiance.pixels[3 * i + c]));
    }
  }
  return {std::move(merged), std::move(background)};
}

LightProbe readLightProbe(const CaptureManifest& m, CaptureSummary& s) {
  ExrReadReport exrReport;
  LightProbe probe;
  probe.image = readExr(m.probeImage, &exrReport);
  if (exrReport.clampedNegative) {
    s.warnings.push_back(m.probeImage.filename().string() + ": " +
                         std::to_string(exrReport.clampedNegative) +
                         " negative values (lossy compression) clamped to 0, down to " +
                         std::to_string(exrReport.mostNegative));
  }
  probe.mapping = m.probeMapping;
  probe.fisheyeFovDegrees = m.probeFisheyeFovDegrees;
  probe.position = m.probePosition;
  probe.rotation = probeRotation(m.probeYawDegrees, m.probePitchDegrees);
  return probe;
}

// The probe's radiance on every patch it sees (§4.2).
ProbeProjection projectLightProbe(const LightProbe& probe, const scene::PatchMesh& mesh,
                                  const EmbreeScene& rays, const CaptureManifest& m,
                                  unsigned threads, const std::string& src, CaptureSummary& s) {
  ProbeProjectionOptions po;
  po.saturationLevel = m.probeSaturation;
  po.threads = threads;
  ProbeProjection proj;
  try {
    proj = projectProbe(probe, mesh, rays, po);
  } catch (const std::invalid_argument& e) {
    throw CaptureError(src + ": probe: " + e.what());
  }
  for (const std::string& w : proj.warnings) s.warnings.push_back("probe: " + w);
  s.probeSeenPatches = proj.seenPatches;
  s.probeEmitters = proj.emitters;
  return proj;
}

// The probe was taken with another camera (or exposure) than the kiosk photographs, so
// its radiance is in other units. Reflectance L/G is a ratio and does not care, but the
// emission (and so every transfer and T() of the frame) does. Each seen reflector that
// the calibrated camera also sees gives a ratio photo / probe per channel; the median
// ties the units (robust to the few patches where the room model and the photo disagree).
void scaleProbeToPhotographs(const CaptureManifest& m, const std::vector<Exposure>& bracket,
                             const MergeResult& merged, const scene::PatchMesh& mesh,
                             const EmbreeScene& rays, const std::string& src, ProbeProjection& proj,
                             CaptureSummary& s) {
  const scene::Intrinsics& intr = s.intrinsics;
  const scene::Pose& pose = s.pose;
  const int width = bracket[0].image.width, height = bracket[0].image.height;
  if (m.probeScale) {
    s.probeScale = *m.probeScale;
  } else {
    const glm::dvec3 eye = pose.centre();
    const glm::dmat3 camToWorld = glm::transpose(pose.rotation);
    const Exposure& shortest = *std::min_element(
        bracket.begin(), bracket.end(),
        [](const Exposure& a, const Exposure& b) { return a.seconds < b.seconds; });
    const Exposure& longest = *std::max_element(
        bracket.begin(), bracket.end(),
        [](const Exposure& a, const Exposure& b) { return a.seconds < b.seconds; });
    std::array<std::vector<double>, 3> ratios;
    std::vector<double> lumRatios;
    for (size_t p = 0; p < mesh.patches.size(); ++p) {
      if (!proj.seen[p] || proj.materials[p].emits()) continue;
      const glm::dvec3 pr = proj.radiance[p];
      if (!(pr.x > 0 && pr.y > 0 && pr.z > 0)) continue;
      const glm::dvec3 cam = pose.toCamera(mesh.patches[p].centre);
      if (cam.z <= 0) continue;
      const glm::dvec2 uv = intr.project(cam);
      const int u0 = int(std::lround(uv.x)), v0 = int(std::lround(uv.y));
      if (u0 < 1 || v0 < 1 || u0 >= width - 1 || v0 >= height - 1) continue;
      // A 3 x 3 window, every pixel of which must show this patch (its camera ray hits it)
      // and be measured in some exposure (not clipped throughout).
      glm::dvec3 sum(0.0);
      int n = 0;
      for (int dv = -1; dv <= 1; ++dv) {
        for (int du = -1; du <= 1; ++du) {
          const int u = u0 + du, v = v0 + dv;
          const glm::dvec3 dir =
              camToWorld * glm::dvec3((u - intr.cx) / intr.fx, (v - intr.cy) / intr.fy, 1.0);
          const std::optional<Hit> hit = rays.intersect(eye, dir);
          if (!hit || mesh.trianglePatch[hit->triangle] != p) continue;
          const size_t i = 3 * (size_t(v) * size_t(width) + size_t(u));
          bool clipped = false;
          for (size_t c = 0; c < 3; ++c) {
            clipped =
                clipped || shortest.image.pixels[i + c] == 255 || longest.image.pixels[i + c] == 0;
          }
          if (clipped) continue;
          sum += glm::dvec3(merged.radiance.pixels[i], merged.radiance.pixels[i + 1],
                            merged.radiance.pixels[i + 2]);
          ++n;
        }
      }
      if (n < 9) continue;
      const glm::dvec3 photo = sum / 9.0;
      for (int c = 0; c < 3; ++c) ratios[size_t(c)].push_back(photo[c] / pr[c]);
      lumRatios.push_back(core::luminance(photo) / core::luminance(pr));
    }
    s.scalePatches = lumRatios.size();
    if (lumRatios.size() < 8) {
      throw CaptureError(src + ": probe: only " + std::to_string(lumRatios.size()) +
                         " reflecting patches are seen by both the camera and the probe; cannot "
                         "tie the probe's units to the photographs' (give probe.scale)");
    }
    for (int c = 0; c < 3; ++c) s.probeScale[c] = median(ratios[size_t(c)]);
    const double mid = median(lumRatios);
    s.scaleSpread = (quantile(lumRatios, 0.75) - quantile(lumRatios, 0.25)) / mid;
    if (s.scaleSpread > 0.25) {
      char buf[200];
      std::snprintf(buf, sizeof buf,
                    "probe scale: photo/probe ratios spread %.0f%% (interquartile) over %zu "
                    "patches: the room model, pose or probe position may be off",
                    100 * s.scaleSpread, lumRatios.size());
      s.warnings.push_back(buf);
    }
  }
  for (size_t p = 0; p < proj.radiance.size(); ++p) {
    proj.radiance[p] *= s.probeScale;
    proj.materials[p].emission *= s.probeScale;
  }
}

}  // namespace

CaptureManifest loadCaptureManifest(const fs::path& path) {
  const core::JsonDocument doc(path, core::throwAs<CaptureError>);
  const JsonValue j = doc.root().object(
      {"format", "version", "scene", "calibration", "exposures", "live_exposure", "probe"});
  CaptureManifest m;
  m.source = path;
  if (j["format"].json() != "penumbra-capture") j["format"].fail("must be \"penumbra-capture\"");
  if (integer(j["version"], 1, 1000) != 1) j["version"].fail("must be 1");
  m.scene = filePath(j["scene"], path);
  readCalibration(j["calibration"], path, m);

  const JsonValue ex = j["exposures"];
  if (!ex.json().is_array() || ex.json().size() < 2) ex.fail("must list at least 2 photographs");
  for (const JsonValue& e : ex.array()) {
    e.object({"image", "seconds"});
    m.exposures.push_back({filePath(e["image"], path), positive(e["seconds"])});
  }
  const JsonValue live = j["live_exposure"].object({"index", "seconds"});
  if (live.has("index") == live.has("seconds")) {
    live.fail("exactly one of \"index\" and \"seconds\" is needed");
  }
  if (live.has("index")) {
    m.liveIndex = integer(live["index"], 0, int(m.exposures.size()) - 1);
  } else {
    m.liveSeconds = positive(live["seconds"]);
  }
  readProbe(j["probe"], path, m);
  return m;
}

CaptureResult runCapture(const CaptureManifest& m, PrecomputeOptions options,
                         const CaptureProgress& progress) {
  const std::string src = m.source.string();
  CaptureResult result;
  CaptureSummary& s = result.summary;
  constexpr int kOwnStages = 6;
  const int kStages = kOwnStages + (options.irradianceVolume ? 6 : 5);
  int stage = 0;
  auto start = std::chrono::steady_clock::now();
  auto begin = [&](const std::string& name) {
    start = std::chrono::steady_clock::now();
    if (progress) progress(name, stage, kStages);
    s.timings.push_back({name, 0});
    ++stage;
  };
  auto endStage = [&] {
    s.timings.back().ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  };

  // --- photographs --------------------------------------------------------------------
  begin("photographs");
  scene::SceneDescription scene = scene::loadSceneFile(m.scene);
  // The refinement needs the lights before the room is cut into patches; a capture finds
  // them afterwards, in the probe's projection onto those patches.
  if (scene.room.shadowBoundaryPatchSize > 0) {
    s.warnings.push_back(
        "shadow_boundary_patch_size: not applied: a capture finds its lights in the probe, "
        "after the room is cut into patches");
    scene.room.shadowBoundaryPatchSize = 0;
  }
  const std::vector<Exposure> bracket = readBracket(m, src);
  const int width = bracket[0].image.width, height = bracket[0].image.height;
  endStage();

  // --- calibration (Gibson & Chalmers 2003 §3) -----------------------------------------
  begin("calibration");
  calibrateCamera(m, width, height, src, scene, s);
  endStage();

  // --- response and HDR (§4) ------------------------------------------------------------
  begin("camera response");
  const shadow::ToneCurve tone = recoverToneCurve(m, bracket, s);
  endStage();

  begin("HDR merge");
  HdrPhotos hdr = mergeHdr(m, bracket, tone, width, height, s);
  endStage();

  // --- probe -> patches (§4.2) -------------------------------------------------------------
  begin("light probe");
  const LightProbe probe = readLightProbe(m, s);
  const scene::PatchMesh mesh = precomputePatchMesh(scene, options);
  const EmbreeScene rays(mesh);
  ProbeProjection proj = projectLightProbe(probe, mesh, rays, m, options.threads, src, s);
  endStage();

  // --- probe units -> photograph units ------------------------------------------------------
  begin("probe scale");
  scaleProbeToPhotographs(m, bracket, hdr.merged, mesh, rays, src, proj, s);
  endStage();

  // --- precompute with everything measured ----------------------------------------------------
  options.measuredMaterials = proj.materials;
  options.measuredRadiance = proj.radiance;
  options.tone = tone;
  options.background = std::move(hdr.background);
  const int offset = stage;
  std::vector<StageTiming> inner;
  result.bundle = precomputeBundle(scene, options, inner, [&](const std::string& n, int i, int) {
    if (progress) progress(n, offset + i, kStages);
  });
  s.timings.insert(s.timings.end(), inner.begin(), inner.end());
  s.patches = result.bundle.patches.size();
  s.sources = result.bundle.sets.sources.size();
  s.receivers = result.bundle.sets.receivers.size();
  return result;
}

}  // namespace penumbra::lighting
