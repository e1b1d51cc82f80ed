#include "reference/synth_showroom.h"
#include "core/random.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "lighting/embree_scene.h"
#include "lighting/exr_io.h"
#include "scene/image_io.h"

namespace penumbra::reference {
namespace {

using glm::dvec3;
using nlohmann::json;

json vec(const dvec3& v) {
  return json::array({v.x, v.y, v.z});
}

// World point -> window position (row 0 at the top, pixel centres at +0.5) through a GL
// view-projection; false when the point is behind the camera.
bool project(const glm::dmat4& viewProj, uint32_t width, uint32_t height, const glm::dvec4& p,
             glm::dvec2& out) {
  const glm::dvec4 c = viewProj * p;
  if (!(std::abs(c.w) > 1e-12)) return false;
  out = {(c.x / c.w + 1.0) * 0.5 * width, (1.0 - c.y / c.w) * 0.5 * height};
  return p.w == 0 || c.w > 0;
}

bool inImage(const glm::dvec2& p, uint32_t width, uint32_t height) {
  return p.x >= 0 && p.y >= 0 && p.x <= width && p.y <= height;
}

std::vector<uint8_t> photograph(const std::vector<glm::vec3>& radiance, double time,
                                const CameraResponse& response) {
  std::vector<uint8_t> rgba(radiance.size() * 4);
  for (size_t i = 0; i < radiance.size(); ++i) {
    for (int c = 0; c < 3; ++c) rgba[4 * i + size_t(c)] = response(double(radiance[i][c]) * time);
    rgba[4 * i + 3] = 255;
  }
  return rgba;
}

void writeJson(const std::filesystem::path& path, const json& j) {
  std::ofstream out(path);
  out << j.dump(2) << "\n";
  if (!out) throw scene::ImageError(path.string() + ": cannot write");
}

core::Mesh toRaster(const scene::TriangleMesh& m) {
  core::Mesh out;
  for (const dvec3& p : m.positions) {
    out.positions.push_back(
        {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)});
  }
  out.indices = m.indices;
  return out;
}

// The "real room" and the kiosk camera every stage looks through.
struct SynthView {
  uint32_t width = 0, height = 0;
  scene::PatchMesh room;  // the scene's own patch mesh, in double
  scene::Aabb bounds;     // of the room's vertices
  scene::Camera camera;   // the scene's, at the image's aspect
  glm::dmat4 viewProj{1.0};
};

// The photographs' exposure series (docs/capture.md manifest entries).
struct BracketSeries {
  double middle = 0;  // the photograph's exposure time
  int mid = 0;        // its index in the series
  json times = json::array(), files = json::array(), exposures = json::array();
};

void checkOptions(const SynthOptions& options) {
  if (options.exposures < 5 || options.exposures > 15) {
    throw std::invalid_argument("synth-showroom: exposures must be 5..15");
  }
  if (!(options.stopsBetween > 0) || options.stopsBetween > 8) {
    throw std::invalid_argument("synth-showroom: stops between exposures must be in (0, 8]");
  }
  if (!(options.response.gamma > 0) || !(options.response.midExposure > 0)) {
    throw std::invalid_argument("synth-showroom: the response needs gamma > 0 and E_mid > 0");
  }
  if (options.probeSize < 8 || options.probeSize > raster::kMaxImageSide) {
    throw std::invalid_argument("synth-showroom: probe size must be 8.." +
                                std::to_string(raster::kMaxImageSide));
  }
}

// The scene's room, bounds and camera; the probe inside the room and the product present.
SynthView viewOf(const scene::SceneDescription& scene, const SynthOptions& options,
                 const shadow::ProductPose& pose) {
  SynthView v;
  v.width = options.width ? options.width : scene.width;
  v.height = options.height ? options.height : scene.height;
  v.room = scene::buildPatchMesh(scene.room, scene.patchSize);
  v.bounds = scene::Aabb::emptyBox();
  for (const dvec3& p : v.room.positions) v.bounds.extend(p);
  const dvec3& q = options.probePosition;
  const scene::Aabb& bounds = v.bounds;
  if (!(q.x > bounds.min.x && q.y > bounds.min.y && q.z > bounds.min.z && q.x < bounds.max.x &&
        q.y < bounds.max.y && q.z < bounds.max.z)) {
    throw std::invalid_argument("synth-showroom: the probe position is outside the room");
  }
  if (pose.product >= scene.products.size()) {
    throw std::invalid_argument("synth-showroom: product " + std::to_string(pose.product) +
                                " does not exist (" + std::to_string(scene.products.size()) +
                                " products)");
  }
  v.camera = scene.camera;
  v.camera.aspect = double(v.width) / v.height;
  v.viewProj = v.camera.viewProj();
  return v;
}

// 1. The kiosk camera: empty room and object-present room from the same samples.
ReferenceImage renderKioskView(const scene::SceneDescription& scene, const SynthView& view,
                               const shadow::ProductPose& pose, const SynthOptions& options,
                               const std::filesystem::path& dir,
                               const ReferenceProgress& progress) {
  const uint32_t width = view.width, height = view.height;
  ReferenceScene kiosk;
  kiosk.room = view.room;
  kiosk.viewProj = view.viewProj;
  kiosk.width = width;
  kiosk.height = height;
  ReferenceObject object;
  shadow::placeMesh(toRaster(scene.products[pose.product].mesh), pose, object.mesh);
  object.reflectance = scene.products[pose.product].reflectance;
  kiosk.object = std::move(object);
  ReferenceImage image = renderReference(kiosk, options.render, progress);
  lighting::writeExr(dir / "room.exr", hdrImageOf(width, height, image.noObject));
  lighting::writeExr(dir / "object_present.exr", hdrImageOf(width, height, image.withObject));
  return image;
}

// 2. Bracketed photographs through the documented response.
BracketSeries writePhotographs(const scene::SceneDescription& scene, const SynthView& view,
                               const ReferenceImage& image, const SynthOptions& options,
                               const std::filesystem::path& dir) {
  const uint32_t width = view.width, height = view.height;
  BracketSeries b;
  b.middle = options.middleExposureTime > 0 ? options.middleExposureTime : scene.tone.exposure;
  const double middle = b.middle;
  b.mid = options.exposures / 2;
  for (int i = 0; i < options.exposures; ++i) {
    const double t = middle * std::exp2(options.stopsBetween * (i - b.mid));
    const std::string name = "bracket-" + std::to_string(i) + ".png";
    scene::writePng(dir / name, width, height, photograph(image.noObject, t, options.response));
    b.times.push_back(t);
    b.files.push_back(name);
    b.exposures.push_back({{"image", name}, {"seconds", t}});
  }
  scene::writePng(dir / "photograph.png", width, height,
                  photograph(image.noObject, middle, options.response));
  scene::writePng(dir / "object_present.png", width, height,
                  photograph(image.withObject, middle, options.response));
  json inverse = json::array();
  for (int k = 0; k < 256; ++k) inverse.push_back(options.response.inverse(k));
  writeJson(dir / "camera_response.json",
            {{"format", "penumbra-camera-response"},
             {"version", 1},
             {"model", "code = round(255 * E^gamma / (E^gamma + E_mid^gamma)), E = L * t"},
             {"gamma", options.response.gamma},
             {"e_mid", options.response.midExposure},
             {"noise", "none"},
             {"exposure_times", b.times},
             {"files", b.files},
             {"photograph_time", middle},
             {"inverse_exposure_per_code", inverse}});
  return b;
}

// 3. The mirrored ball: an ideal reflective sphere of vanishing radius at the probe
// position, seen orthographically from direction `toward` (the kiosk camera's side).
// The ball's frame is lighting/light_probe.h's MirrorBall frame turned by yaw about +y
// (docs/capture.md probe.yaw_deg: probe -> room = R_y(yaw)): the viewer is at +z of the
// probe frame, so yaw is chosen to put it on the kiosk camera's side of the ball.
// Returns the ball's yaw in degrees.
double writeProbe(const scene::SceneDescription& scene, const scene::PatchMesh& room,
                  const SynthOptions& options, const std::filesystem::path& dir,
                  const ReferenceProgress& progress) {
  const dvec3& q = options.probePosition;
  const double yaw = std::atan2(scene.camera.eye.x - q.x, scene.camera.eye.z - q.z);
  const dvec3 toward(std::sin(yaw), 0.0, std::cos(yaw));  // R_y(yaw) (0, 0, 1)
  const dvec3 up(0, 1, 0);
  const dvec3 right(std::cos(yaw), 0.0, -std::sin(yaw));  // R_y(yaw) (1, 0, 0)
  const double yawDegrees = yaw * 180.0 / std::numbers::pi;
  const uint32_t n = options.probeSize;
  ReferenceScene probe;
  probe.room = room;
  probe.width = probe.height = n;
  probe.cameraRay = [=](double xw, double yw, dvec3& origin, dvec3& direction, double& tMax) {
    const double u = 2.0 * xw / n - 1.0, v = 1.0 - 2.0 * yw / n;
    const double r2 = u * u + v * v;
    if (r2 >= 1.0) return false;
    const dvec3 normal = u * right + v * up + std::sqrt(1.0 - r2) * toward;
    const dvec3 view = -toward;
    direction = view - 2.0 * glm::dot(view, normal) * normal;
    origin = q;
    tMax = 1e3;
    return true;
  };
  ReferenceOptions probeOptions = options.render;
  probeOptions.seed = core::splitmix64(options.render.seed ^ 0x50524F4245ull);  // "PROBE"
  const ReferenceImage probeImage = renderReference(probe, probeOptions, progress);
  lighting::writeExr(dir / "probe.exr", hdrImageOf(n, n, probeImage.noObject));
  writeJson(dir / "probe.json",
            {{"format", "penumbra-light-probe"},
             {"version", 1},
             {"mapping", "mirror_ball"},
             {"yaw_deg", yawDegrees},
             {"file", "probe.exr"},
             {"size", n},
             {"position", vec(q)},
             {"toward_viewer", vec(toward)},
             {"up", vec(up)},
             {"right", vec(right)},
             {"radius", 0.0},
             {"convention",
              "pixel (x, y), row 0 at the top: u = 2 (x + 0.5) / size - 1, v = 1 - 2 (y + 0.5) / "
              "size; inside u^2 + v^2 < 1 the sphere normal is n = u right + v up + sqrt(1 - u^2 "
              "- v^2) toward_viewer and the pixel holds the radiance arriving at `position` from "
              "direction r = d - 2 (d . n) n, d = -toward_viewer; black outside the disc"}});
  return yawDegrees;
}

// The part of the segment a-b the camera sees (201 samples along it), as world and window
// end points; null when less than a nanometre of it is in the image.
json visibleSegment(const SynthView& view, const dvec3& a, const dvec3& b, const char* axis,
                    const char* name) {
  const uint32_t width = view.width, height = view.height;
  const glm::dmat4& vp = view.viewProj;
  json j = {{"axis", axis}, {"name", name}};
  std::optional<dvec3> first, last;
  for (int s = 0; s <= 200; ++s) {
    const dvec3 p = a + (s / 200.0) * (b - a);
    glm::dvec2 w;
    if (project(vp, width, height, glm::dvec4(p, 1.0), w) && inImage(w, width, height)) {
      if (!first) first = p;
      last = p;
    }
  }
  if (!first || glm::length(*last - *first) < 1e-9) return json();
  glm::dvec2 wa, wb;
  project(vp, width, height, glm::dvec4(*first, 1.0), wa);
  project(vp, width, height, glm::dvec4(*last, 1.0), wb);
  j["world"] = json::array({vec(*first), vec(*last)});
  j["image"] = json::array({json::array({wa.x, wa.y}), json::array({wb.x, wb.y})});
  return j;
}

// 4. Calibration marks: known room corners and line pairs along x and z, as the camera
// sees them (projections of exact 3D points; a calibration should recover `camera`).
void writeCalibration(const SynthView& view, const std::filesystem::path& dir) {
  const uint32_t width = view.width, height = view.height;
  const scene::Aabb& bounds = view.bounds;
  const scene::Camera& camera = view.camera;
  const lighting::EmbreeScene rays(view.room);
  const glm::dmat4 vp = view.viewProj;
  json corners = json::array();
  for (size_t k = 0; k < 8; ++k) {
    const dvec3 p = bounds.corner(k);
    glm::dvec2 w(0.0);  // project() leaves it alone for a point at the camera's plane
    const bool front = project(vp, width, height, glm::dvec4(p, 1.0), w);
    // A corner lies on three walls; it is visible when nothing else is in the way.
    const bool visible = front && inImage(w, width, height) && !rays.occluded(camera.eye, p);
    corners.push_back({{"world", vec(p)},
                       {"image", json::array({w.x, w.y})},
                       {"in_front", front},
                       {"in_image", front && inImage(w, width, height)},
                       {"visible", visible}});
  }
  // Lines: floor and ceiling edges of the far walls, each clipped to its visible part.
  const dvec3 lo = bounds.min, hi = bounds.max;
  json lines = json::array();
  for (const json& j : {visibleSegment(view, {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, "x",
                                       "floor edge of wall z = max"),
                        visibleSegment(view, {lo.x, hi.y, hi.z}, {hi.x, hi.y, hi.z}, "x",
                                       "ceiling edge of wall z = max"),
                        visibleSegment(view, {lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, "x",
                                       "floor edge of wall z = min"),
                        visibleSegment(view, {hi.x, lo.y, lo.z}, {hi.x, lo.y, hi.z}, "z",
                                       "floor edge of wall x = max"),
                        visibleSegment(view, {hi.x, hi.y, lo.z}, {hi.x, hi.y, hi.z}, "z",
                                       "ceiling edge of wall x = max"),
                        visibleSegment(view, {lo.x, lo.y, lo.z}, {lo.x, lo.y, hi.z}, "z",
                                       "floor edge of wall x = min")}) {
    if (!j.is_null()) lines.push_back(j);
  }
  json vanishing = json::object();
  for (const auto& [axis, d] : {std::pair{"x", dvec3(1, 0, 0)}, std::pair{"z", dvec3(0, 0, 1)}}) {
    glm::dvec2 w(0.0);  // as above: a direction along the image plane has no image
    project(vp, width, height, glm::dvec4(d, 0.0), w);
    vanishing[axis] = json::array({w.x, w.y});
  }
  const double tanHalf = std::tan(0.5 * camera.fovYDegrees * 3.14159265358979323846 / 180.0);
  writeJson(dir / "calibration.json",
            {{"format", "penumbra-synthetic-calibration"},
             {"version", 1},
             {"image", {{"width", width}, {"height", height}}},
             {"convention",
              "image positions in pixels, x right, y down, (0, 0) the top-left "
              "corner of the top-left pixel (pixel centres at +0.5)"},
             {"corners", corners},
             {"lines", lines},
             {"vanishing_points", vanishing},
             {"camera",
              {{"eye", vec(camera.eye)},
               {"target", vec(camera.target)},
               {"up", vec(camera.up)},
               {"fov_y_deg", camera.fovYDegrees},
               {"focal_px", 0.5 * height / tanHalf},
               {"principal_point", json::array({0.5 * width, 0.5 * height})}}}});
}

// 4b. The same marks in the vanishing-point format `penumbra capture` reads
// (docs/calibration.md "marks file": pixel centres at integer positions, so window
// positions minus 0.5): per axis x and z, the two room edges along it that are longest in
// the view; the origin is the floor point under the image point (0.5 w, 0.8 h), with
// axis points 0.5 m along +x, +y and +z. Exact projections, not rounded to clicks.
// Returns the marks' origin on the floor.
dvec3 writeMarks(const SynthView& view, const std::filesystem::path& dir) {
  const uint32_t width = view.width, height = view.height;
  const glm::dmat4& vp = view.viewProj;
  const dvec3 lo = view.bounds.min, hi = view.bounds.max;
  auto mark = [&](const dvec3& p) {
    glm::dvec2 w;
    const bool ok = project(vp, width, height, glm::dvec4(p, 1.0), w) && inImage(w, width, height);
    return std::pair{ok, json::array({w.x - 0.5, w.y - 0.5})};
  };
  auto longestEdges = [&](int axis) {
    std::vector<std::pair<double, json>> found;
    for (int k = 0; k < 4; ++k) {
      const int other = axis == 0 ? 2 : 0;  // the edge's other horizontal coordinate
      dvec3 a = lo;
      if (k & 1) a[other] = hi[other];
      if (k & 2) a.y = hi.y;
      dvec3 b = a;
      b[axis] = hi[axis];
      const json j = visibleSegment(view, a, b, axis == 0 ? "x" : "z", "");
      if (j.is_null()) continue;
      const json& im = j["image"];
      const double du = im[1][0].get<double>() - im[0][0].get<double>();
      const double dv = im[1][1].get<double>() - im[0][1].get<double>();
      json seg = json::array();
      for (int e = 0; e < 2; ++e) {
        seg.push_back(json::array({im[e][0].get<double>() - 0.5, im[e][1].get<double>() - 0.5}));
      }
      found.emplace_back(std::sqrt(du * du + dv * dv), seg);
    }
    std::stable_sort(found.begin(), found.end(),
                     [](const auto& l, const auto& r) { return l.first > r.first; });
    if (found.size() < 2 || found[1].first < 0.1 * width) {
      throw std::invalid_argument(
          "synth-showroom: fewer than two room edges along an axis are in view (>= 10% of the "
          "width)");
    }
    return json::array({found[0].second, found[1].second});
  };
  const glm::dmat4 inverseVp = glm::inverse(vp);
  auto unproject = [&](double nx, double ny, double nz) {
    const glm::dvec4 p = inverseVp * glm::dvec4(nx, ny, nz, 1.0);
    return dvec3(p) / p.w;
  };
  const dvec3 nearPoint = unproject(0.0, -0.6, -1.0), farPoint = unproject(0.0, -0.6, 1.0);
  if (!(nearPoint.y > 0 && farPoint.y < 0)) {
    throw std::invalid_argument("synth-showroom: the camera sees no floor below the image centre");
  }
  const dvec3 origin =
      nearPoint + (nearPoint.y / (nearPoint.y - farPoint.y)) * (farPoint - nearPoint);
  json marks = {{"comment",
                 "synthetic (penumbra synth-showroom): room edges and points projected through "
                 "the true camera, exact"},
                {"image", {{"width", width}, {"height", height}}},
                {"vanishing_lines", {{"x", longestEdges(0)}, {"z", longestEdges(2)}}}};
  const auto [originOk, originMark] = mark(origin);
  if (!originOk) throw std::invalid_argument("synth-showroom: the marks' origin is out of view");
  marks["origin"] = originMark;
  for (int a = 0; a < 3; ++a) {
    dvec3 p = origin;
    p[a] += 0.5;
    const auto [ok, m] = mark(p);
    if (!ok)
      throw std::invalid_argument("synth-showroom: an axis point of the marks is out of view");
    marks["axis_points"][std::string(1, "xyz"[a])] = {{"image", m}, {"distance", 0.5}};
  }
  writeJson(dir / "marks.json", marks);
  return origin;
}

// 4c. The capture manifest (docs/capture.md, "penumbra-capture" version 1): these
// photographs, marks and probe as a real capture of this room would give them.
void writeCaptureManifest(const scene::SceneDescription& scene, const SynthOptions& options,
                          const BracketSeries& brackets, const dvec3& origin, double yawDegrees,
                          const std::filesystem::path& dir) {
  const dvec3& q = options.probePosition;
  writeJson(dir / "capture.json",
            {{"format", "penumbra-capture"},
             {"version", 1},
             {"scene", std::filesystem::absolute(scene.source).string()},
             {"calibration", {{"vanishing", "marks.json"}, {"origin_world", vec(origin)}}},
             {"exposures", brackets.exposures},
             {"live_exposure", {{"index", brackets.mid}}},
             {"probe",
              {{"image", "probe.exr"},
               {"mapping", "mirror_ball"},
               {"position", vec(q)},
               {"yaw_deg", yawDegrees}}}});
}

// 5. The manifest.
void writeManifest(const scene::SceneDescription& scene, const SynthOptions& options,
                   const SynthView& view, const shadow::ProductPose& pose,
                   const BracketSeries& brackets, const std::filesystem::path& dir) {
  const uint32_t width = view.width, height = view.height;
  const ReferenceOptions& r = options.render;
  writeJson(dir / "synth_showroom.json", {{"format", "penumbra-synthetic-showroom"},
                                          {"version", 1},
                                          {"scene", scene.source.string()},
                                          {"image", {{"width", width}, {"height", height}}},
                                          {"render",
                                           {{"spp", r.samplesPerPixel},
                                            {"light_samples", r.lightSamples},
                                            {"bounces", r.bounces},
                                            {"seed", r.seed}}},
                                          {"product",
                                           {{"index", pose.product},
                                            {"name", scene.products[pose.product].name},
                                            {"x", pose.x},
                                            {"z", pose.z},
                                            {"lift", pose.lift},
                                            {"yaw_deg", pose.yawDegrees}}},
                                          {"files",
                                           {{"room_hdr", "room.exr"},
                                            {"exposures", brackets.files},
                                            {"camera_response", "camera_response.json"},
                                            {"photograph", "photograph.png"},
                                            {"object_present", "object_present.png"},
                                            {"object_present_hdr", "object_present.exr"},
                                            {"probe", "probe.exr"},
                                            {"probe_pose", "probe.json"},
                                            {"calibration", "calibration.json"},
                                            {"marks", "marks.json"},
                                            {"capture_manifest", "capture.json"}}}});
}

}  // namespace

uint8_t CameraResponse::operator()(double exposure) const {
  if (!(exposure > 0)) return 0;
  const double e = std::pow(exposure, gamma), m = std::pow(midExposure, gamma);
  const double code = std::floor(255.0 * e / (e + m) + 0.5);
  return static_cast<uint8_t>(std::clamp(code, 0.0, 255.0));
}

double CameraResponse::inverse(int code) const {
  // Continuous curve v = 255 E^g / (E^g + m^g)  =>  E = m (v / (255 - v))^(1/g).
  auto at = [&](double v) { return midExposure * std::pow(v / (255.0 - v), 1.0 / gamma); };
  if (code <= 0) return 0.5 * at(0.5);
  if (code >= 255) return at(254.5);
  return at(double(code));
}

void writeSynthShowroom(const scene::SceneDescription& scene, const SynthOptions& options,
                        const std::filesystem::path& dir, const ReferenceProgress& progress) {
  checkOptions(options);
  const shadow::ProductPose pose = options.pose.value_or(shadow::ProductPose{
      static_cast<uint32_t>(scene.startPose.product), static_cast<float>(scene.startPose.x),
      static_cast<float>(scene.startPose.z), static_cast<float>(scene.startPose.yawDegrees), 0.0f});
  const SynthView view = viewOf(scene, options, pose);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (!std::filesystem::is_directory(dir)) {
    throw scene::ImageError(dir.string() + ": cannot create the output folder");
  }
  const ReferenceImage image = renderKioskView(scene, view, pose, options, dir, progress);
  const BracketSeries brackets = writePhotographs(scene, view, image, options, dir);
  const double yawDegrees = writeProbe(scene, view.room, options, dir, progress);
  writeCalibration(view, dir);
  const dvec3 origin = writeMarks(view, dir);
  writeCaptureManifest(scene, options, brackets, origin, yawDegrees, dir);
  writeManifest(scene, options, view, pose, brackets, dir);
}

}  // namespace penumbra::reference
