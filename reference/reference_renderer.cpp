#include "reference/reference_renderer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <mutex>
#include <numbers>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>

#include "core/colour.h"
#include "core/job_pool.h"
#include "core/random.h"
#include "lighting/embree_scene.h"
#include "lighting/form_factor.h"
#include "lighting/radiance_transfer.h"

namespace penumbra::reference {
namespace {

using glm::dvec3;

struct Emitter {
  std::array<dvec3, 4> polygon;  // counter-clockwise about `normal`
  dvec3 normal, emission;
  double area;
  dvec3 centre;   // of a sphere holding the polygon
  double radius;  // (inflated like the product's, below)
};

// A ball holding `points` (centre: their box's), inflated by 0.1 % and a micrometre so that
// rounding in the tests against it can only keep a ray, never lose one.
template <class Points>
std::pair<dvec3, double> boundingBall(const Points& points) {
  dvec3 lo(INFINITY), hi(-INFINITY);
  for (const auto& p : points) {
    lo = glm::min(lo, dvec3(p));
    hi = glm::max(hi, dvec3(p));
  }
  const dvec3 centre = 0.5 * (lo + hi);
  double r = 0;
  for (const auto& p : points) r = std::max(r, glm::length(dvec3(p) - centre));
  return {centre, 1.001 * r + 1e-6};
}

// A surface point a ray found.
struct SurfaceHit {
  dvec3 x, n;         // n: the shading normal
  dvec3 offset{0.0};  // the geometric normal facing the ray's origin: rays start off it
  dvec3 reflectance{0.0}, emission{0.0};
  double t = 0;  // ray parameter of the hit
};

// The radiance of one path with and without the product.
struct Pair {
  dvec3 absent{0.0}, present{0.0};
};

enum Active : int { kAbsent = 1, kPresent = 2, kBoth = 3 };

// A stream of uniform variates keyed by (seed, pixel, sample).
struct Stream {
  uint64_t key;
  uint64_t counter = 0;
  double next() { return core::unitSample(key, counter++); }
};

dvec3 faceNormal(const std::vector<dvec3>& positions, const std::vector<uint32_t>& indices,
                 uint32_t triangle) {
  const dvec3& a = positions[indices[3 * size_t{triangle}]];
  const dvec3& b = positions[indices[3 * size_t{triangle} + 1]];
  const dvec3& c = positions[indices[3 * size_t{triangle} + 2]];
  const dvec3 n = glm::cross(b - a, c - a);
  const double length = glm::length(n);
  return length > 0 ? n / length : dvec3(0, 1, 0);
}

// `v` normalized; zero stays zero.
dvec3 unit(const dvec3& v) {
  const double length = glm::length(v);
  return length > 0 ? v / length : dvec3(0.0);
}

class Tracer {
 public:
  Tracer(const ReferenceScene& scene, const ReferenceOptions& options)
      : scene_(scene), options_(options), room_(scene.room) {
    for (uint32_t p = 0; p < scene.room.patches.size(); ++p) {
      const scene::Patch& patch = scene.room.patches[p];
      if (!patch.emits()) continue;
      const std::array<dvec3, 4> polygon = lighting::patchPolygon(scene.room, p);
      const auto [centre, radius] = boundingBall(polygon);
      emitters_.push_back({polygon, patch.normal, patch.emission, patch.area, centre, radius});
    }
    if (scene.object) {
      objectMesh_.indices = scene.object->mesh.indices;
      for (const core::Vec3& v : scene.object->mesh.positions) {
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
          throw std::invalid_argument("renderReference: object position is not finite");
        }
        objectMesh_.positions.emplace_back(v.x, v.y, v.z);
      }
      objectMesh_.normals.assign(objectMesh_.positions.size(), dvec3(0.0));
      objectMesh_.trianglePatch.assign(objectMesh_.triangleCount(), 0);
      object_ = std::make_unique<lighting::EmbreeScene>(objectMesh_);
      std::tie(objectCentre_, objectRadius_) = boundingBall(objectMesh_.positions);
    }
  }

