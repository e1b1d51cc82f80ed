// `penumbra capture`: photographs of a real room + calibration marks + the room JSON + a
// light probe -> a scene bundle (issue 4 item 8; Gibson & Chalmers 2003 §3-4, the ARIS
// pipeline). docs/capture.md documents the manifest and every stage.
//
//   calibration  vanishing-point marks (§3, eq. 1) or chessboard photos, optionally room
//                corners for the pose -> scene::Camera (an off-centre principal point
//                becomes an off-axis frustum; lens distortion is reported, not modelled)
//   response     the bracket -> g() per channel (Debevec & Malik); channels brought to one
//                grey scale so a single T() reproduces the photograph
//   HDR          the bracket merged to radiance (hat weights, clipped codes ignored)
//   probe        EXR -> per-patch radiance and materials (§4.2), its units tied to the
//                photograph's by a per-channel scale fitted on the patches both see
//   precompute   lighting/precompute.h with the measured materials and radiance, the
//                calibrated camera, T() at the live exposure and the live photograph as
//                the background
//
// Offline only (libm, OpenCV through penumbra_calibration for photos and chessboards; no
// OpenCV type here). Library: penumbra_capture (needs Embree, OpenCV and OpenEXR).
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "core/error.h"
#include "lighting/camera_response.h"
#include "lighting/light_probe.h"
#include "lighting/precompute.h"
#include "scene/camera_intrinsics.h"
#include "shadow/scene_bundle.h"

namespace penumbra::lighting {

// Bad manifest or inconsistent inputs: the message starts with "FILE: field: ".
class CaptureError : public core::Error {
 public:
  using core::Error::Error;
};

struct CaptureManifest {
  std::filesystem::path source;  // the manifest file (relative paths resolve against it)
  std::filesystem::path scene;   // room geometry, products, patch size

  // Calibration: vanishing marks (intrinsics and pose) or chessboard photos (intrinsics);
  // `corners` (room-corner marks) fits the pose instead and is required with chessboards.
  std::filesystem::path vanishingMarks;
  glm::dvec3 vanishingOriginWorld{0.0};  // room coordinates of the marked origin
  std::vector<std::filesystem::path> chessboardPhotos;
  int chessboardCols = 0, chessboardRows = 0;
  double chessboardSquare = 1.0;
  std::filesystem::path corners;

  struct Photo {
    std::filesystem::path file;
    double seconds = 0;
  };
  std::vector<Photo> exposures;       // the bracket from the kiosk camera
  std::optional<int> liveIndex;       // the kiosk's live exposure: one of the bracket...
  std::optional<double> liveSeconds;  // ...or a time (background synthesised through T())

  std::filesystem::path probeImage;  // EXR
  ProbeMapping probeMapping = ProbeMapping::LatLong;
  double probeFisheyeFovDegrees = 180;
  glm::dvec3 probePosition{0.0};
  double probeYawDegrees = 0, probePitchDegrees = 0;  // probe frame -> room: Ry(yaw) Rx(pitch)
  float probeSaturation = 0;                          // <= 0: no saturation check
  std::optional<glm::dvec3> probeScale;               // probe units -> photo units; empty: fit
};

// Strict reading (unknown or missing fields, wrong types, bad values are errors naming the
// file and the field); relative paths are made absolute against the manifest's folder.
CaptureManifest loadCaptureManifest(const std::filesystem::path& path);

struct CaptureSummary {
  // Camera.
  std::string calibrationMethod;  // "vanishing points", "chessboard", "+ room corners"
  scene::Intrinsics intrinsics;
  scene::Pose pose;
  double reprojectionErrorPx = 0;  // RMS of the marks that gave the pose
  double intrinsicsErrorPx = 0;    // RMS of the intrinsics' fit (chessboard corners) or the same
  // |principal point - image centre|; modelled by an off-axis frustum (Camera::principalNdc).
  double principalOffsetPx = 0;
  // Light.
  double dynamicRangeStops = 0;  // merged HDR max / min over unclipped values, log2
  size_t clippedBright = 0, clippedDark = 0;
  CameraResponse response;  // g per channel, g(128) = 0 (Debevec & Malik)
  double liveSeconds = 0;
  glm::dvec3 channelToGrey{1.0};  // per-channel factor applied to the merged radiance
  glm::dvec3 probeScale{1.0};     // probe radiance x this = photo radiance
  size_t scalePatches = 0;        // patches the fit used (seen by camera and probe)
  double scaleSpread = 0;         // interquartile range of the luminance ratios / median
  size_t probeSeenPatches = 0, probeEmitters = 0;
  // Bundle.
  size_t patches = 0, sources = 0, receivers = 0;
  std::vector<std::string> warnings;  // probe, response and camera warnings
  std::vector<StageTiming> timings;   // every stage, precompute's included
};

// Called at the start of each stage (capture's own and precompute's).
using CaptureProgress = std::function<void(const std::string& stage, int index, int count)>;

struct CaptureResult {
  shadow::SceneBundle bundle;
  CaptureSummary summary;
};

// Runs the whole pipeline. `options` passes threads, seed and the like to precompute (its
// measured fields, tone and background are filled here). Throws CaptureError,
// scene::CalibrationError, HdrError or SceneFileError naming the file and the problem.
CaptureResult runCapture(const CaptureManifest& manifest, PrecomputeOptions options = {},
                         const CaptureProgress& progress = {});

}  // namespace penumbra::lighting
