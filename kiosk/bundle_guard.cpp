#include "kiosk/bundle_guard.h"

#include <system_error>

#include "kiosk/kiosk_loop.h"

namespace penumbra::kiosk {
namespace {

// Loads and checks that at least one product can be shown; throws with the reason.
shadow::SceneBundle loadUsable(const std::filesystem::path& path) {
  shadow::SceneBundle b = shadow::loadBundle(path);
  std::vector<std::string> why;
  if (validateProducts(b, why).empty()) {
    std::string all;
    for (const std::string& w : why) all += (all.empty() ? "" : "; ") + w;
    throw std::runtime_error(path.string() + ": no usable product (" + all + ")");
  }
  return b;
}

}  // namespace

GuardedBundle loadBundleKeepingLastGood(const std::filesystem::path& configured,
                                        const std::filesystem::path& lastGood, KioskLog& log,
                                        int64_t nowNs) {
  GuardedBundle out;
  try {
    out.bundle = loadUsable(configured);
    out.loadedFrom = configured;
    log.write(nowNs, LogLevel::kInfo, "bundle: " + configured.string());
    std::error_code ec;
    if (!lastGood.empty() && !std::filesystem::equivalent(configured, lastGood, ec)) {
      const std::filesystem::path tmp = lastGood.string() + ".tmp";
      std::filesystem::copy_file(configured, tmp, std::filesystem::copy_options::overwrite_existing,
                                 ec);
      if (!ec) std::filesystem::rename(tmp, lastGood, ec);
      if (ec) {
        log.write(nowNs, LogLevel::kWarning,
                  "bundle: could not keep a last good copy at " + lastGood.string() + ": " +
                      ec.message());
      }
    }
    return out;
  } catch (const std::exception& e) {
    out.refusal = e.what();
  }
  log.write(nowNs, LogLevel::kError, "bundle: refused " + configured.string() + ": " + out.refusal);
  if (lastGood.empty()) {
    throw NoUsableBundle("no usable scene bundle: " + out.refusal +
                         " (and no last good bundle is configured)");
  }
  try {
    out.bundle = loadUsable(lastGood);
  } catch (const std::exception& e) {
    throw NoUsableBundle("no usable scene bundle: " + out.refusal + "; last good bundle " +
                         lastGood.string() + " refused too: " + e.what());
  }
  out.loadedFrom = lastGood;
  out.fellBack = true;
  log.write(nowNs, LogLevel::kWarning,
            "bundle: running on the last good bundle " + lastGood.string());
  return out;
}

}  // namespace penumbra::kiosk
