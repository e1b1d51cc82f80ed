#include "scene/image_io.h"

#ifdef PENUMBRA_HAVE_PNG
#include <png.h>
#endif

namespace penumbra::scene {

#ifdef PENUMBRA_HAVE_PNG

// libpng's simplified API (1.6): no setjmp, errors come back in image.message.
void writePng(const std::filesystem::path& path, uint32_t width, uint32_t height,
              std::span<const uint8_t> rgba) {
  if (rgba.size() != size_t{width} * height * 4) {
    throw ImageError(path.string() + ": pixel buffer size does not match " + std::to_string(width) +
                     "x" + std::to_string(height));
  }
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  image.width = width;
  image.height = height;
  image.format = PNG_FORMAT_RGBA;
  if (!png_image_write_to_file(&image, path.string().c_str(), 0, rgba.data(), 0, nullptr)) {
    throw ImageError(path.string() + ": cannot write PNG: " + image.message);
  }
}

#else

void writePng(const std::filesystem::path& path, uint32_t, uint32_t, std::span<const uint8_t>) {
  throw ImageError(path.string() + ": this build has no PNG support (PENUMBRA_WITH_PNG=OFF)");
}

#endif

}  // namespace penumbra::scene
