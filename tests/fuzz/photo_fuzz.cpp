// Photographs, PNG and JPEG (scene/photo_io.h, OpenCV's imread): the exposure brackets of
// `penumbra capture` and the calibration photographs. imread picks the decoder by the
// content, not the name.
#include "scene/photo_io.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace penumbra;
  const auto path = fuzz::writeScratch("photo.img", {data, size});
  fuzz::expectOnlyProjectErrors([&] { (void)scene::readPhotoRgb8(path); });
  return 0;
}
