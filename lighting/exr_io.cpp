#include "lighting/exr_io.h"

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>

#include <cmath>
#include <string>
#include <system_error>
#include <vector>

namespace penumbra::lighting {

namespace {
constexpr float kHalfMax = 65504.0f;  // the largest finite binary16
}  // namespace

core::ImageF readExr(const std::filesystem::path& path, ExrReadReport* report) {
  const std::string name = path.filename().string();
  if (!std::filesystem::is_regular_file(path)) {
    throw HdrError(name + ": no such file (" + path.string() + ")");
  }
  // OpenEXR allocates from the header as it opens the file: our own walk checks it first.
  const ExrLayout layout = readExrLayout(path);
  core::ImageF img;
  try {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const long w = long(dw.max.x) - dw.min.x + 1, h = long(dw.max.y) - dw.min.y + 1;
    if (w != layout.width || h != layout.height) {
      throw HdrError(name + ": OpenEXR reads a " + std::to_string(w) + "x" + std::to_string(h) +
                     " data window where the header walk read " + std::to_string(layout.width) +
                     "x" + std::to_string(layout.height));
    }
    const Imf::ChannelList& channels = file.header().channels();
    const bool rgb =
        channels.findChannel("R") && channels.findChannel("G") && channels.findChannel("B");
    const bool grey = !rgb && channels.findChannel("Y");
    if (!rgb && !grey) throw HdrError(name + ": has neither R, G, B nor Y channels");
    img = core::ImageF(uint32_t(w), uint32_t(h));
    Imf::FrameBuffer fb;
    const size_t xs = 3 * sizeof(float), ys = xs * size_t(w);
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < (grey ? 1 : 3); ++c) {
      fb.insert(grey ? "Y" : names[c],
                Imf::Slice::Make(Imf::FLOAT, img.pixels.data() + c, dw, xs, ys));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    if (grey) {
      for (size_t p = 0; p < size_t(w) * size_t(h); ++p) {
        img.pixels[3 * p + 1] = img.pixels[3 * p + 2] = img.pixels[3 * p];
      }
    }
  } catch (const HdrError&) {
    throw;
  } catch (const std::exception& e) {
    throw HdrError(name + ": cannot read as OpenEXR: " + e.what());
  }
  ExrReadReport r;
  size_t nonFinite = 0;
  for (float& v : img.pixels) {
    if (!std::isfinite(v)) {
      ++nonFinite;
    } else if (v < 0) {
      ++r.clampedNegative;
      if (v < r.mostNegative) r.mostNegative = v;
      v = 0;
    }
  }
  if (nonFinite > 0) {
    throw HdrError(name + ": " + std::to_string(nonFinite) + " channel values are NaN or infinite");
  }
  if (report != nullptr) *report = r;
  return img;
}

void writeExr(const std::filesystem::path& path, const core::ImageF& image, ExrPixels pixels) {
  const std::string name = path.filename().string();
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != size_t(image.width) * size_t(image.height) * 3) {
    throw HdrError(name + ": image is empty or its pixel data is not 3 x width x height");
  }
  for (float v : image.pixels) {
    if (!std::isfinite(v)) throw HdrError(name + ": image holds NaN or infinite values");
    if (pixels == ExrPixels::Half && std::fabs(v) > kHalfMax)
      throw HdrError(name + ": value " + std::to_string(v) +
                     " is beyond half float's range (65504); write it as float");
  }
  const bool half = pixels == ExrPixels::Half;
  try {
    Imf::Header header(image.width, image.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    const char* names[3] = {"R", "G", "B"};
    for (const char* n : names)
      header.channels().insert(n, Imf::Channel(half ? Imf::HALF : Imf::FLOAT));
    Imf::OutputFile file(path.c_str(), header);
    // OpenEXR writes a channel from a slice of its own type only: half samples are rounded to
    // the nearest binary16 here (Imath's conversion; in range, checked above).
    std::vector<Imath::half> halves;
    if (half) halves.assign(image.pixels.begin(), image.pixels.end());
    // OpenEXR's slices take a non-const base pointer even for writing.
    char* base = half ? reinterpret_cast<char*>(halves.data())
                      : const_cast<char*>(reinterpret_cast<const char*>(image.pixels.data()));
    const size_t sample = half ? sizeof(Imath::half) : sizeof(float);
    const size_t xs = 3 * sample, ys = xs * size_t(image.width);
    Imf::FrameBuffer fb;
    for (int c = 0; c < 3; ++c)
      fb.insert(names[c], Imf::Slice(half ? Imf::HALF : Imf::FLOAT, base + c * sample, xs, ys));
    file.setFrameBuffer(fb);
    file.writePixels(image.height);
  } catch (const std::exception& e) {
    std::error_code ec;
    std::filesystem::remove(path, ec);
    throw HdrError(name + ": cannot write OpenEXR: " + e.what());
  }
}

}  // namespace penumbra::lighting
