// A capture with a known answer (issue 4 item 8's closed loop): a scene file's room is the
// truth; its light is solved to convergence (lighting/patch_radiosity.h); a known camera
// photographs it at several exposures through a known response (8-bit PNG brackets); a
// lat-long probe is ray-cast from a point (lighting/light_probe.h renderProbe, EXR);
// vanishing-point marks are room lines projected through the true camera; a manifest
// (docs/capture.md) ties them together. `penumbra capture` on that manifest must give the
// camera, the response, the reflectances and the emitters back.
//
// Offline (libm). Part of penumbra_capture; used by lighting/capture_test.cpp and the
// `penumbra-capture-synth` generator (apps/capture_synth_main.cpp).
#pragma once

#include <filesystem>
#include <vector>

#include <glm/glm.hpp>

#include "scene/camera_intrinsics.h"
#include "scene/patch_mesh.h"

namespace penumbra::lighting {

struct SyntheticCaptureOptions {
  // The kiosk camera's response: code = 255 (gain_c * L * dt)^(1 / gamma) + noise, rounded,
  // clipped to 0..255.
  glm::dvec3 gains{1.0, 0.8, 1.2};
  double gamma = 2.2;
  double noiseCodes = 1.0;  // uniform sensor noise, this many codes peak to peak
  std::vector<double> seconds{1.0 / 16, 1.0 / 8, 1.0 / 4, 1.0 / 2, 1.0, 2.0, 4.0};  // 1 stop apart
  int liveIndex = 4;
  glm::dvec3 probePosition{3.0, 1.3, 2.5};
  double probeYawDegrees = 20;
  int probeWidth = 1024;        // lat-long, width x width / 2
  int bounces = 30;             // gathering steps of the truth (rho <= 0.8: 0.8^30 ~ 1e-3)
  double markRoundingPx = 0.1;  // vanishing marks rounded to this (a user's clicks)
  // Principal point offset from the image centre (pixels). Vanishing points assume it is 0,
  // so a non-zero offset wants `chessboard`.
  glm::dvec2 principalOffsetPx{0.0};
  // Calibrate from chessboard photos (chess-N.png, 9 x 6 inner corners, 10 cm squares, nine
  // poses) and room-corner marks (corners.json) instead of vanishing marks.
  bool chessboard = false;
};

struct SyntheticCapture {
  std::filesystem::path manifest;
  scene::Intrinsics intrinsics;  // the true camera
  scene::Pose pose;
  scene::PatchMesh mesh;             // the scene file's patch mesh (its materials: the truth)
  std::vector<glm::dvec3> radiance;  // per patch, the truth the photos and probe show
  glm::dvec3 probeScale{1.0};        // probe units -> merged photo units (g(128) = 0)
};

// Writes bracket-N.png, probe.exr, marks.json (or chess-N.png and corners.json) and
// capture.json into `dir` (created). The camera is the scene file's view, square pixels,
// principal point at the centre plus options.principalOffsetPx. Throws
// std::runtime_error when a marked line is not in view.
SyntheticCapture writeSyntheticCapture(const std::filesystem::path& scenePath,
                                       const std::filesystem::path& dir,
                                       const SyntheticCaptureOptions& options = {});

}  // namespace penumbra::lighting