  // One camera sample: fills the pair (room without / with the product) and says whether
  // the sample saw the product; `roomDelta` is absent - present for room samples.
  void cameraSample(const dvec3& origin, const dvec3& dir, double tMax, Stream& rng, Pair& out,
                    bool& sawObject) const {
    const std::optional<SurfaceHit> roomHit = traceRoom(origin, dir, tMax);
    const std::optional<lighting::Hit> objectHit =
        object_ ? object_->intersect(origin, dir, 0.0, tMax) : std::nullopt;
    sawObject = objectHit && (!roomHit || objectHit->t < roomHit->t);
    out = Pair{};
    const bool differenceOnly = options_.differenceOnly && options_.bounces == 0;
    if (sawObject) {
      // The product in front: `present` is its radiance, `absent` the room behind it. The
      // two paths draw from copies of the stream so each sees the numbers a lone path would.
      const SurfaceHit hit = objectSurface(origin, dir, *objectHit);
      Stream objectRng = rng;
      out.present = shade(hit, kPresent, objectRng, 0).present;
      if (roomHit && !differenceOnly) {
        out.absent = roomHit->emission + shade(*roomHit, kAbsent, rng, 0).absent;
      }
      return;
    }
    if (!roomHit) return;
    if (differenceOnly && !productMayShadow(*roomHit)) {
      out.absent = out.present = roomHit->emission;
      return;
    }
    const Pair p = shade(*roomHit, kBoth, rng, 0);
    out.absent = roomHit->emission + p.absent;
    out.present = roomHit->emission + p.present;
  }

 private:
  // Nearest room surface on origin + t dir, t in [0, tMax].
  std::optional<SurfaceHit> traceRoom(const dvec3& origin, const dvec3& dir, double tMax) const {
    const std::optional<lighting::Hit> h = room_.intersect(origin, dir, 0.0, tMax);
    if (!h) return std::nullopt;
    const scene::PatchMesh& m = scene_.room;
    SurfaceHit s;
    s.x = origin + h->t * dir;
    s.t = h->t;
    s.n = faceNormal(m.positions, m.indices, h->triangle);
    const scene::Patch& patch = m.patches[m.trianglePatch[h->triangle]];
    s.reflectance = patch.reflectance;
    // One-sided emitters (as lighting/radiance_transfer.cpp treats sources): seen from the
    // front only.
    if (glm::dot(patch.normal, dir) < 0) s.emission = patch.emission;
    if (glm::dot(s.n, dir) > 0) s.n = -s.n;
    s.offset = s.n;
    return s;
  }

  SurfaceHit objectSurface(const dvec3& origin, const dvec3& dir, const lighting::Hit& h) const {
    SurfaceHit s;
    s.x = origin + h.t * dir;
    s.t = h.t;
    // The face normal, turned towards the viewer, offsets the rays leaving the surface.
    s.offset = faceNormal(objectMesh_.positions, objectMesh_.indices, h.triangle);
    if (glm::dot(s.offset, dir) > 0) s.offset = -s.offset;
    const ReferenceObject& object = *scene_.object;
    const size_t t = 3 * size_t{h.triangle};
    const uint32_t i0 = objectMesh_.indices[t], i1 = objectMesh_.indices[t + 1],
                   i2 = objectMesh_.indices[t + 2];
    const double w0 = 1.0 - h.u - h.v;
    if (object.normals.empty()) {
      s.n = s.offset;
    } else {
      // The per-frame path's vertex normals, interpolated as its rasterizer interpolates the
      // vertex colours they give (Phong 1975 interpolates normals; the frame path interpolates
      // colours, Gouraud 1971: the two agree at the vertices).
      const dvec3 n = w0 * unit(object.normals[i0]) + h.u * unit(object.normals[i1]) +
                      h.v * unit(object.normals[i2]);
      const double length = glm::length(n);
      s.n = length > 0 ? n / length : s.offset;
    }
    s.reflectance = object.reflectances.empty()
                        ? object.reflectance
                        : w0 * object.reflectances[i0] + h.u * object.reflectances[i1] +
                              h.v * object.reflectances[i2];
    return s;
  }

