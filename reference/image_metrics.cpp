#include "reference/image_metrics.h"

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/quality/qualityssim.hpp>

namespace penumbra::reference {
namespace {

std::string sizeText(uint32_t w, uint32_t h) {
  return std::to_string(w) + "x" + std::to_string(h);
}

// Throws unless `image` is RGB of `base`'s size, naming both.
void requireSizeOf(const core::Image8& image, const core::Image8& base) {
  const uint32_t w = base.width, h = base.height;
  if (image.width != w || image.height != h || image.pixels.size() != 3 * size_t(w) * h) {
    throw MetricsError(image.name + ": size " + sizeText(image.width, image.height) +
                       " differs from " + base.name + " (" + sizeText(w, h) + ")");
  }
}

// Throws unless `mask` (when given) is one channel of w x h.
void requireMaskSize(const core::Image8* mask, uint32_t w, uint32_t h) {
  if (mask != nullptr &&
      (mask->width != w || mask->height != h || mask->pixels.size() != size_t(w) * h)) {
    throw MetricsError(mask->name + ": mask size " + sizeText(mask->width, mask->height) +
                       " differs from the images (" + sizeText(w, h) + ")");
  }
}

cv::Mat readOrThrow(const std::filesystem::path& path, int flags, const char* what) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw MetricsError(path.string() + ": " + what + " not found (no such file)");
  }
  cv::Mat m;
  try {
    m = cv::imread(path.string(), flags);
  } catch (const cv::Exception& e) {
    throw MetricsError(path.string() + ": cannot decode " + what + " (" + e.what() + ")");
  }
  if (m.empty()) {
    throw MetricsError(path.string() + ": cannot decode " + what +
                       " (not an image OpenCV can read, or truncated)");
  }
  if (m.depth() != CV_8U) {  // IMREAD_COLOR / IMREAD_GRAYSCALE already give 8 bits
    throw MetricsError(path.string() + ": " + what + " is not 8-bit after decoding");
  }
  return m;
}

// Per region: a histogram of the 256 possible absolute errors gives mean, percentile, max
// and MSE exactly (integer counts, summed in value order).
struct Histogram {
  std::array<uint64_t, 256> count{};
  uint64_t pixels = 0;
  double flipSum = 0;

  RegionErrors finish() const {
    RegionErrors r;
    r.pixels = pixels;
    const uint64_t samples = 3 * pixels;
    if (samples == 0) return r;
    uint64_t sumAbs = 0, sumSq = 0, seen = 0;
    // Nearest rank: the ⌈0.99·N⌉-th smallest sample (1-based), in integers.
    const uint64_t rank = (99 * samples + 99) / 100;
    bool haveP99 = false;
    for (uint32_t v = 0; v < 256; ++v) {
      const uint64_t c = count[v];
      if (c == 0) continue;
      sumAbs += c * v;
      sumSq += c * v * v;
      seen += c;
      r.maxAbs = v;
      if (!haveP99 && seen >= rank) {
        r.p99Abs = v;
        haveP99 = true;
      }
    }
    r.meanAbs = double(sumAbs) / double(samples);
    const double mse = double(sumSq) / double(samples);
    r.psnr =
        mse == 0 ? std::numeric_limits<double>::infinity() : 10.0 * std::log10(255.0 * 255.0 / mse);
    r.flipMean = flipSum / double(pixels);
    return r;
  }
};

nlohmann::json regionJson(const RegionErrors& r) {
  nlohmann::json j;
  j["pixels"] = r.pixels;
  if (r.pixels == 0) {
    for (const char* k : {"mean_abs", "p99_abs", "max_abs", "psnr", "flip_mean"}) j[k] = nullptr;
    return j;
  }
  j["mean_abs"] = r.meanAbs;
  j["p99_abs"] = r.p99Abs;
  j["max_abs"] = r.maxAbs;
  j["identical"] = r.maxAbs == 0;
  if (std::isinf(r.psnr)) {
    j["psnr"] = nullptr;  // infinite: identical region
  } else {
    j["psnr"] = r.psnr;
  }
  j["flip_mean"] = r.flipMean;
  return j;
}

}  // namespace

