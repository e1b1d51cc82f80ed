#include "reference/reference_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include "lighting/form_factor.h"
#include "reference/differential.h"
#include "scene/camera.h"
#include "tests/showroom_bundle.h"

namespace penumbra::reference {
namespace {

using glm::dvec3;

// Appends the quad (a, b, c, d), counter-clockwise about its normal, as one patch of two
// triangles (a, b, c), (a, c, d) — the layout lighting::patchPolygon expects.
void addQuad(scene::PatchMesh& m, const dvec3& a, const dvec3& b, const dvec3& c, const dvec3& d,
             const dvec3& reflectance, const dvec3& emission) {
  const uint32_t v = static_cast<uint32_t>(m.positions.size());
  const dvec3 n = glm::normalize(glm::cross(b - a, d - a));
  for (const dvec3& p : {a, b, c, d}) {
    m.positions.push_back(p);
    m.normals.push_back(n);
  }
  const uint32_t patch = static_cast<uint32_t>(m.patches.size());
  scene::Patch p;
  p.centre = 0.25 * (a + b + c + d);
  p.normal = n;
  p.area = glm::length(glm::cross(b - a, d - a));
  p.reflectance = reflectance;
  p.emission = emission;
  p.firstTriangle = static_cast<uint32_t>(m.triangleCount());
  m.patches.push_back(p);
  for (uint32_t i : {v, v + 1, v + 2, v, v + 2, v + 3}) m.indices.push_back(i);
  m.trianglePatch.push_back(patch);
  m.trianglePatch.push_back(patch);
}

constexpr double kRho = 0.5;
const dvec3 kEmission(10.0, 8.0, 6.0);

// A 6 m floor (reflectance kRho) under one 1 m square emitter at height 2, facing down.
scene::PatchMesh floorAndLamp() {
  scene::PatchMesh m;
  addQuad(m, {-3, 0, -3}, {-3, 0, 3}, {3, 0, 3}, {3, 0, -3}, dvec3(kRho), dvec3(0.0));
  addQuad(m, {-0.5, 2, -0.5}, {0.5, 2, -0.5}, {0.5, 2, 0.5}, {-0.5, 2, 0.5}, dvec3(0.0), kEmission);
  return m;
}

// An opaque sheet at height 1 over x in [-3, 0]: from a floor point (x0, 0, z) with
// 0 <= x0 <= 0.5 it hides the lamp's part with x < -x0.
core::Mesh occluderSheet() {
  core::Mesh m;
  m.positions = {{-3, 1, -3}, {0, 1, -3}, {0, 1, 3}, {-3, 1, 3}};
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

glm::dmat4 cameraAt(const dvec3& eye, const dvec3& target, double fovYDegrees, double aspect) {
  scene::Camera c;
  c.eye = eye;
  c.target = target;
  c.fovYDegrees = fovYDegrees;
  c.aspect = aspect;
  c.zNear = 0.05;
  c.zFar = 20;
  return c.viewProj();
}

double rectangleFormFactor(const dvec3& x, double x0, double x1) {
  const std::vector<dvec3> poly = {{x0, 2, -0.5}, {x1, 2, -0.5}, {x1, 2, 0.5}, {x0, 2, 0.5}};
  return lighting::pointToPolygonFormFactor(x, dvec3(0, 1, 0), poly);
}

// A one-pixel camera with a 0.02 degree field of view at `eye`, looking at `target` under
// the lamp: every sample lands within a millimetre of it.
ReferenceScene onePixelScene(const dvec3& eye, const dvec3& target) {
  ReferenceScene scene;
  scene.room = floorAndLamp();
  scene.viewProj = cameraAt(eye, target, 0.02, 1.0);
  scene.width = scene.height = 1;
  return scene;
}

// A one-pixel camera with a 0.02 degree field of view: every sample lands within a
// millimetre of `target`, where the form factors are the closed-form ones.
TEST(ReferenceRenderer, MatchesClosedFormFormFactorWithinMonteCarloError) {
  const dvec3 target(0.2, 0, 0.1);
  ReferenceScene scene = onePixelScene({1.6, 0.6, 0.1}, target);
  scene.object = ReferenceObject{occluderSheet(), dvec3(0.3)};
  ReferenceOptions o;
  o.samplesPerPixel = 16;
  o.lightSamples = 256;
  o.threads = 1;
  const ReferenceImage image = renderReference(scene, o);

  const double full = rectangleFormFactor(target, -0.5, 0.5);
  const double visible = rectangleFormFactor(target, -target.x, 0.5);
  ASSERT_GT(full, 0.05);
  ASSERT_LT(visible, 0.8 * full);
  // Without the product nothing blocks the lamp: the estimator is the closed form itself.
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(image.noObject[0][c], kRho * kEmission[c] * full, 1e-5 * kEmission[c]) << c;
  }
  // With it, the blocked part is a Monte Carlo estimate over N = 4096 shadow rays, each
  // blocked with probability p ~ 1 - visible / full and weighing about `full`: standard
  // error full * sqrt(p (1 - p) / N). Allow four of them.
  const double p = 1.0 - visible / full;
  const double sigma = full * std::sqrt(p * (1 - p) / 4096.0);
  for (int c = 0; c < 3; ++c) {
    const double expected = kRho * kEmission[c] * visible;
    EXPECT_NEAR(image.withObject[0][c], expected, 4 * sigma * kRho * kEmission[c]) << c;
    EXPECT_FLOAT_EQ(image.roomDelta[0][c], image.noObject[0][c] - image.withObject[0][c]);
  }
  EXPECT_EQ(image.objectCoverage[0], 0.0f);
}

// Point lights: each emitter is blocked or not as seen from its centre, so the 1 m lamp over
// the sheet's edge is either all there or all gone, with its closed-form light.
TEST(ReferenceRenderer, PointLightsBlockEachEmitterAsAWholeFromItsCentre) {
  ReferenceOptions o;
  o.samplesPerPixel = 4;
  o.lightSamples = 16;
  o.threads = 1;
  o.pointLights = true;
  // From (0.2, 0, 0.1) the ray to the lamp's centre (0, 2, 0) crosses the sheet's height at
  // x = 0.1, past its edge; from (-0.2, 0, 0.1), at x = -0.1, through it.
  for (const double x : {0.2, -0.2}) {
    const dvec3 target(x, 0, 0.1);
    ReferenceScene scene = onePixelScene({x + 1.4, 0.6, 0.1}, target);
    scene.object = ReferenceObject{occluderSheet(), dvec3(0.3)};
    const ReferenceImage image = renderReference(scene, o);
    const double full = rectangleFormFactor(target, -0.5, 0.5);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(image.noObject[0][c], kRho * kEmission[c] * full, 1e-5 * kEmission[c]) << c;
      const double lit = x > 0 ? image.noObject[0][c] : 0.0;
      EXPECT_NEAR(image.withObject[0][c], lit, 1e-5 * kEmission[c]) << x << " " << c;
    }
  }
  // The default spreads the rays over the lamp: from (0.2, 0, 0.1) the sheet hides part of it.
  o.pointLights = false;
  ReferenceScene scene = onePixelScene({1.6, 0.6, 0.1}, {0.2, 0, 0.1});
  scene.object = ReferenceObject{occluderSheet(), dvec3(0.3)};
  const ReferenceImage area = renderReference(scene, o);
  EXPECT_LT(area.withObject[0][0], 0.9 * area.noObject[0][0]);
}

// Issue 15 item 6: the reference shades the product as the frame path does, with the
// model's vertex normals and reflectances interpolated at the hit. A small quad at 0.5 m
// under the lamp, seen by a one-pixel camera at its centre, with every vertex normal tilted
// 45 degrees towards +x and reflectances varying across it: nothing blocks the lamp from it,
// so its radiance is the closed form rho(hit) E F(x, n) exactly.
TEST(ReferenceRenderer, ProductIsShadedWithItsVertexNormalsAndReflectances) {
  const dvec3 target(0.2, 0.5, 0.1);
  ReferenceScene scene = onePixelScene({0.25, 1.2, 0.1}, target);
  ReferenceObject object;
  object.mesh.positions = {
      {0.1f, 0.5f, 0.0f}, {0.1f, 0.5f, 0.2f}, {0.3f, 0.5f, 0.2f}, {0.3f, 0.5f, 0.0f}};
  object.mesh.indices = {0, 1, 2, 0, 2, 3};
  object.normals.assign(4, dvec3(1, 1, 0));  // normalized at the hit
  // Reflectance 0.2 along x = 0.1, 0.6 along x = 0.3: 0.4 at the centre line x = 0.2.
  object.reflectances = {dvec3(0.2), dvec3(0.2), dvec3(0.6), dvec3(0.6)};
  scene.object = object;
  ReferenceOptions o;
  o.samplesPerPixel = 4;
  o.lightSamples = 16;
  o.threads = 1;
  const ReferenceImage image = renderReference(scene, o);
  ASSERT_EQ(image.objectCoverage[0], 1.0f);
  const std::vector<dvec3> lamp = {{-0.5, 2, -0.5}, {0.5, 2, -0.5}, {0.5, 2, 0.5}, {-0.5, 2, 0.5}};
  const double tilted =
      lighting::pointToPolygonFormFactor(target, glm::normalize(dvec3(1, 1, 0)), lamp);
  const double flat = lighting::pointToPolygonFormFactor(target, dvec3(0, 1, 0), lamp);
  ASSERT_GT(std::abs(tilted - flat), 0.05 * flat);  // the normals matter here
  for (int c = 0; c < 3; ++c) {
    // The samples spread within a millimetre of the target: reflectance 0.4 +- 0.01.
    EXPECT_NEAR(image.objectRadiance[0][c], 0.4 * kEmission[c] * tilted,
                0.01 * kEmission[c] * tilted)
        << c;
  }
}

ReferenceScene shadowScene(uint32_t width, uint32_t height) {
  ReferenceScene scene;
  scene.room = floorAndLamp();
  // Looking down at the floor across the sheet's shadow edge, from the lit side.
  scene.viewProj = cameraAt({1.8, 0.9, 0.0}, {0.1, 0, 0}, 50, double(width) / height);
  scene.width = width;
  scene.height = height;
  scene.object = ReferenceObject{occluderSheet(), dvec3(0.3)};
  return scene;
}

double rmsDifference(const std::vector<glm::vec3>& a, const std::vector<glm::vec3>& b) {
  double sum = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    const glm::vec3 d = a[i] - b[i];
    sum += double(glm::dot(d, d));
  }
  return std::sqrt(sum / double(a.size()));
}

