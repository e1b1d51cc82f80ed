// The synthetic showroom with a known answer (issue 5 item 2): from a scene file, path
// trace everything a real capture of the room would give, so the capture pipeline, the
// precompute and Penumbra's frames can be checked against a scene whose truth is known.
//
// `penumbra synth-showroom SCENE.json --out DIR` writes into DIR:
//   room.exr                 HDR radiance of the empty room from the kiosk camera (R, G, B)
//   exposure_<i>.png         8-bit photographs at bracketed exposure times (i = 0..n-1)
//   camera_response.json     the response curve and exposure times they were taken through
//   photograph.png           the middle exposure: the "background photograph"
//   object_present.png/.exr  the same photograph with the product physically in the room
//   probe.exr, probe.json    a mirrored-ball image taken at a point in the room, its pose
//   calibration.json         image positions of known room corners, line pairs along the
//                            x and z axes, their vanishing points and the true camera
//   synth_showroom.json      the manifest: every file, the options and the seed
// docs/synth-showroom.md documents every file's format.
//
// Light transport is reference::renderReference with interreflections (bounces) over the
// scene's own patch mesh (the "real room"); the empty and object-present images come from
// one render (the same samples), so they differ only where the product changes the light.
// Every byte is a function of (scene, options): same files for any thread count.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>

#include <glm/glm.hpp>

#include "reference/reference_renderer.h"
#include "scene/scene_file.h"
#include "shadow/scene_bundle.h"

namespace penumbra::reference {

// The synthetic camera's response: a smooth S-curve in log exposure (a Hill / Naka–Rushton
// curve, the shape of film and of most measured camera responses):
//
//   code(E) = round(255 E^g / (E^g + E_mid^g)),   E = radiance x exposure time,
//
// monotone, code 128 near E = E_mid, 0 and 255 reached about 7 stops below / above it
// (g = 1.6). Noise-free.
struct CameraResponse {
  double gamma = 1.6;
  double midExposure = 0.5;
  uint8_t operator()(double exposure) const;
  // The exposure at the middle of code k's interval (what an ideal calibration recovers):
  // the inverse of the continuous curve at k (k = 0: half of code 1's lower edge; 255: its
  // lower edge).
  double inverse(int code) const;
};

struct SynthOptions {
  ReferenceOptions render{.samplesPerPixel = 16,
                          .lightSamples = 16,
                          .bounces = 2,
                          .threads = 2,
                          .seed = 7,
                          .normalOffset = 1e-4,
                          .window = std::nullopt};
  uint32_t width = 0, height = 0;  // 0: the scene file's
  int exposures = 5;               // >= 5 bracketed photographs
  double stopsBetween = 2.0;       // exposure ratio 2^stopsBetween between neighbours
  CameraResponse response;
  // The middle exposure time; 0: the scene's display exposure (tone.exposure).
  double middleExposureTime = 0;
  glm::dvec3 probePosition{3.0, 1.2, 2.5};
  uint32_t probeSize = 256;
  // The product in the object-present photograph; empty: the scene's start pose.
  std::optional<shadow::ProductPose> pose;
};

// Writes the files above into `dir` (created if missing). Throws std::invalid_argument for
// bad options (fewer than 5 exposures, non-positive sizes, a probe outside the room's
// bounds, a product index out of range), scene::ImageError for files it cannot write.
void writeSynthShowroom(const scene::SceneDescription& scene, const SynthOptions& options,
                        const std::filesystem::path& dir, const ReferenceProgress& progress = {});

}  // namespace penumbra::reference
