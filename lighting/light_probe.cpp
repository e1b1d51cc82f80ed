#include "lighting/light_probe.h"
#include "core/colour.h"
#include "core/random.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/job_pool.h"
#include "lighting/patch_radiosity.h"
#include "lighting/radiance_transfer.h"
#include "shadow/intensity_transfer.h"

namespace penumbra::lighting {
namespace {

constexpr double kPi = std::numbers::pi;

void checkImage(const core::ImageF& img) {
  if (img.width <= 0 || img.height <= 0 ||
      img.pixels.size() != size_t(img.width) * size_t(img.height) * 3) {
    throw std::invalid_argument("light probe: image size does not match its pixels");
  }
}

// Pixel containing image-plane point (u, v) in [-1, 1]^2 (v up).
void discPixel(const core::ImageF& img, double u, double v, uint32_t& x, uint32_t& y) {
  const double fx = (u + 1) * 0.5 * img.width, fy = (1 - v) * 0.5 * img.height;
  x = static_cast<uint32_t>(std::clamp(fx, 0.0, double(img.width - 1)));
  y = static_cast<uint32_t>(std::clamp(fy, 0.0, double(img.height - 1)));
}

}  // namespace

bool LightProbe::radiance(const glm::dvec3& d, glm::dvec3& out) const {
  checkImage(image);
  const double len = glm::length(d);
  if (!(len > 0)) return false;
  const glm::dvec3 p = glm::transpose(rotation) * (d / len);  // probe frame
  uint32_t x = 0, y = 0;
  switch (mapping) {
    case ProbeMapping::LatLong: {
      const double u = 0.5 + std::atan2(p.x, -p.z) / (2 * kPi);
      const double v = std::acos(std::clamp(p.y, -1.0, 1.0)) / kPi;
      x = static_cast<uint32_t>(std::clamp(u * image.width, 0.0, double(image.width - 1)));
      y = static_cast<uint32_t>(std::clamp(v * image.height, 0.0, double(image.height - 1)));
      break;
    }
    case ProbeMapping::MirrorBall: {
      glm::dvec3 h = p + glm::dvec3(0, 0, 1);
      const double hl = glm::length(h);
      // Straight behind the ball: its rim (every rim point reflects there).
      h = hl > 1e-12 ? h / hl : glm::dvec3(1, 0, 0);
      discPixel(image, h.x, h.y, x, y);
      break;
    }
    case ProbeMapping::Fisheye: {
      const double theta = std::acos(std::clamp(-p.z, -1.0, 1.0));
      const double r = theta / (fisheyeFovDegrees * kPi / 360.0);
      if (r > 1) return false;
      const double rxy = std::sqrt(p.x * p.x + p.y * p.y);
      const double u = rxy > 0 ? r * p.x / rxy : 0, v = rxy > 0 ? r * p.y / rxy : 0;
      discPixel(image, u, v, x, y);
      break;
    }
  }
  const float* px = image.pixel(x, y);
  out = glm::dvec3(px[0], px[1], px[2]);
  return true;
}

bool LightProbe::direction(uint32_t x, uint32_t y, glm::dvec3& out) const {
  checkImage(image);
  glm::dvec3 p;
  const double u = 2 * (x + 0.5) / image.width - 1, v = 1 - 2 * (y + 0.5) / image.height;
  switch (mapping) {
    case ProbeMapping::LatLong: {
      const double phi = ((x + 0.5) / image.width - 0.5) * 2 * kPi;
      const double theta = (y + 0.5) / image.height * kPi;
      p = {std::sin(theta) * std::sin(phi), std::cos(theta), -std::sin(theta) * std::cos(phi)};
      break;
    }
    case ProbeMapping::MirrorBall: {
      const double r2 = u * u + v * v;
      if (r2 > 1) return false;
      const glm::dvec3 n(u, v, std::sqrt(1 - r2));
      p = glm::dvec3(0, 0, -1) + 2 * n.z * n;  // reflect the view ray (0, 0, -1) in n
      break;
    }
    case ProbeMapping::Fisheye: {
      const double r = std::sqrt(u * u + v * v);
      if (r > 1) return false;
      const double theta = r * fisheyeFovDegrees * kPi / 360.0;
      const double s = std::sin(theta);
      p = r > 0 ? glm::dvec3(s * u / r, s * v / r, -std::cos(theta)) : glm::dvec3(0, 0, -1);
      break;
    }
  }
  out = rotation * glm::normalize(p);
  return true;
}

ProbeSanitizeReport sanitizeProbe(core::ImageF& image, float saturationLevel) {
  ProbeSanitizeReport r;
  for (size_t i = 0; i < image.pixels.size(); i += 3) {
    bool saturated = false;
    for (size_t c = i; c < i + 3; ++c) {
      float& v = image.pixels[c];
      if (!std::isfinite(v)) {
        ++r.nonFinite;
        v = 0;
      } else if (v < 0) {
        ++r.negative;
        r.mostNegative = std::min(r.mostNegative, v);
        v = 0;
      } else if (saturationLevel > 0 && v >= saturationLevel) {
        saturated = true;
      }
    }
    r.saturated += saturated;
  }
  return r;
}

ProbeProjection projectProbe(const LightProbe& probeIn, const scene::PatchMesh& mesh,
                             const EmbreeScene& rays, const ProbeProjectionOptions& options) {
  checkImage(probeIn.image);
  if (options.samplesPerSide < 1) {
    throw std::invalid_argument("projectProbe: samplesPerSide must be >= 1");
  }
  if (!(options.inset >= 0 && options.inset < 0.5)) {
    throw std::invalid_argument("projectProbe: inset must be in [0, 0.5)");
  }
  ProbeProjection out;
  LightProbe probe = probeIn;
  out.sanitize = sanitizeProbe(probe.image, options.saturationLevel);
  const ProbeSanitizeReport& s = out.sanitize;
  if (s.nonFinite) {
    out.warnings.push_back(std::to_string(s.nonFinite) + " NaN/infinite probe values set to 0");
  }
  if (s.negative) {
    out.warnings.push_back(std::to_string(s.negative) + " negative probe values (down to " +
                           std::to_string(s.mostNegative) + ", lossy compression) clamped to 0");
  }
  if (s.saturated) {
    out.warnings.push_back(std::to_string(s.saturated) +
                           " saturated probe pixels: their radiance is a lower bound, so patches "
                           "seen through them are too dark (take a shorter exposure)");
  }

  const size_t n = mesh.patches.size();
  out.radiance.assign(n, glm::dvec3(0.0));
  out.seen.assign(n, 0);
  const int side = options.samplesPerSide;
  // One pool per call (core/job_pool.h): this stage runs far longer than starting threads.
  core::JobPool pool(static_cast<int>(options.threads));
  pool.parallelFor(n, [&](size_t p, int) {
    const std::array<glm::dvec3, 4> poly = patchPolygon(mesh, static_cast<uint32_t>(p));
    const glm::dvec3& normal = mesh.patches[p].normal;
    const uint64_t key = core::splitmix64(options.seed ^ (uint64_t(p) * core::kGolden));
    glm::dvec3 sum(0.0);
    int hits = 0;
    for (int a = 0; a < side; ++a) {
      for (int b = 0; b < side; ++b) {
        const uint64_t h = core::splitmix64(key + core::kGolden * uint64_t(a * side + b));
        const double span = 1 - 2 * options.inset;
        const double su = options.inset + span * (a + core::unitInterval(h)) / side;
        const double sv =
            options.inset + span * (b + core::unitInterval(core::splitmix64(h))) / side;
        const glm::dvec3 point = poly[0] + su * (poly[1] - poly[0]) + sv * (poly[3] - poly[0]);
        const glm::dvec3 dir = point - probe.position;
        if (!(glm::dot(dir, normal) < 0)) continue;  // the probe is behind this patch
        const std::optional<Hit> hit = rays.intersect(probe.position, dir, 0, 1.0 + 1e-6);
        if (!hit || mesh.trianglePatch[hit->triangle] != p) continue;
        glm::dvec3 l;
        if (!probe.radiance(dir, l)) continue;
        sum += l;
        ++hits;
      }
    }
    if (hits > 0) {
      out.radiance[p] = sum / double(hits);
      out.seen[p] = 1;
    }
  });
  for (uint8_t v : out.seen) out.seenPatches += v;
  if (out.seenPatches == 0) {
    throw std::invalid_argument("projectProbe: the probe sees no patch (is it inside the room?)");
  }

  // §4.2: unseen patches reflect the default reflectance of what they gather.
  GatherOptions gather;
  gather.threads = options.threads;
  for (int it = 0; it < options.unseenIterations; ++it) {
    const std::vector<glm::dvec3> g = gatherPatchIrradiance(mesh, rays, out.radiance, gather);
    for (size_t p = 0; p < n; ++p) {
      if (!out.seen[p]) out.radiance[p] = options.defaultReflectance * g[p];
    }
  }
  out.gathered = gatherPatchIrradiance(mesh, rays, out.radiance, gather);

  out.materials.resize(n);
  for (size_t p = 0; p < n; ++p) {
    scene::Material& m = out.materials[p];
    m.reflectance = options.defaultReflectance;
    if (!out.seen[p]) continue;
    const glm::dvec3& l = out.radiance[p];
    const glm::dvec3& g = out.gathered[p];
    if (core::luminance(l) >
        core::luminance(g)) {  // implied reflectance > 1: an emitter (header rule)
      m.emission = glm::max(l - options.defaultReflectance * g, glm::dvec3(0.0));
      if (m.emits()) ++out.emitters;
      continue;
    }
    bool clamped = false;
    for (int c = 0; c < 3; ++c) {
      if (g[c] > 0) {
        const double r = l[c] / g[c];
        clamped = clamped || r > 1;
        m.reflectance[c] = std::min(1.0, r);
      }
    }
    out.clampedReflectances += clamped;
  }
  const size_t unseen = n - out.seenPatches;
  if (unseen) {
    out.warnings.push_back(std::to_string(unseen) + " of " + std::to_string(n) +
                           " patches not seen by the probe: reflectance set to the default, "
                           "radiance gathered");
  }
  if (out.clampedReflectances) {
    out.warnings.push_back(std::to_string(out.clampedReflectances) +
                           " patches with a channel reflectance above 1 clamped to 1");
  }
  return out;
}

void renderProbe(LightProbe& probe, const scene::PatchMesh& mesh, const EmbreeScene& rays,
                 const std::vector<glm::dvec3>& patchRadiance) {
  checkImage(probe.image);
  if (patchRadiance.size() != mesh.patches.size()) {
    throw std::invalid_argument("renderProbe: one radiance per patch needed");
  }
  for (uint32_t y = 0; y < uint32_t(probe.image.height); ++y) {
    for (uint32_t x = 0; x < uint32_t(probe.image.width); ++x) {
      float* px = probe.image.pixel(x, y);
      px[0] = px[1] = px[2] = 0.0f;
      glm::dvec3 d;
      if (!probe.direction(x, y, d)) continue;
      const std::optional<Hit> hit = rays.intersect(probe.position, d);
      if (!hit) continue;
      const glm::dvec3& l = patchRadiance[mesh.trianglePatch[hit->triangle]];
      px[0] = float(l.x), px[1] = float(l.y), px[2] = float(l.z);
    }
  }
}

}  // namespace penumbra::lighting
