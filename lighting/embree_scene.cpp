#include "lighting/embree_scene.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace penumbra::lighting {
namespace {

[[noreturn]] void throwEmbreeError(RTCDevice device, const char* what) {
  const RTCError code = device ? rtcGetDeviceError(device) : RTC_ERROR_UNKNOWN;
  throw std::runtime_error(std::string("EmbreeScene: ") + what + " (Embree error " +
                           std::to_string(static_cast<int>(code)) + ")");
}

float toFloat(double v) {
  return static_cast<float>(v);
}

}  // namespace

EmbreeScene::EmbreeScene(const scene::PatchMesh& mesh, const EmbreeSceneOptions& options)
    : triangleCount_(mesh.triangleCount()), options_(options) {
  for (uint32_t index : mesh.indices) {
    if (index >= mesh.positions.size()) {
      throw std::invalid_argument("EmbreeScene: triangle index out of range");
    }
  }
  const std::string config = "threads=" + std::to_string(options.buildThreads);
  device_ = rtcNewDevice(config.c_str());
  if (!device_) throwEmbreeError(nullptr, "cannot create device");
  try {
    scene_ = rtcNewScene(device_);
    if (!scene_) throwEmbreeError(device_, "cannot create scene");
    rtcSetSceneFlags(scene_, options.robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE);
    rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_HIGH);
    if (triangleCount_ > 0) {
      RTCGeometry geometry = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
      if (!geometry) throwEmbreeError(device_, "cannot create geometry");
      // Embree may read 16 bytes at the last vertex (its SSE loads): rtcSetNewGeometryBuffer
      // allocates with that padding.
      auto* vertices = static_cast<float*>(
          rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                  3 * sizeof(float), mesh.positions.size()));
      auto* indices = static_cast<unsigned*>(
          rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                  3 * sizeof(unsigned), triangleCount_));
      if (!vertices || !indices) {
        rtcReleaseGeometry(geometry);
        throwEmbreeError(device_, "cannot allocate buffers");
      }
      for (size_t v = 0; v < mesh.positions.size(); ++v) {
        vertices[3 * v + 0] = toFloat(mesh.positions[v].x);
        vertices[3 * v + 1] = toFloat(mesh.positions[v].y);
        vertices[3 * v + 2] = toFloat(mesh.positions[v].z);
      }
      for (size_t i = 0; i < mesh.indices.size(); ++i) indices[i] = mesh.indices[i];
      rtcCommitGeometry(geometry);
      // Geometry id 0: primID is then the PatchMesh triangle index.
      rtcAttachGeometryByID(scene_, geometry, 0);
      rtcReleaseGeometry(geometry);
    }
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) {
      throwEmbreeError(device_, "scene build failed");
    }
  } catch (...) {
    release();
    throw;
  }
}

EmbreeScene::~EmbreeScene() {
  release();
}

EmbreeScene::EmbreeScene(EmbreeScene&& other) noexcept
    : device_(std::exchange(other.device_, nullptr)),
      scene_(std::exchange(other.scene_, nullptr)),
      triangleCount_(std::exchange(other.triangleCount_, 0)),
      options_(other.options_) {}

EmbreeScene& EmbreeScene::operator=(EmbreeScene&& other) noexcept {
  if (this != &other) {
    release();
    device_ = std::exchange(other.device_, nullptr);
    scene_ = std::exchange(other.scene_, nullptr);
    triangleCount_ = std::exchange(other.triangleCount_, 0);
    options_ = other.options_;
  }
  return *this;
}

void EmbreeScene::release() noexcept {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
  scene_ = nullptr;
  device_ = nullptr;
}

bool EmbreeScene::occluded(const glm::dvec3& origin, const glm::dvec3& target) const {
  if (!scene_ || triangleCount_ == 0) return false;
  const glm::dvec3 d = target - origin;
  const double length = glm::length(d);
  const double eps = options_.segmentEpsilon;
  if (!(length > 2 * eps)) return false;
  // Unit direction, so tnear / tfar are distances and the epsilon is in metres.
  const glm::dvec3 dir = d / length;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray{};
  ray.org_x = toFloat(origin.x);
  ray.org_y = toFloat(origin.y);
  ray.org_z = toFloat(origin.z);
  ray.dir_x = toFloat(dir.x);
  ray.dir_y = toFloat(dir.y);
  ray.dir_z = toFloat(dir.z);
  ray.tnear = toFloat(eps);
  ray.tfar = toFloat(length - eps);
  ray.mask = 0xFFFFFFFFu;
  ray.flags = 0;
  rtcOccluded1(scene_, &context, &ray);
  // Embree marks an occluded ray by setting tfar to -inf.
  return ray.tfar < 0;
}

void EmbreeScene::occluded(std::span<const Segment> segments, std::span<uint8_t> out) const {
  if (segments.size() != out.size()) {
    throw std::invalid_argument("EmbreeScene::occluded: output length differs from segments");
  }
  for (size_t i = 0; i < segments.size(); ++i) {
    out[i] = occluded(segments[i].origin, segments[i].target) ? 1 : 0;
  }
}

std::optional<Hit> EmbreeScene::intersect(const glm::dvec3& origin, const glm::dvec3& dir,
                                          double tMin, double tMax) const {
  if (!scene_ || triangleCount_ == 0) return std::nullopt;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rh{};
  rh.ray.org_x = toFloat(origin.x);
  rh.ray.org_y = toFloat(origin.y);
  rh.ray.org_z = toFloat(origin.z);
  rh.ray.dir_x = toFloat(dir.x);
  rh.ray.dir_y = toFloat(dir.y);
  rh.ray.dir_z = toFloat(dir.z);
  rh.ray.tnear = toFloat(tMin);
  rh.ray.tfar = std::isinf(tMax) ? std::numeric_limits<float>::infinity() : toFloat(tMax);
  rh.ray.mask = 0xFFFFFFFFu;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(scene_, &context, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  return Hit{rh.hit.primID, static_cast<double>(rh.ray.tfar), static_cast<double>(rh.hit.u),
             static_cast<double>(rh.hit.v)};
}

}  // namespace penumbra::lighting