  // Reflected radiance at `hit` for the active scenes: direct light from every emitter,
  // then (below options_.bounces) one indirect bounce.
  Pair shade(const SurfaceHit& hit, int active, Stream& rng, int depth) const {
    Pair out = direct(hit, active, rng);
    if (depth >= options_.bounces) return out;
    // Cosine-distributed direction about n (Malley's method): pdf cos / pi against the
    // diffuse BRDF rho / pi leaves the weight rho (FCG ch. 23).
    const double u1 = rng.next(), u2 = rng.next();
    const double r = std::sqrt(u1), phi = 2.0 * std::numbers::pi * u2;
    const dvec3 n = hit.n;
    const dvec3 t = glm::normalize(std::abs(n.x) > 0.5 ? glm::cross(n, dvec3(0, 1, 0))
                                                       : glm::cross(n, dvec3(1, 0, 0)));
    const dvec3 b = glm::cross(n, t);
    const dvec3 dir =
        r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0, 1.0 - u1)) * n;
    const dvec3 origin = hit.x + options_.normalOffset * hit.offset;
    constexpr double kFar = 1e3;
    const std::optional<SurfaceHit> roomHit = traceRoom(origin, dir, kFar);
    const double roomT = roomHit ? roomHit->t : kFar;
    std::optional<lighting::Hit> objectHit;
    if ((active & kPresent) && object_) objectHit = object_->intersect(origin, dir, 0.0, kFar);
    const bool presentOnObject = objectHit && objectHit->t < roomT;
    Pair in;
    if (!presentOnObject) {
      if (roomHit) in = shade(*roomHit, active, rng, depth + 1);
    } else {
      Stream objectRng = rng;
      in.present =
          shade(objectSurface(origin, dir, *objectHit), kPresent, objectRng, depth + 1).present;
      if ((active & kAbsent) && roomHit)
        in.absent = shade(*roomHit, kAbsent, rng, depth + 1).absent;
    }
    out.absent += hit.reflectance * in.absent;
    out.present += hit.reflectance * in.present;
    return out;
  }

  // The direct term of the header's equation for the active scenes.
  Pair direct(const SurfaceHit& hit, int active, Stream& rng) const {
    const size_t count = emitters_.size();
    // Unoccluded light and the sampling distribution, in emitter order.
    // Per-thread scratch (direct() does not recurse).
    thread_local std::vector<double> cdf, formFactor;
    cdf.assign(count, 0.0);
    formFactor.assign(count, 0.0);
    dvec3 unoccluded(0.0);
    double total = 0;
    for (size_t j = 0; j < count; ++j) {
      const Emitter& e = emitters_[j];
      // One-sided: a point behind the emitter's plane receives nothing from it.
      if (glm::dot(e.normal, hit.x - e.polygon[0]) > 0) {
        formFactor[j] = lighting::pointToPolygonFormFactor(hit.x, hit.n, e.polygon);
      }
      unoccluded += e.emission * formFactor[j];
      total += core::luminance(e.emission) * formFactor[j];
      cdf[j] = total;
    }
    Pair out;
    if (!(total > 0)) return out;
    dvec3 blockedByRoom(0.0), blockedByObject(0.0);
    const int n = options_.lightSamples;
    const dvec3 origin = hit.x + options_.normalOffset * hit.offset;
    for (int k = 0; k < n; ++k) {
      // Systematic sampling of the emitter distribution: sample k picks from the k-th
      // n-quantile, so each emitter gets its share of the samples to within one.
      const double target = (k + rng.next()) / n * total;
      size_t j =
          static_cast<size_t>(std::upper_bound(cdf.begin(), cdf.end(), target) - cdf.begin());
      j = std::min(j, count - 1);
      while (j > 0 && formFactor[j] == 0) --j;  // a rounding overshoot onto a dark emitter
      // Both variates are drawn either way, so the stream stays in step with the default's.
      double su = rng.next(), sv = rng.next();
      if (options_.pointLights) su = sv = 0.5;
      const Emitter& e = emitters_[j];
      const dvec3 y =
          e.polygon[0] + su * (e.polygon[1] - e.polygon[0]) + sv * (e.polygon[3] - e.polygon[0]);
      const double pj = core::luminance(e.emission) * formFactor[j] / total;
      if (!(pj > 0)) continue;
      if (options_.pointLights) {
        // A centre behind the surface, or facing away, is not a direction light comes from.
        const dvec3 toCentre = y - hit.x;
        if (!(glm::dot(hit.n, toCentre) > 0) || !(glm::dot(e.normal, toCentre) < 0)) continue;
        // The whole patch's light, F_j E_j, over the samples it expects (pj n): the blocked
        // sum is then exactly the light of the emitters whose centre is hidden, once every
        // emitter gets its share of the samples.
        const dvec3 weight = e.emission * (formFactor[j] / (pj * n));
        if (room_.occluded(origin, y)) {
          blockedByRoom += weight;
        } else if ((active & kPresent) && object_ && object_->occluded(origin, y)) {
          blockedByObject += weight;
        }
        continue;
      }
      const dvec3 d = y - hit.x;
      const double r2 = glm::dot(d, d);
      if (!(r2 > 0)) continue;
      const double r = std::sqrt(r2);
      const double cosX = glm::dot(hit.n, d) / r, cosY = -glm::dot(e.normal, d) / r;
      if (!(cosX > 0) || !(cosY > 0)) continue;  // outside the clipped polygon F integrates
      const dvec3 weight = e.emission * (cosX * cosY / (std::numbers::pi * r2) * e.area / (pj * n));
      if (room_.occluded(origin, y)) {
        blockedByRoom += weight;
      } else if ((active & kPresent) && object_ && object_->occluded(origin, y)) {
        blockedByObject += weight;
      }
    }
    const dvec3 absent = unoccluded - blockedByRoom;
    out.absent = hit.reflectance * absent;
    out.present = hit.reflectance * (absent - blockedByObject);
    return out;
  }

  // Whether any shadow ray direct() could cast from `hit` might meet the product. Such a ray
  // runs from the offset origin o to a point y of an emitter that faces the hit (direct()
  // samples no other). If it meets the product, it passes through the product's ball (centre
  // s, radius R), so its direction lies within asin(R/|s - o|) of s - o; y lies in the
  // emitter's ball (c, rho), so within asin(rho/|c - o|) of c - o. Both cones must overlap:
  // angle(s - o, c - o) <= asin(R/|s - o|) + asin(rho/|c - o|), compared as cosines (cos of a
  // sum from the sines, no trigonometry). And the product must come before y: |s - o| - R <
  // |c - o| + rho. Inside either ball nothing is ruled out.
  bool productMayShadow(const SurfaceHit& hit) const {
    if (!object_) return false;
    const dvec3 o = hit.x + options_.normalOffset * hit.offset;
    const dvec3 a = objectCentre_ - o;
    const double da = glm::length(a);
    if (da <= objectRadius_) return true;
    const double sinA = objectRadius_ / da, cosA = std::sqrt(1.0 - sinA * sinA);
    for (const Emitter& e : emitters_) {
      if (!(glm::dot(e.normal, hit.x - e.polygon[0]) > 0)) continue;  // as direct() skips it
      const dvec3 b = e.centre - o;
      const double db = glm::length(b);
      if (db <= e.radius) return true;
      if (da - objectRadius_ >= db + e.radius) continue;
      const double sinB = e.radius / db, cosB = std::sqrt(1.0 - sinB * sinB);
      if (glm::dot(a, b) / (da * db) >= cosA * cosB - sinA * sinB - 1e-12) return true;
    }
    return false;
  }

  const ReferenceScene& scene_;
  const ReferenceOptions& options_;
  lighting::EmbreeScene room_;
  scene::PatchMesh objectMesh_;
  std::unique_ptr<lighting::EmbreeScene> object_;
  dvec3 objectCentre_{0.0};
  double objectRadius_ = 0;
  std::vector<Emitter> emitters_;
};

