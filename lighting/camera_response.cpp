#include "lighting/camera_response.h"

#include <algorithm>
#include <cmath>

namespace penumbra::lighting {
namespace {

constexpr const char* kChannel[3] = {"R", "G", "B"};

// SplitMix64 (Steele, Lea & Flood 2014): a counter-based hash, so sample k is the same
// whatever else is sampled.
uint64_t mix(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// Dense symmetric positive-definite solve A x = b by Cholesky (A = L L^T), in place, in a
// fixed loop order. n is a few hundred, so O(n^3 / 6) is milliseconds.
std::vector<double> choleskySolve(std::vector<double>& a, std::vector<double> b, size_t n) {
  for (size_t j = 0; j < n; ++j) {
    double d = a[j * n + j];
    for (size_t k = 0; k < j; ++k) d -= a[j * n + k] * a[j * n + k];
    if (!(d > 0)) throw HdrError("camera response: the least-squares system is singular");
    const double ljj = std::sqrt(d);
    a[j * n + j] = ljj;
    for (size_t i = j + 1; i < n; ++i) {
      double s = a[i * n + j];
      const double* ri = &a[i * n];
      const double* rj = &a[j * n];
      for (size_t k = 0; k < j; ++k) s -= ri[k] * rj[k];
      a[i * n + j] = s / ljj;
    }
  }
  for (size_t i = 0; i < n; ++i) {  // L y = b
    double s = b[i];
    for (size_t k = 0; k < i; ++k) s -= a[i * n + k] * b[k];
    b[i] = s / a[i * n + i];
  }
  for (size_t i = n; i-- > 0;) {  // L^T x = y
    double s = b[i];
    for (size_t k = i + 1; k < n; ++k) s -= a[k * n + i] * b[k];
    b[i] = s / a[i * n + i];
  }
  return b;
}

// Sample pixels for one channel: candidates from a seeded hash, stratified into 32 bins of
// the code in the middle exposure so dark and bright codes are represented (Debevec &
// Malik §2.1 pick pixels "with a reasonably even distribution of pixel values"). Pixels
// clipped in every exposure are skipped: their ln E would be unconstrained.
std::vector<size_t> choosePixels(std::span<const Exposure> bracket, int channel,
                                 const ResponseOptions& opt) {
  const size_t pixels = size_t(bracket[0].image.width) * size_t(bracket[0].image.height);
  const size_t want = std::min(size_t(opt.samplesPerChannel), pixels);
  const core::Image8& middle = bracket[bracket.size() / 2].image;
  const size_t perBin = want / 32 + 1;
  std::array<size_t, 32> filled{};
  std::vector<size_t> chosen;
  std::vector<uint8_t> taken(pixels, 0);
  const uint64_t salt = mix(opt.seed ^ (uint64_t(channel + 1) << 56));
  // Two passes: first respect the per-bin quota, then fill up from whatever remains.
  for (int pass = 0; pass < 2 && chosen.size() < want; ++pass) {
    for (uint64_t k = 0; k < 64 * want && chosen.size() < want; ++k) {
      const size_t p = size_t(mix(salt + k) % pixels);
      if (taken[p]) continue;
      bool informative = false;
      for (const Exposure& e : bracket)
        informative |= hatWeight(e.image.pixels[3 * p + channel]) > 0;
      if (!informative) continue;
      const size_t bin = middle.pixels[3 * p + channel] / 8u;
      if (pass == 0 && filled[bin] >= perBin) continue;
      ++filled[bin];
      taken[p] = 1;
      chosen.push_back(p);
    }
  }
  return chosen;
}

}  // namespace

void checkBracket(std::span<const Exposure> bracket) {
  if (bracket.size() < 2) {
    throw HdrError("HDR bracket: " + std::to_string(bracket.size()) +
                   " exposure(s), need at least 2");
  }
  const core::Image8& first = bracket[0].image;
  for (size_t i = 0; i < bracket.size(); ++i) {
    const Exposure& e = bracket[i];
    const std::string name = e.name.empty() ? "exposure " + std::to_string(i) : e.name;
    if (e.image.width <= 0 || e.image.height <= 0) throw HdrError(name + ": empty image");
    if (e.image.channels != 3 || !e.image.hasExpectedSize()) {
      throw HdrError(name + ": pixel data is not 3 bytes x width x height");
    }
    if (e.image.width != first.width || e.image.height != first.height) {
      throw HdrError(name + ": size " + std::to_string(e.image.width) + "x" +
                     std::to_string(e.image.height) + " differs from the first exposure's " +
                     std::to_string(first.width) + "x" + std::to_string(first.height));
    }
    if (!(e.seconds > 0) || !std::isfinite(e.seconds)) {
      throw HdrError(name + ": exposure time must be positive and finite");
    }
    for (size_t j = 0; j < i; ++j) {
      if (bracket[j].seconds == e.seconds) {
        throw HdrError(
            name + ": duplicate exposure time " + std::to_string(e.seconds) + " s (also " +
            (bracket[j].name.empty() ? "exposure " + std::to_string(j) : bracket[j].name) + ")");
      }
    }
  }
}

std::vector<ToneSample> CameraResponse::toneSamples(int channel) const {
  std::vector<ToneSample> out(256);
  for (int z = 0; z < 256; ++z) out[z] = {radiance(channel, z), double(z)};
  return out;
}

std::vector<ToneSample> CameraResponse::greyToneSamples() const {
  std::vector<ToneSample> out(256);
  for (int z = 0; z < 256; ++z) {
    const double g = (logExposure[0][z] + logExposure[1][z] + logExposure[2][z]) / 3.0;
    out[z] = {std::exp(g), double(z)};
  }
  return out;
}

double CameraResponse::radiance(int channel, int z) const {
  return std::exp(logExposure[channel][z]);
}

CameraResponse recoverResponse(std::span<const Exposure> bracket, const ResponseOptions& opt) {
  checkBracket(bracket);
  // The normal matrix is dense (256 + samples)^2 doubles: 2,000 samples take 42 MB.
  if (opt.samplesPerChannel < 2 || opt.samplesPerChannel > 2000 || !(opt.smoothness > 0)) {
    throw HdrError("camera response: need 2..2000 samples per channel and a positive smoothness");
  }
  std::vector<double> logDt(bracket.size());
  for (size_t j = 0; j < bracket.size(); ++j) logDt[j] = std::log(bracket[j].seconds);

  CameraResponse out;
  for (int c = 0; c < 3; ++c) {
    const std::vector<size_t> pixels = choosePixels(bracket, c, opt);
    // Debevec & Malik need N (P - 1) > Zmax - Zmin for an overdetermined system.
    if (pixels.size() * (bracket.size() - 1) < 64) {
      throw HdrError(std::string("camera response: channel ") + kChannel[c] + " has only " +
                     std::to_string(pixels.size()) +
                     " pixels that are not clipped in every exposure");
    }
    // Unknowns: g(0..255), then ln E_i per sample. Normal equations accumulated row by row.
    const size_t n = 256 + pixels.size();
    std::vector<double> ata(n * n, 0.0), atb(n, 0.0);
    auto addRow = [&](std::initializer_list<std::pair<size_t, double>> row, double rhs) {
      for (const auto& [i, vi] : row) {
        atb[i] += vi * rhs;
        for (const auto& [k, vk] : row) ata[i * n + k] += vi * vk;
      }
    };
    for (size_t s = 0; s < pixels.size(); ++s) {
      for (size_t j = 0; j < bracket.size(); ++j) {
        const int z = bracket[j].image.pixels[3 * pixels[s] + c];
        const double w = hatWeight(z);
        if (w == 0) continue;
        addRow({{size_t(z), w}, {256 + s, -w}}, w * logDt[j]);
      }
    }
    addRow({{128, 1.0}}, 0.0);  // fixes the free constant: g(128) = 0
    for (int z = 1; z < 255; ++z) {
      const double w = opt.smoothness * hatWeight(z);
      addRow({{size_t(z - 1), w}, {size_t(z), -2 * w}, {size_t(z + 1), w}}, 0.0);
    }
    const std::vector<double> x = choleskySolve(ata, atb, n);
    std::array<double, 256>& g = out.logExposure[c];
    // The anchor row is one equation among thousands, so g(128) comes out near 0, not at
    // it; shifting the whole curve is exact (only differences of g carry information).
    for (int z = 0; z < 256; ++z) g[z] = x[z] - x[128];

    // T() must be monotone (the intensity transfers telescope only then, shadow/
    // intensity_transfer.h). Repair small violations by the running maximum.
    int repaired = 0, first = -1;
    for (int z = 1; z < 256; ++z) {
      if (g[z] < g[z - 1]) {
        g[z] = g[z - 1];
        ++repaired;
        if (first < 0) first = z;
      }
    }
    out.repairedCodes[c] = repaired;
    if (repaired > 0) {
      const std::string what = std::string("channel ") + kChannel[c] +
                               ": response not monotone at " + std::to_string(repaired) +
                               " code(s), first at " + std::to_string(first);
      if (repaired > opt.maxRepairedFraction * 256) {
        throw HdrError("camera response: " + what +
                       "; too many to repair (check exposure times and their order)");
      }
      out.warnings.push_back(what + "; flattened to the running maximum");
    }
  }
  return out;
}

}  // namespace penumbra::lighting
