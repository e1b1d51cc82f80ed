#include "firmware-sim/sim_run.h"

#include "core/regular_file.h"
#include "kiosk/product_files.h"
#include "scene/bundle_io.h"
#include "simd/targets.h"
#ifdef PENUMBRA_HAVE_FOOTAGE
#include "firmware-sim/footage.h"
#include "firmware-sim/virtual_environment_camera.h"
#endif

#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <limits>

namespace penumbra::firmware_sim {

SimTimebase::SimTimebase(shadow::CostModel model, std::vector<Overrun> overruns)
    : model_(std::move(model)), overruns_(std::move(overruns)) {}

void SimTimebase::sleepUntil(int64_t ns) {
  const int64_t now = clock_.nowNanoseconds();
  if (ns > now) clock_.advance(ns - now);
}

void SimTimebase::charge(const kiosk::FrameWork& w) {
  int64_t ns = model_.frameNs(w.startNs, w.work);
  for (const Overrun& o : overruns_) {
    if (o.frame == w.frame) ns += o.extraNs;
  }
  clock_.advance(ns);
}

namespace {

// The start-up faults of a session: a corrupted copy of the bundle (bytes flipped in the
// middle, as a failing SD card would), written next to the system's temporary files.
std::filesystem::path corruptedCopy(const std::filesystem::path& bundle) {
  std::vector<uint8_t> bytes = core::readRegularFile(bundle, scene::kMaxBundleBytes,
                                                     "a scene bundle", core::throwAs<SessionError>);
  for (size_t i = bytes.size() / 2; i < bytes.size() && i < bytes.size() / 2 + 64; ++i) {
    bytes[i] = static_cast<uint8_t>(bytes[i] ^ 0x5A);
  }
  std::filesystem::path out = std::filesystem::temp_directory_path() /
                              ("penumbra-sim-corrupt-" + std::to_string(::getpid()) + ".bundle");
  std::ofstream o(out, std::ios::binary);
  o.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!o) throw SessionError(out.string() + ": cannot write the corrupted bundle copy");
  return out;
}

}  // namespace

SimOptions bestTargetOneThread() {
  SimOptions o;
  o.render.isa = simd::bestIsa();
  o.render.threads = 1;
  return o;
}