void validate(const ReferenceScene& scene, const ReferenceOptions& options) {
  if (scene.width == 0 || scene.height == 0 || scene.width > raster::kMaxImageSide ||
      scene.height > raster::kMaxImageSide) {
    throw std::invalid_argument("renderReference: image size must be 1.." +
                                std::to_string(raster::kMaxImageSide) + " per side");
  }
  if (options.samplesPerPixel < 1 || options.samplesPerPixel > 65536) {
    throw std::invalid_argument("renderReference: samples per pixel must be 1..65536");
  }
  if (options.lightSamples < 1 || options.lightSamples > 65536) {
    throw std::invalid_argument("renderReference: light samples must be 1..65536");
  }
  if (options.bounces < 0 || options.bounces > 16) {
    throw std::invalid_argument("renderReference: bounces must be 0..16");
  }
  if (!(options.normalOffset >= 0) || !std::isfinite(options.normalOffset)) {
    throw std::invalid_argument("renderReference: normal offset must be finite, >= 0");
  }
  if (const auto& w = options.window;
      w && !(w->x0 < w->x1 && w->x1 <= scene.width && w->y0 < w->y1 && w->y1 <= scene.height)) {
    throw std::invalid_argument(
        "renderReference: the window must be a non-empty part of the image");
  }
  const scene::PatchMesh& m = scene.room;
  if (m.trianglePatch.size() != m.triangleCount()) {
    throw std::invalid_argument("renderReference: room mesh has no patch for some triangle");
  }
  for (uint32_t p : m.trianglePatch) {
    if (p >= m.patches.size()) {
      throw std::invalid_argument("renderReference: triangle patch out of range");
    }
  }
  for (const dvec3& p : m.positions) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      throw std::invalid_argument("renderReference: room position is not finite");
    }
  }
  if (scene.object) {
    const ReferenceObject& o = *scene.object;
    for (uint32_t i : o.mesh.indices) {
      if (i >= o.mesh.positions.size()) {
        throw std::invalid_argument("renderReference: object index out of range");
      }
    }
    if ((!o.normals.empty() && o.normals.size() != o.mesh.positions.size()) ||
        (!o.reflectances.empty() && o.reflectances.size() != o.mesh.positions.size())) {
      throw std::invalid_argument("renderReference: object attributes are not one per vertex");
    }
  }
  if (!scene.cameraRay && (std::abs(glm::determinant(scene.viewProj)) == 0 ||
                           !std::isfinite(glm::determinant(scene.viewProj)))) {
    throw std::invalid_argument("renderReference: camera matrix is singular");
  }
}

}  // namespace

