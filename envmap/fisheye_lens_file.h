// The environment camera's calibrated fisheye lens as a file (issue 16 item 1): OpenCV's
// fisheye model (cv::fisheye; fisheye_resampler.h) as `penumbra calibrate-fisheye` recovers
// it from chessboard photos (fisheye_calibration.h) and as the kiosk reads it
// ("environment": {"lens": "lens.json"}, kiosk_config.h). Plain C++: the board reads it
// without OpenCV.
//
//   {"format": "penumbra-fisheye-lens", "version": 1,
//    "image_size": [480, 480],                       the frames' size, pixels
//    "fx": 146.0, "fy": 146.0, "cx": 240.0, "cy": 240.0,
//    "k": [k1, k2, k3, k4],                          θ_d = θ (1 + k1 θ² + k2 θ⁴ + k3 θ⁶ + k4 θ⁸)
//    "rms_px": 0.05,                                 the fit's RMS reprojection error
//    "views": 13,                                    photos the fit used
//    "board": "9x6", "square": 0.025}                (optional: where it came from)
//
// cx, cy are in FisheyeLens's convention, the image's corner at (0, 0) and pixel (0, 0)'s
// centre at (0.5, 0.5): OpenCV's own principal point (pixel centres at integers, as its
// corner finder reports them) plus half a pixel. Numbers are written so they read back bit
// for bit (nlohmann's shortest round-trip form).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

#include "core/regular_file.h"
#include "envmap/fisheye_resampler.h"

namespace penumbra::envmap {

inline constexpr std::string_view kFisheyeLensFormat = "penumbra-fisheye-lens";
inline constexpr int64_t kFisheyeLensVersion = 1;
// A fit worse than this is not a calibration of this lens model (a wrong board size, a
// blurred set, a lens cv::fisheye cannot describe): `penumbra calibrate-fisheye` writes none
// and the reader refuses one. At f ≈ 150 px, 5 px is about 2° of direction.
inline constexpr double kMostFisheyeRmsPx = 5.0;
// The image sizes the kiosk's environment camera accepts (kiosk_config.h).
inline constexpr int64_t kMostFisheyeImageSide = 4096;

struct FisheyeLensFile {
  FisheyeLens lens;
  double rmsPx = 0;
  int64_t views = 0;
  std::string board;  // "COLSxROWS", or empty
  double square = 0;  // the board's square size, or 0
};

// Reads and checks a lens file: `file: field: problem` through `raise` for a file that is not
// JSON, another format or a newer version, a missing or unknown field, a size outside
// [2, 4096], a focal length that is not positive, a centre outside the image, a k beyond
// ±100, an rms_px that is negative or over kMostFisheyeRmsPx, fewer than 3 views.
FisheyeLensFile readFisheyeLensFile(const std::filesystem::path& path, core::ErrorThrower raise);

// The file's text (the format above, indented by 2, a final newline).
std::string fisheyeLensJson(const FisheyeLensFile& file);
// Writes it with core::writeFileReplacing (no partial file on any error; core::Error naming
// the file).
void writeFisheyeLensFile(const std::filesystem::path& path, const FisheyeLensFile& file);

// How far from the optical axis the lens sees in its worst direction, in radians: the angle θ
// whose image radius f·θ_d(θ) first reaches the nearest image edge (the shortest of cx/fx,
// (width − cx)/fx, cy/fy, (height − cy)/fy in θ_d units: the model is radial in normalised
// coordinates, so the nearest edge is met along an axis), or where θ_d(θ) stops increasing
// (beyond that fold the model sends two directions to one radius), at most π. The hemisphere
// map needs π/2 (Havran et al. 2005 §5.1: the whole upper hemisphere); the ideal
// equidistant180 lens reaches exactly that. Plain arithmetic (no OpenCV): the same model as
// cv::fisheye::projectPoints.
double nearestEdgeReach(const FisheyeLens& lens);

// `reach` is enough for the hemisphere map: at least π/2 less 1e-9 rad (the equidistant180
// lens's f = (size / 2) / (π / 2) gives π/2 only to an ulp).
bool reachesHemisphere(double reach);

}  // namespace penumbra::envmap