TEST(ReferenceRenderer, ErrorHalvesWhenSamplesQuadruple) {
  const ReferenceScene scene = shadowScene(32, 24);
  ReferenceOptions o;
  o.lightSamples = 4;
  o.threads = 2;
  o.samplesPerPixel = 64;
  o.seed = 99;  // the high-spp render draws numbers unrelated to the ones it judges
  const ReferenceImage truth = renderReference(scene, o);
  o.seed = 1;
  o.samplesPerPixel = 1;
  const double e1 = rmsDifference(renderReference(scene, o).withObject, truth.withObject);
  o.samplesPerPixel = 4;
  const double e4 = rmsDifference(renderReference(scene, o).withObject, truth.withObject);
  // Error against truth: sqrt(s^2 / spp + s^2 / 64); the ratio is 1.96 for 1 -> 4.
  ASSERT_GT(e4, 0);
  EXPECT_GT(e1 / e4, 1.6) << e1 << " " << e4;
  EXPECT_LT(e1 / e4, 2.5) << e1 << " " << e4;
}

template <class T>
bool sameBytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST(ReferenceRenderer, SameBytesForAnyThreadCount) {
  ReferenceScene scene = shadowScene(20, 15);
  ReferenceOptions o;
  o.samplesPerPixel = 2;
  o.lightSamples = 8;
  o.bounces = 1;
  o.threads = 1;
  const ReferenceImage one = renderReference(scene, o);
  o.threads = 3;
  const ReferenceImage three = renderReference(scene, o);
  EXPECT_TRUE(sameBytes(one.noObject, three.noObject));
  EXPECT_TRUE(sameBytes(one.withObject, three.withObject));
  EXPECT_TRUE(sameBytes(one.roomDelta, three.roomDelta));
  EXPECT_TRUE(sameBytes(one.objectRadiance, three.objectRadiance));
  EXPECT_TRUE(sameBytes(one.objectCoverage, three.objectCoverage));
  o.seed = 2;  // and the seed does matter
  EXPECT_FALSE(sameBytes(one.withObject, renderReference(scene, o).withObject));
}

