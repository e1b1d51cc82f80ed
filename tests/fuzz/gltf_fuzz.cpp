// glTF models (scene/gltf_io.h, through tinygltf): text .gltf or binary .glb, chosen as the
// loader does, by the file's extension — here by the input's first bytes (a .glb starts
// with the magic "glTF").
#include <cstring>

#include "scene/gltf_io.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace penumbra;
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const auto path = fuzz::writeScratch(binary ? "model.glb" : "model.gltf", {data, size});
  fuzz::expectOnlyProjectErrors([&] { (void)scene::loadGltf(path); });
  return 0;
}