core::Image8 loadRgb8(const std::filesystem::path& path) {
  const cv::Mat bgr = readOrThrow(path, cv::IMREAD_COLOR, "image");
  core::Image8 img(uint32_t(bgr.cols), uint32_t(bgr.rows), 3, path.string());
  for (int y = 0; y < bgr.rows; ++y) {
    const uint8_t* row = bgr.ptr<uint8_t>(y);
    for (int x = 0; x < bgr.cols; ++x) {
      const size_t o = (size_t(y) * img.width + size_t(x)) * 3;
      img.pixels[o] = row[3 * x + 2];
      img.pixels[o + 1] = row[3 * x + 1];
      img.pixels[o + 2] = row[3 * x];
    }
  }
  return img;
}

core::Image8 loadMask(const std::filesystem::path& path) {
  const cv::Mat grey = readOrThrow(path, cv::IMREAD_GRAYSCALE, "mask");
  core::Image8 m(uint32_t(grey.cols), uint32_t(grey.rows), 1, path.string());
  for (int y = 0; y < grey.rows; ++y) {
    const uint8_t* row = grey.ptr<uint8_t>(y);
    std::copy(row, row + grey.cols, m.pixels.begin() + std::ptrdiff_t(y) * grey.cols);
  }
  return m;
}

core::Image8 fromRgba8(std::span<const uint8_t> rgba, uint32_t width, uint32_t height,
                       std::string name) {
  const size_t n = size_t(width) * height;
  if (rgba.size() != 4 * n) {
    throw MetricsError(name + ": expected " + sizeText(width, height) + " RGBA8 pixels");
  }
  core::Image8 img(width, height, 3, std::move(name));
  for (size_t i = 0; i < n; ++i) {
    for (size_t c = 0; c < 3; ++c) img.pixels[3 * i + c] = rgba[4 * i + c];
  }
  return img;
}

ImageComparison compareImages(const core::Image8& reference, const core::Image8& test,
                              const core::Image8* mask, const CompareOptions& options) {
  const uint32_t w = reference.width, h = reference.height;
  const size_t n = size_t(w) * h;
  if (n == 0) throw MetricsError(reference.name + ": empty image");
  if (reference.pixels.size() != 3 * n) {
    throw MetricsError(reference.name + ": pixel buffer does not match " + sizeText(w, h));
  }
  requireSizeOf(test, reference);
  requireMaskSize(mask, w, h);

  ImageComparison c;
  c.width = w;
  c.height = h;
  c.pixelsPerDegree = options.flip.pixelsPerDegree;
  if (options.computeFlip)
    c.flipMap = flipErrorMap(reference.pixels, test.pixels, w, h, options.flip);

  Histogram all, in;
  for (size_t i = 0; i < n; ++i) {
    const bool inside = mask != nullptr && mask->pixels[i] != 0;
    const double flip = c.flipMap.empty() ? 0.0 : double(c.flipMap[i]);
    ++all.pixels;
    all.flipSum += flip;
    if (inside) {
      ++in.pixels;
      in.flipSum += flip;
    }
    for (size_t k = 0; k < 3; ++k) {
      const int e = std::abs(int(reference.pixels[3 * i + k]) - int(test.pixels[3 * i + k]));
      ++all.count[size_t(e)];
      if (inside) ++in.count[size_t(e)];
    }
  }
  c.frame = all.finish();
  if (mask != nullptr) c.masked = in.finish();

  // SSIM through OpenCV contrib (Wang et al. 2004 with OpenCV's Gaussian window). The Mats
  // wrap our buffers without copying; channel order does not matter for a per-channel mean.
  const cv::Mat a(int(h), int(w), CV_8UC3, const_cast<uint8_t*>(reference.pixels.data()));
  const cv::Mat b(int(h), int(w), CV_8UC3, const_cast<uint8_t*>(test.pixels.data()));
  cv::Mat map;
  const cv::Scalar s = cv::quality::QualitySSIM::compute(a, b, map);
  c.ssim = (s[0] + s[1] + s[2]) / 3.0;
  if (mask != nullptr && in.pixels > 0) {
    cv::Mat map64;
    map.convertTo(map64, CV_64FC3);
    double sum = 0;
    for (uint32_t y = 0; y < h; ++y) {
      const cv::Vec3d* row = map64.ptr<cv::Vec3d>(int(y));
      for (uint32_t x = 0; x < w; ++x) {
        if (mask->pixels[size_t(y) * w + x] == 0) continue;
        sum += (row[x][0] + row[x][1] + row[x][2]) / 3.0;
      }
    }
    c.ssimMasked = sum / double(in.pixels);
  }
  return c;
}

