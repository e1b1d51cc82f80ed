#include "kiosk/bundle_guard.h"

#include <fstream>
#include <sstream>
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

std::filesystem::path trialMarkOf(const std::filesystem::path& lastGood) {
  return lastGood.string() + ".trial";
}

// Which file a trial is of: its path, size and modification time, so that a bundle
// replaced at the same path (the technician's fix) is tried afresh. Empty when the file
// cannot be examined (loading it will say why).
std::string identityOf(const std::filesystem::path& bundle) {
  std::error_code ec;
  const uintmax_t size = std::filesystem::file_size(bundle, ec);
  if (ec) return {};
  const auto modified = std::filesystem::last_write_time(bundle, ec);
  if (ec) return {};
  std::ostringstream id;
  id << bundle.string() << "\n" << size << "\n" << modified.time_since_epoch().count() << "\n";
  return id.str();
}

// The identity in a trial mark; empty when there is none. A mark is a few hundred bytes;
// anything longer is not ours and is read only that far.
std::string readTrialMark(const std::filesystem::path& mark) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(mark, ec)) return {};
  std::ifstream in(mark, std::ios::binary);
  std::string text(4096, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<size_t>(in.gcount()));
  return text;
}

void writeTrialMark(const std::filesystem::path& mark, const std::string& identity, KioskLog& log,
                    int64_t nowNs) {
  std::ofstream out(mark, std::ios::binary | std::ios::trunc);
  out << identity;
  out.close();
  if (!out) {
    log.write(nowNs, LogLevel::kWarning,
              "bundle: cannot write the trial mark " + mark.string() +
                  " (a crash of this bundle will not be recognised at the next start)");
  }
}

}  // namespace

GuardedBundle loadBundleKeepingLastGood(const std::filesystem::path& configured,
                                        const std::filesystem::path& lastGood, KioskLog& log,
                                        int64_t nowNs) {
  GuardedBundle out;
  std::error_code ec;
  const bool isLastGood = lastGood.empty() || std::filesystem::equivalent(configured, lastGood, ec);
  try {
    const std::string identity = identityOf(configured);
    if (!isLastGood && !identity.empty() && readTrialMark(trialMarkOf(lastGood)) == identity) {
      throw std::runtime_error(configured.string() +
                               ": the last run stopped before it had rendered " +
                               std::to_string(kFramesBeforeLastGood) +
                               " frames with this bundle (a crash or a render error)");
    }
    out.bundle = loadUsable(configured);
    out.loadedFrom = configured;
    if (!isLastGood) {
      out.keepAs = lastGood;
      writeTrialMark(trialMarkOf(lastGood), identity, log, nowNs);
    }
    log.write(nowNs, LogLevel::kInfo, "bundle: " + configured.string());
    return out;
  } catch (const std::exception& e) {
    out.refusal = e.what();
  }
  if (lastGood.empty()) {
    log.write(nowNs, LogLevel::kError,
              "bundle: refused " + configured.string() + ": " + out.refusal);
    throw NoUsableBundle("no usable scene bundle: " + out.refusal +
                         " (and no last good bundle is configured)");
  }
  try {
    out.bundle = loadUsable(lastGood);
  } catch (const std::exception& e) {
    log.write(nowNs, LogLevel::kError,
              "bundle: refused " + configured.string() + ": " + out.refusal);
    throw NoUsableBundle("no usable scene bundle: " + out.refusal + "; last good bundle " +
                         lastGood.string() + " refused too: " + e.what());
  }
  out.loadedFrom = lastGood;
  out.fellBack = true;
  // One line says what happened and what the kiosk does about it.
  log.write(nowNs, LogLevel::kError,
            "bundle: refused " + configured.string() + ": " + out.refusal +
                "; running on the last good bundle " + lastGood.string());
  return out;
}

void noteFrameRendered(GuardedBundle& guarded, KioskLog& log, int64_t nowNs) {
  if (guarded.kept || guarded.keepAs.empty()) return;
  if (++guarded.framesRendered < kFramesBeforeLastGood) return;
  guarded.kept = true;
  const std::filesystem::path& lastGood = guarded.keepAs;
  // The trial has passed whether or not the copy below succeeds.
  std::error_code ec;
  std::filesystem::remove(trialMarkOf(lastGood), ec);
  const std::filesystem::path tmp = lastGood.string() + ".tmp";
  std::filesystem::copy_file(guarded.loadedFrom, tmp,
                             std::filesystem::copy_options::overwrite_existing, ec);
  if (!ec) std::filesystem::rename(tmp, lastGood, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);  // no half-written copy left beside the last good one
    log.write(
        nowNs, LogLevel::kWarning,
        "bundle: could not keep a last good copy at " + lastGood.string() + ": " + ec.message());
    return;
  }
  log.write(nowNs, LogLevel::kInfo,
            "bundle: " + guarded.loadedFrom.string() + " rendered " +
                std::to_string(kFramesBeforeLastGood) + " frames; kept as the last good bundle " +
                lastGood.string());
}

}  // namespace penumbra::kiosk
