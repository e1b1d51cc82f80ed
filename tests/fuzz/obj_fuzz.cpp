// Wavefront OBJ models (scene/mesh_io.h), as scene files and the kiosk's product files
// give them.
#include "scene/mesh_io.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace penumbra;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  fuzz::expectOnlyProjectErrors([&] { (void)scene::parseObj(text, "fuzz.obj"); });
  return 0;
}