SimRun::SimRun(const Session& s, const SimOptions& options)
    : log_(options.logEcho), time_(shadow::CostModel(s.cost, s.loadSteps), s.overruns) {
  if (s.corruptBundle) {
    // The configured bundle is corrupt; the session's bundle plays the last good one.
    const std::filesystem::path bad = corruptedCopy(s.bundle);
    try {
      bundle_ = std::make_unique<kiosk::GuardedBundle>(
          kiosk::loadBundleKeepingLastGood(bad, s.bundle, log_, 0));
    } catch (...) {
      std::filesystem::remove(bad);
      throw;
    }
    std::filesystem::remove(bad);
  } else {
    bundle_ = std::make_unique<kiosk::GuardedBundle>(
        kiosk::loadBundleKeepingLastGood(s.bundle, s.lastGood, log_, 0));
  }
  if (!s.corruptProduct.empty()) {
    bool found = false;
    for (shadow::ProductModel& p : bundle_->bundle.products) {
      if (p.name == s.corruptProduct && !p.mesh.positions.empty()) {
        p.mesh.positions[p.mesh.positions.size() / 2].y = std::numeric_limits<float>::quiet_NaN();
        found = true;
      }
    }
    if (!found) {
      throw SessionError(s.file.string() + ": startup.corrupt_product: no product named '" +
                         s.corruptProduct + "' in " + s.bundle.string());
    }
  }
  // Product files at start-up replace the bundle's models before the carousel is built;
  // a refused one keeps the bundle's model (the last good one) and is said on the HUD.
  std::vector<std::pair<std::string, std::string>> refused;
  for (const ScriptedProductFile& f : s.productFiles) {
    const auto& products = bundle_->bundle.products;
    if (std::none_of(products.begin(), products.end(),
                     [&](const shadow::ProductModel& p) { return p.name == f.product; })) {
      throw SessionError(s.file.string() + ": product_files: no product named '" + f.product +
                         "' in " + s.bundle.string());
    }
  }
  for (const ScriptedProductFile& f : s.productFiles) {
    if (f.atNs > 0) {
      pendingProductFiles_.push_back(f);
      continue;
    }
    const std::string why = kiosk::swapProductFile(bundle_->bundle, {f.product, f.file}, log_, 0);
    if (!why.empty()) refused.emplace_back(f.product, why);
  }
  const shadow::SceneBundle& b = bundle_->bundle;
  kiosk::Peripherals io;
  io.led = &led_;
  io.time = &time_;
  io.log = &log_;
  if (s.cameraPresent && !s.cameraSource.empty()) {
#ifdef PENUMBRA_HAVE_FOOTAGE
    try {
      camera_ =
          std::make_unique<VirtualCamera>(loadFootage(s.cameraSource, b.view.width, b.view.height),
                                          b.view.width, b.view.height, s.camera);
    } catch (const FootageError& e) {
      throw SessionError(s.file.string() + ": camera.source: " + e.what());
    }
#else
    throw SessionError(s.file.string() +
                       ": camera.source: footage needs a build with OpenCV "
                       "(PENUMBRA_WITH_OPENCV)");
#endif
    io.camera = camera_.get();
  } else if (s.cameraPresent) {
    camera_ = std::make_unique<VirtualCamera>(b.background, b.view.width, b.view.height, s.camera);
    io.camera = camera_.get();
  } else {
    log_.write(0, kiosk::LogLevel::kWarning, "camera: none found (simulated: absent)");
  }
  if (s.environment) {
#ifdef PENUMBRA_HAVE_FOOTAGE
    try {
      environment_ = std::make_unique<VirtualEnvironmentCamera>(
          loadExrSequence(s.environment->frames), s.environment->frames.filename().string(),
          s.environment->periodNs, s.environment->stopAtNs);
    } catch (const std::exception& e) {
      throw SessionError(s.file.string() + ": environment.frames: " + e.what());
    }
    io.environment = environment_.get();
#else
    throw SessionError(s.file.string() +
                       ": environment: the fisheye camera needs a build with OpenCV "
                       "(PENUMBRA_WITH_OPENCV)");
#endif
  }
  try {
    if (!s.gpioPresent) throw GpioUnavailable("/dev/gpiochip0: no such GPIO chip (simulated)");
    gpio_ = std::make_unique<VirtualGpio>(s.presses);
    io.buttons = gpio_.get();
  } catch (const GpioUnavailable& e) {
    log_.write(0, kiosk::LogLevel::kWarning, std::string("gpio: ") + e.what());
  }
  loop_ = std::make_unique<kiosk::KioskLoop>(b, s.kiosk, io, options.render);
  for (const auto& [product, why] : refused)
    loop_->setFault(product, kiosk::productFileFault(product));
}

kiosk::FrameReport SimRun::step() {
  // Hot-swaps: the file lands between two frames; a refused one changes nothing on screen.
  const int64_t now = time_.nowNanoseconds();
  while (!pendingProductFiles_.empty() && pendingProductFiles_.front().atNs <= now) {
    const ScriptedProductFile f = pendingProductFiles_.front();
    pendingProductFiles_.erase(pendingProductFiles_.begin());
    const std::string why = kiosk::swapProductFile(bundle_->bundle, {f.product, f.file}, log_, now);
    loop_->setFault(f.product, why.empty() ? std::string() : kiosk::productFileFault(f.product));
    if (why.empty()) {
      for (uint32_t i = 0; i < bundle_->bundle.products.size(); ++i) {
        if (bundle_->bundle.products[i].name == f.product) loop_->productReplaced(i);
      }
    }
  }
  kiosk::FrameReport report = loop_->step();
  if (camera_) {
    // The virtual camera rendered inside the kiosk's camera stage: take it out of the board.
    const int64_t rendering = camera_->takeRenderNs();
    report.stages[shadow::FrameStage::kCamera] -= rendering;
    report.stages[shadow::FrameStage::kSimulatorCamera] = rendering;
  }
  kiosk::noteFrameRendered(*bundle_, log_, time_.nowNanoseconds());
  return report;
}

SimRun::~SimRun() = default;

}  // namespace penumbra::firmware_sim
