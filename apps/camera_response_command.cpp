#include "apps/camera_response_command.h"

#ifdef PENUMBRA_HAVE_CAMERA_RESPONSE
#include <cstdio>
#include <memory>
#include <string>

#include "core/cli.h"
#include "kiosk/camera_response_file.h"
#include "lighting/camera_response.h"
#include "scene/photo_io.h"
#endif

namespace penumbra::apps {

#ifdef PENUMBRA_HAVE_CAMERA_RESPONSE
namespace {

constexpr const char* kChannel[3] = {"R", "G", "B"};

struct CameraResponseFlags {
  std::vector<std::string> shots;  // IMAGE:EXPOSURE_US
  std::string out;
  int samples = lighting::ResponseOptions{}.samplesPerChannel;
  double smoothness = lighting::ResponseOptions{}.smoothness;
};

// "dir/e250.png:250" → the image and its exposure time in µs (after the last ':', so that a
// path may hold one).
std::pair<std::string, int64_t> parseShot(const std::string& shot) {
  const size_t colon = shot.rfind(':');
  const std::string usage = shot + ": expected IMAGE:EXPOSURE_US, e.g. e250.png:250";
  if (colon == std::string::npos || colon == 0 || colon + 1 == shot.size())
    throw cli::UsageError(usage);
  const std::string us = shot.substr(colon + 1);
  size_t used = 0;
  long long value = 0;
  try {
    value = std::stoll(us, &used);
  } catch (const std::exception&) {
    throw cli::UsageError(usage);
  }
  if (used != us.size() || value < 1 || value > 1'000'000'000)
    throw cli::UsageError(shot +
                          ": the exposure must be a whole number of microseconds in [1, "
                          "1000000000]");
  return {shot.substr(0, colon), int64_t(value)};
}

int runCameraResponse(const CameraResponseFlags& f) {
  kiosk::CameraResponseCurves curves;
  for (const std::string& shot : f.shots) {
    const auto [image, us] = parseShot(shot);
    curves.bracket.push_back({image, us});
  }
  if (curves.bracket.size() < 2) throw cli::UsageError("need at least two IMAGE:EXPOSURE_US");
  std::vector<lighting::Exposure> bracket;
  for (const kiosk::CameraResponseCurves::Shot& shot : curves.bracket) {
    bracket.push_back(
        {shot.image, double(shot.exposureUs) * 1e-6, scene::readPhotoRgb8(shot.image)});
  }
  lighting::ResponseOptions options;
  options.samplesPerChannel = f.samples;
  options.smoothness = f.smoothness;
  const lighting::CameraResponse response = lighting::recoverResponse(bracket, options);
  curves.logExposure = response.logExposure;
  curves.warnings = response.warnings;
  kiosk::writeCameraResponse(f.out, curves);
  for (size_t c = 0; c < 3; ++c) {
    const auto& g = response.logExposure[c];
    std::printf("channel %s g(0) %.4f g(128) %.4f g(255) %.4f repaired_codes %d\n", kChannel[c],
                g[0], g[128], g[255], response.repairedCodes[c]);
  }
  for (const std::string& w : response.warnings) std::printf("warning %s\n", w.c_str());
  std::printf("wrote %s\n", f.out.c_str());
  return 0;
}

}  // namespace
#endif

std::vector<Command> addCameraResponseCommands([[maybe_unused]] CLI::App& app) {
  std::vector<Command> commands;
#ifdef PENUMBRA_HAVE_CAMERA_RESPONSE
  auto flags = std::make_shared<CameraResponseFlags>();
  CLI::App* cmd = app.add_subcommand(
      "camera-response",
      "An 8-bit bracket -> the camera's response file (Debevec & Malik 1997), for the "
      "environment camera's \"response\" (docs/kiosk.md)");
  cmd->add_option("SHOTS", flags->shots,
                  "IMAGE:EXPOSURE_US, two or more: one still scene at fixed gain and white "
                  "balance, each exposure time once")
      ->required();
  cmd->add_option("-o,--out", flags->out, "response file to write (.json)")->required();
  cmd->add_option("--samples", flags->samples, "pixels sampled per channel")
      ->check(cli::NumberRange(2, 2000))
      ->capture_default_str();
  cmd->add_option("--smoothness", flags->smoothness, "lambda of the smoothness term")
      ->check(cli::NumberRange(1e-3, 1e6))
      ->capture_default_str();
  commands.push_back({cmd, [flags] { return runCameraResponse(*flags); }});
#endif
  return commands;
}

}  // namespace penumbra::apps
