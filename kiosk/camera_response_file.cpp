#include "kiosk/camera_response_file.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/json_reader.h"

namespace penumbra::kiosk {
namespace {

constexpr const char* kChannelKey[3] = {"r", "g", "b"};
constexpr const char* kChannelName[3] = {"R", "G", "B"};

// A JSON string literal (quotes and escapes by nlohmann).
std::string quoted(const std::string& s) {
  return nlohmann::json(s).dump();
}

}  // namespace

std::string checkLogExposure(const std::array<std::array<double, 256>, 3>& g) {
  for (size_t c = 0; c < 3; ++c) {
    const std::string channel = std::string("channel ") + kChannelName[c];
    for (size_t z = 0; z < 256; ++z) {
      const double v = g[c][z];
      if (!std::isfinite(v)) return channel + ": g(" + std::to_string(z) + ") is not finite";
      if (std::abs(v) > kMostLogExposure) {
        return channel + ": g(" + std::to_string(z) + ") = " + core::formatNumber(v) +
               " is beyond ±" + core::formatNumber(kMostLogExposure);
      }
      if (z > 0 && v < g[c][z - 1]) {
        return channel + ": g(" + std::to_string(z) + ") = " + core::formatNumber(v) +
               " is below g(" + std::to_string(z - 1) + ") = " + core::formatNumber(g[c][z - 1]) +
               " (a response must not decrease)";
      }
    }
    if (!(g[c][255] > g[c][0])) return channel + ": g is flat (it records no change of light)";
  }
  return {};
}

void writeCameraResponse(const std::filesystem::path& path, const CameraResponseCurves& curves) {
  if (const std::string why = checkLogExposure(curves.logExposure); !why.empty()) {
    throw core::Error(path.string(), "", why);
  }
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw core::Error(path.string(), "", "cannot be written");
  out << "{\"format\": " << quoted(std::string(kCameraResponseFormat))
      << ", \"version\": " << kCameraResponseVersion << ",\n \"log_exposure\": {";
  for (size_t c = 0; c < 3; ++c) {
    out << (c ? ",\n  " : "\n  ") << quoted(kChannelKey[c]) << ": [";
    for (size_t z = 0; z < 256; ++z) {
      out << (z == 0 ? "" : (z % 8 == 0 ? ",\n   " : ", "))
          << core::formatNumber(curves.logExposure[c][z]);
    }
    out << "]";
  }
  out << "},\n \"bracket\": [";
  for (size_t i = 0; i < curves.bracket.size(); ++i) {
    out << (i ? ", " : "") << "{\"image\": " << quoted(curves.bracket[i].image)
        << ", \"exposure_us\": " << curves.bracket[i].exposureUs << "}";
  }
  out << "],\n \"warnings\": [";
  for (size_t i = 0; i < curves.warnings.size(); ++i) {
    out << (i ? ", " : "") << quoted(curves.warnings[i]);
  }
  out << "]}\n";
  out.close();
  if (!out) throw core::Error(path.string(), "", "write failed");
}

CameraResponseCurves readCameraResponse(const std::filesystem::path& path,
                                        core::ErrorThrower raise) {
  const core::JsonDocument doc(path, raise);
  const core::JsonValue j =
      doc.root().object({"format", "version", "log_exposure", "bracket", "warnings"});
  if (j["format"].string() != kCameraResponseFormat) {
    j["format"].fail("expected \"" + std::string(kCameraResponseFormat) +
                     "\" (a file written by `penumbra camera-response`), got \"" +
                     j["format"].string() + "\"");
  }
  j["version"].integer(kCameraResponseVersion, kCameraResponseVersion);
  CameraResponseCurves curves;
  const core::JsonValue g = j["log_exposure"].object({"r", "g", "b"});
  for (size_t c = 0; c < 3; ++c) {
    const std::vector<double> values = g[kChannelKey[c]].numbers(256);
    std::copy(values.begin(), values.end(), curves.logExposure[c].begin());
  }
  if (const std::string why = checkLogExposure(curves.logExposure); !why.empty()) {
    g.fail(why);
  }
  for (const core::JsonValue& shot : j.optionalArray("bracket")) {
    shot.object({"image", "exposure_us"});
    curves.bracket.push_back({shot["image"].string(), shot["exposure_us"].integer(1, INT64_MAX)});
  }
  for (const core::JsonValue& w : j.optionalArray("warnings"))
    curves.warnings.push_back(w.string());
  return curves;
}

}  // namespace penumbra::kiosk