ReferenceImage renderReference(const ReferenceScene& scene, const ReferenceOptions& options,
                               const ReferenceProgress& progress) {
  validate(scene, options);
  const Tracer tracer(scene, options);
  const ReferenceOptions::Window window =
      options.window.value_or(ReferenceOptions::Window{0, 0, scene.width, scene.height});
  const glm::dmat4 inverse = scene.cameraRay ? glm::dmat4(1.0) : glm::inverse(scene.viewProj);
  const auto unproject = [&](double nx, double ny, double nz) {
    const glm::dvec4 p = inverse * glm::dvec4(nx, ny, nz, 1.0);
    return dvec3(p) / p.w;
  };
  ReferenceImage image;
  image.width = scene.width;
  image.height = scene.height;
  const size_t pixels = size_t{scene.width} * scene.height;
  image.noObject.assign(pixels, glm::vec3(0.0f));
  image.withObject.assign(pixels, glm::vec3(0.0f));
  image.roomDelta.assign(pixels, glm::vec3(0.0f));
  image.objectRadiance.assign(pixels, glm::vec3(0.0f));
  image.objectCoverage.assign(pixels, 0.0f);

  std::mutex progressMutex;
  uint32_t rowsDone = 0;
  const double halfW = 0.5 * scene.width, halfH = 0.5 * scene.height;
  // One image row per work item: a pixel's samples, draws and sums never leave its thread.
  // One pool per image (core/job_pool.h): rendering runs far longer than starting threads.
  core::JobPool pool(static_cast<int>(options.threads));
  pool.parallelFor(scene.height, [&](size_t py, int) {
    if (py < window.y0 || py >= window.y1) return;
    for (uint32_t px = window.x0; px < window.x1; ++px) {
      const size_t pixel = py * scene.width + px;
      const uint64_t pixelKey = core::splitmix64(options.seed ^ (uint64_t{pixel} * core::kGolden));
      dvec3 noObject(0.0), withObject(0.0), delta(0.0), objectSum(0.0);
      int objectSamples = 0;
      for (int s = 0; s < options.samplesPerPixel; ++s) {
        Stream rng{core::splitmix64(pixelKey ^ uint64_t(s))};
        // Drawn either way, so the light samples' streams do not depend on the choice.
        double jx = rng.next(), jy = rng.next();
        if (options.pixelCentres) jx = jy = 0.5;
        dvec3 origin, dir;
        double tMax = 1.0;
        Pair sample;
        bool sawObject = false;
        if (scene.cameraRay) {
          if (scene.cameraRay(double(px) + jx, double(py) + jy, origin, dir, tMax)) {
            tracer.cameraSample(origin, dir, tMax, rng, sample, sawObject);
          }
        } else {
          const double nx = (double(px) + jx) / halfW - 1.0;
          const double ny = 1.0 - (double(py) + jy) / halfH;
          origin = unproject(nx, ny, -1.0);
          tracer.cameraSample(origin, unproject(nx, ny, 1.0) - origin, 1.0, rng, sample, sawObject);
        }
        noObject += sample.absent;
        withObject += sample.present;
        if (sawObject) {
          objectSum += sample.present;
          ++objectSamples;
        } else {
          delta += sample.absent - sample.present;
        }
      }
      const double spp = options.samplesPerPixel;
      const int roomSamples = options.samplesPerPixel - objectSamples;
      image.noObject[pixel] = glm::vec3(noObject / spp);
      image.withObject[pixel] = glm::vec3(withObject / spp);
      if (roomSamples > 0) image.roomDelta[pixel] = glm::vec3(delta / double(roomSamples));
      if (objectSamples > 0) {
        image.objectRadiance[pixel] = glm::vec3(objectSum / double(objectSamples));
      }
      image.objectCoverage[pixel] = static_cast<float>(objectSamples / spp);
    }
    if (progress) {
      const std::lock_guard<std::mutex> lock(progressMutex);
      progress(++rowsDone, scene.height);
    }
  });
  return image;
}

