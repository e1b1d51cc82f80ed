#include "lighting/probe_image_io.h"

#ifdef PENUMBRA_HAVE_OPENEXR

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>

#include <exception>
#include <string>

namespace penumbra::lighting {

ProbeImage readExrProbe(const std::filesystem::path& path) {
  const std::string name = path.string();
  try {
    Imf::InputFile file(name.c_str());
    const Imath::Box2i dw = file.header().dataWindow();
    const int64_t w = int64_t{dw.max.x} - dw.min.x + 1, h = int64_t{dw.max.y} - dw.min.y + 1;
    if (w <= 0 || h <= 0 || w > 65536 || h > 65536) {
      throw ProbeImageError(name + ": empty or oversized data window");
    }
    const Imf::ChannelList& channels = file.header().channels();
    const char* names[3] = {"R", "G", "B"};
    bool any = false;
    for (const char* c : names) any = any || channels.findChannel(c) != nullptr;
    if (!any) throw ProbeImageError(name + ": no R, G or B channel");
    ProbeImage img;
    img.width = static_cast<uint32_t>(w);
    img.height = static_cast<uint32_t>(h);
    img.rgb.assign(size_t(w) * size_t(h) * 3, 0.0f);
    Imf::FrameBuffer fb;
    // Base pointer shifted so that pixel (dw.min.x, dw.min.y) lands on element 0.
    char* base = reinterpret_cast<char*>(img.rgb.data()) -
                 (int64_t{dw.min.x} + int64_t{dw.min.y} * w) * 3 * int64_t(sizeof(float));
    for (int c = 0; c < 3; ++c) {
      fb.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), 3 * sizeof(float),
                                     size_t(w) * 3 * sizeof(float), 1, 1, 0.0));
    }
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    return img;
  } catch (const ProbeImageError&) {
    throw;
  } catch (const std::exception& e) {
    throw ProbeImageError(name + ": cannot read EXR: " + e.what());
  }
}

void writeExrProbe(const ProbeImage& img, const std::filesystem::path& path) {
  const std::string name = path.string();
  if (img.width == 0 || img.height == 0 || img.rgb.size() != size_t{img.width} * img.height * 3) {
    throw ProbeImageError(name + ": image size does not match its pixels");
  }
  try {
    Imf::Header header(static_cast<int>(img.width), static_cast<int>(img.height));
    header.compression() = Imf::ZIP_COMPRESSION;
    const char* names[3] = {"R", "G", "B"};
    for (const char* c : names) header.channels().insert(c, Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(name.c_str(), header);
    Imf::FrameBuffer fb;
    char* base = const_cast<char*>(reinterpret_cast<const char*>(img.rgb.data()));
    for (int c = 0; c < 3; ++c) {
      fb.insert(names[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), 3 * sizeof(float),
                                     size_t{img.width} * 3 * sizeof(float)));
    }
    file.setFrameBuffer(fb);
    file.writePixels(static_cast<int>(img.height));
  } catch (const std::exception& e) {
    throw ProbeImageError(name + ": cannot write EXR: " + e.what());
  }
}

}  // namespace penumbra::lighting

#endif  // PENUMBRA_HAVE_OPENEXR