TEST(ReferenceRenderer, ProductFarAwayLeavesTheBackgroundByteExact) {
  ReferenceScene scene = shadowScene(32, 24);
  // The sheet moved 50 m under the floor: it blocks no shadow ray and no camera ray.
  for (core::Vec3& p : scene.object->mesh.positions) p.y -= 50;
  ReferenceOptions o;
  o.samplesPerPixel = 2;
  o.lightSamples = 8;
  o.bounces = 1;
  const ReferenceImage image = renderReference(scene, o);
  // A background with every code in every channel.
  std::vector<uint8_t> background(size_t{scene.width} * scene.height * 4);
  for (size_t i = 0; i < background.size(); ++i) {
    background[i] = i % 4 == 3 ? 255 : static_cast<uint8_t>((i * 37 + i / 4) % 256);
  }
  const shadow::ToneCurve tone = shadow::ToneCurve::gamma(0.4, 2.2);
  const DifferentialFrame frame = composeDifferential(image, background, tone);
  EXPECT_EQ(frame.rgba, background);
  EXPECT_EQ(frame.shadowPixels, 0u);
  EXPECT_EQ(frame.objectPixels, 0u);
}

TEST(ReferenceRenderer, ProductInPlaceCastsAShadowAndShowsItself) {
  ReferenceScene scene = shadowScene(32, 24);
  ReferenceOptions o;
  o.samplesPerPixel = 2;
  o.lightSamples = 8;
  const ReferenceImage image = renderReference(scene, o);
  std::vector<uint8_t> background(size_t{scene.width} * scene.height * 4, 200);
  const DifferentialFrame frame =
      composeDifferential(image, background, shadow::ToneCurve::gamma(0.4, 2.2));
  EXPECT_GT(frame.shadowPixels, 20u);
  // Shadow pixels only ever get darker.
  for (size_t i = 0; i < frame.shadowMask.size(); ++i) {
    if (frame.shadowMask[i] == 0) continue;
    for (int c = 0; c < 3; ++c) EXPECT_LE(frame.rgba[4 * i + size_t(c)], 200);
  }
}