core::ImageF hdrImageOf(uint32_t width, uint32_t height, const std::vector<glm::vec3>& radiance) {
  if (radiance.size() != size_t{width} * height) {
    throw std::invalid_argument("hdrImageOf: " + std::to_string(radiance.size()) +
                                " pixels for a " + std::to_string(width) + "x" +
                                std::to_string(height) + " image");
  }
  core::ImageF image;
  image.width = width;
  image.height = height;
  image.pixels.reserve(radiance.size() * 3);
  for (const glm::vec3& v : radiance) {
    image.pixels.push_back(v.r);
    image.pixels.push_back(v.g);
    image.pixels.push_back(v.b);
  }
  return image;
}

ReferenceScene referenceSceneOf(const shadow::SceneBundle& bundle,
                                const std::optional<shadow::ProductPose>& pose) {
  ReferenceScene scene;
  scene.room = shadow::patchMeshOf(bundle);
  scene.width = bundle.view.width;
  scene.height = bundle.view.height;
  // The trace stores rows (element (r, c) at m[4r + c]); GLM stores columns.
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c)
      scene.viewProj[c][r] = bundle.view.cameraViewProj.m[4 * size_t(r) + size_t(c)];
  }
  if (pose) {
    if (pose->product >= bundle.products.size()) {
      throw std::invalid_argument("product " + std::to_string(pose->product) + " does not exist (" +
                                  std::to_string(bundle.products.size()) + " products)");
    }
    if (!std::isfinite(pose->x) || !std::isfinite(pose->z) || !std::isfinite(pose->yawDegrees) ||
        !std::isfinite(pose->lift)) {
      throw std::invalid_argument("product pose is not finite");
    }
    const shadow::ProductModel& model = bundle.products[pose->product];
    ReferenceObject object;
    shadow::placeMesh(model.mesh, *pose, object.mesh);
    object.reflectance = dvec3(model.reflectance);
    // The normals and reflectances the per-frame shading uses (shadow::shadingNormals).
    for (const glm::vec3& n : shadow::shadingNormals(model, object.mesh, *pose)) {
      object.normals.emplace_back(n);
    }
    for (const glm::vec3& r : model.reflectances) object.reflectances.emplace_back(r);
    scene.object = std::move(object);
  }
  return scene;
}

}  // namespace penumbra::reference