RegionErrors intervalErrors(const core::Image8& lower, const core::Image8& upper,
                            const core::Image8& test, const core::Image8& mask) {
  const uint32_t w = test.width, h = test.height;
  const size_t n = size_t(w) * h;
  for (const core::Image8* img : {&lower, &upper, &test}) requireSizeOf(*img, test);
  requireMaskSize(&mask, w, h);
  Histogram in;
  for (size_t i = 0; i < n; ++i) {
    if (mask.pixels[i] == 0) continue;
    ++in.pixels;
    for (size_t k = 0; k < 3; ++k) {
      const int lo = lower.pixels[3 * i + k], hi = upper.pixels[3 * i + k];
      if (lo > hi) {
        throw MetricsError(lower.name + ": above " + upper.name + " at pixel (" +
                           std::to_string(i % w) + ", " + std::to_string(i / w) + ")");
      }
      const int v = test.pixels[3 * i + k];
      ++in.count[size_t(std::max({0, lo - v, v - hi}))];
    }
  }
  return in.finish();
}

nlohmann::json toJson(const ImageComparison& c) {
  nlohmann::json j;
  j["width"] = c.width;
  j["height"] = c.height;
  j["frame"] = regionJson(c.frame);
  if (c.masked) j["mask"] = regionJson(*c.masked);
  j["ssim"] = c.ssim;
  if (c.masked) {
    j["ssim_mask"] = c.ssimMasked ? nlohmann::json(*c.ssimMasked) : nlohmann::json(nullptr);
  }
  j["flip_ppd"] = c.flipMap.empty() ? nlohmann::json(nullptr) : nlohmann::json(c.pixelsPerDegree);
  if (c.flipMap.empty()) {
    j["frame"]["flip_mean"] = nullptr;
    if (c.masked) j["mask"]["flip_mean"] = nullptr;
  }
  return j;
}

std::array<uint8_t, 3> heatmapColour(float v) {
  // Nine samples of matplotlib's "magma" (dark for no error, bright for large), linearly
  // interpolated: perceptually ordered and readable in greyscale.
  static constexpr uint8_t kTable[9][3] = {{0, 0, 4},      {28, 16, 68},    {79, 18, 123},
                                           {129, 37, 129}, {181, 54, 122},  {229, 80, 100},
                                           {251, 135, 97}, {254, 194, 135}, {252, 253, 191}};
  const float t = std::isnan(v) ? 1.0f : std::clamp(v, 0.0f, 1.0f) * 8.0f;
  const int i = std::min(int(t), 7);
  const float f = t - float(i);
  std::array<uint8_t, 3> out{};
  for (size_t k = 0; k < 3; ++k) {
    const float x = float(kTable[i][k]) + f * (float(kTable[i + 1][k]) - float(kTable[i][k]));
    out[k] = uint8_t(std::lround(x));
  }
  return out;
}

void writeHeatmapPng(const std::filesystem::path& path, std::span<const float> map, uint32_t width,
                     uint32_t height) {
  if (map.size() != size_t(width) * height || map.empty()) {
    throw MetricsError(path.string() + ": heat map has no pixels (FLIP not computed?)");
  }
  cv::Mat bgr(int(height), int(width), CV_8UC3);
  for (uint32_t y = 0; y < height; ++y) {
    auto* row = bgr.ptr<cv::Vec3b>(int(y));
    for (uint32_t x = 0; x < width; ++x) {
      const std::array<uint8_t, 3> c = heatmapColour(map[size_t(y) * width + x]);
      row[x] = cv::Vec3b(c[2], c[1], c[0]);
    }
  }
  bool ok = false;
  try {
    ok = cv::imwrite(path.string(), bgr);
  } catch (const cv::Exception& e) {
    throw MetricsError(path.string() + ": cannot write heat map (" + e.what() + ")");
  }
  if (!ok) throw MetricsError(path.string() + ": cannot write heat map");
}

}  // namespace penumbra::reference