TEST(ReferenceRenderer, PixelCentresSampleWhatTheRasterizerSamples) {
  ReferenceScene scene = shadowScene(32, 24);
  // From above the sheet (y = 1, x <= 0) and beside the lamp (y = 2, |x| <= 0.5), looking
  // down at the sheet's edge x = 0.
  scene.viewProj = cameraAt({1.5, 2.5, 0.0}, {0.0, 1, 0}, 50, 32.0 / 24);
  ReferenceOptions o;
  o.samplesPerPixel = 4;
  o.lightSamples = 4;
  const ReferenceImage jittered = renderReference(scene, o);
  o.pixelCentres = true;
  const ReferenceImage centred = renderReference(scene, o);
  // Jittered samples straddle the sheet's silhouette (partial coverage); through the centre
  // a pixel is the product's or not, as a rasterized pixel is.
  size_t partialJittered = 0;
  for (float c : jittered.objectCoverage) partialJittered += c > 0 && c < 1;
  size_t covered = 0;
  for (float c : centred.objectCoverage) {
    EXPECT_TRUE(c == 0 || c == 1) << c;
    covered += c == 1;
  }
  EXPECT_GT(partialJittered, 0u);
  EXPECT_GT(covered, 0u);
}

TEST(ReferenceRenderer, AWindowRendersItsPixelsAsTheWholeImageDoes) {
  const ReferenceScene scene = shadowScene(32, 24);
  ReferenceOptions o;
  o.samplesPerPixel = 2;
  o.lightSamples = 4;
  const ReferenceImage whole = renderReference(scene, o);
  o.window = ReferenceOptions::Window{5, 3, 20, 11};
  const ReferenceImage part = renderReference(scene, o);
  size_t inside = 0;
  for (uint32_t y = 0; y < scene.height; ++y) {
    for (uint32_t x = 0; x < scene.width; ++x) {
      const size_t i = size_t{y} * scene.width + x;
      const bool in = x >= 5 && x < 20 && y >= 3 && y < 11;
      inside += in;
      // Per-pixel streams: a pixel's bytes do not depend on which others are rendered.
      EXPECT_EQ(part.withObject[i], in ? whole.withObject[i] : glm::vec3(0.0f)) << x << "," << y;
      EXPECT_EQ(part.roomDelta[i], in ? whole.roomDelta[i] : glm::vec3(0.0f)) << x << "," << y;
    }
  }
  EXPECT_EQ(inside, 15u * 8u);
  o.window = ReferenceOptions::Window{5, 3, 33, 11};  // past the right edge
  EXPECT_THROW(renderReference(scene, o), std::invalid_argument);
  o.window = ReferenceOptions::Window{5, 3, 5, 11};  // empty
  EXPECT_THROW(renderReference(scene, o), std::invalid_argument);
}

// differenceOnly: the showroom's teapot in the far corner, a window round it and far beyond.
// The difference, the product's radiance and coverage are the same bytes; most room pixels
// (those whose emitters all lie outside the teapot's cone) skip their light, and every pixel
// the teapot shadows is among those that do not. With a bounce it changes nothing.
// The same render without and with ReferenceOptions::differenceOnly.
std::pair<ReferenceImage, ReferenceImage> withoutAndWithDifferenceOnly(const ReferenceScene& scene,
                                                                       ReferenceOptions o) {
  o.differenceOnly = false;
  ReferenceImage full = renderReference(scene, o);
  o.differenceOnly = true;
  return {std::move(full), renderReference(scene, o)};
}

TEST(ReferenceRenderer, DifferenceOnlyGivesTheSameDifferenceAndSkipsWhatCannotBeShadowed) {
  const ReferenceScene scene =
      referenceSceneOf(testing::showroomBundle(), shadow::ProductPose{2, 5.6f, 3.05f, 0.0f, 0.0f});
  ReferenceOptions o;
  o.samplesPerPixel = 2;
  o.lightSamples = 4;
  o.threads = 2;
  o.window = ReferenceOptions::Window{120, 180, 330, 330};
  const auto [full, part] = withoutAndWithDifferenceOnly(scene, o);
  EXPECT_TRUE(sameBytes(full.roomDelta, part.roomDelta));
  EXPECT_TRUE(sameBytes(full.objectRadiance, part.objectRadiance));
  EXPECT_TRUE(sameBytes(full.objectCoverage, part.objectCoverage));
  size_t room = 0, skipped = 0, shadowed = 0;
  for (size_t i = 0; i < full.roomDelta.size(); ++i) {
    if (full.objectCoverage[i] > 0 || full.noObject[i] == glm::vec3(0.0f)) continue;
    ++room;
    const bool skip = part.noObject[i] != full.noObject[i];
    skipped += skip;
    if (full.roomDelta[i] != glm::vec3(0.0f)) {
      ++shadowed;
      EXPECT_FALSE(skip) << "pixel " << i % scene.width << ", " << i / scene.width;
    }
  }
  EXPECT_GT(shadowed, 50u);
  EXPECT_GT(skipped, room / 2) << "of " << room << " room pixels";

  o.bounces = 1;
  o.window = ReferenceOptions::Window{200, 230, 240, 260};
  const auto [bouncedFull, bounced] = withoutAndWithDifferenceOnly(scene, o);
  EXPECT_TRUE(sameBytes(bounced.noObject, bouncedFull.noObject));
  EXPECT_TRUE(sameBytes(bounced.roomDelta, bouncedFull.roomDelta));
}

TEST(ReferenceRenderer, IndirectLightOnlyAdds) {
  // A closed box lit from inside: one bounce adds light to every pixel, never removes it.
  scene::PatchMesh m;
  const dvec3 rho(0.6);
  addQuad(m, {0, 0, 0}, {0, 0, 2}, {2, 0, 2}, {2, 0, 0}, rho, dvec3(0.0));  // floor, up
  addQuad(m, {0, 2, 0}, {2, 2, 0}, {2, 2, 2}, {0, 2, 2}, rho, dvec3(0.0));  // ceiling, down
  addQuad(m, {0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, rho, dvec3(0.0));  // z = 0, +z
  addQuad(m, {0, 0, 2}, {0, 2, 2}, {2, 2, 2}, {2, 0, 2}, rho, dvec3(0.0));  // z = 2, -z
  addQuad(m, {0, 0, 0}, {0, 2, 0}, {0, 2, 2}, {0, 0, 2}, rho, dvec3(0.0));  // x = 0, +x
  addQuad(m, {1.8, 0.8, 0.8}, {1.8, 0.8, 1.2}, {1.8, 1.2, 1.2}, {1.8, 1.2, 0.8}, dvec3(0.0),
          dvec3(20.0));  // a lamp near x = 2, facing -x
  ReferenceScene scene;
  scene.room = m;
  scene.viewProj = cameraAt({1.7, 1.5, 0.3}, {0.0, 0.5, 1.5}, 80, 1.0);
  scene.width = scene.height = 12;
  ReferenceOptions o;
  o.samplesPerPixel = 4;
  o.lightSamples = 8;
  const ReferenceImage direct = renderReference(scene, o);
  o.bounces = 1;
  const ReferenceImage bounced = renderReference(scene, o);
  double directSum = 0, bouncedSum = 0;
  for (size_t i = 0; i < direct.noObject.size(); ++i) {
    directSum += direct.noObject[i].x;
    bouncedSum += bounced.noObject[i].x;
    EXPECT_GE(bounced.noObject[i].x, direct.noObject[i].x) << i;
  }
  // Walls of reflectance 0.6 around the lamp: the first bounce adds a large share.
  EXPECT_GT(bouncedSum, 1.2 * directSum);
}

TEST(ReferenceRenderer, RejectsBadArguments) {
  const ReferenceScene good = shadowScene(8, 6);
  ReferenceOptions o;
  auto expectThrow = [&](ReferenceScene s, ReferenceOptions opt) {
    EXPECT_THROW(renderReference(s, opt), std::invalid_argument);
  };
  ReferenceScene s = good;
  s.width = 0;
  expectThrow(s, o);
  s = good;
  s.viewProj = glm::dmat4(0.0);
  expectThrow(s, o);
  s = good;
  s.object->mesh.indices.push_back(99);
  s.object->mesh.indices.push_back(0);
  s.object->mesh.indices.push_back(1);
  expectThrow(s, o);
  s = good;
  s.room.positions[0].x = std::nan("");
  expectThrow(s, o);
  ReferenceOptions bad = o;
  bad.samplesPerPixel = 0;
  expectThrow(good, bad);
  bad = o;
  bad.lightSamples = -1;
  expectThrow(good, bad);
  bad = o;
  bad.bounces = 17;
  expectThrow(good, bad);
  const ReferenceImage image = renderReference(good, o);
  std::vector<uint8_t> wrong(10);
  EXPECT_THROW(composeDifferential(image, wrong, shadow::ToneCurve::gamma(1)),
               std::invalid_argument);
}

}  // namespace
}  // namespace penumbra::reference
