// Wavefront OBJ models (scene/mesh_io.h), as scene files and the kiosk's product files
// give them, with the files they name: the input is the OBJ text, then (after a NUL byte)
// the text every `mtllib` reads, then (after another) the bytes every `map_Kd` texture
// reads, so the MTL parser, the texture decoders (PPM, PNG, JPEG) and the per-vertex
// attributes (vn, vt, smoothing groups, crease angles) are all reached from one input.
#include <string>

#include "scene/mesh_io.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace penumbra;
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const size_t mtlStart = std::min(input.find('\0'), input.size());
  const std::string_view obj = input.substr(0, mtlStart);
  const std::string_view rest = input.substr(std::min(mtlStart + 1, input.size()));
  const size_t textureStart = std::min(rest.find('\0'), rest.size());
  const std::string mtl(rest.substr(0, textureStart));
  const std::string texture(rest.substr(std::min(textureStart + 1, rest.size())));
  scene::MeshOptions options;
  // The crease angle from the input's length: 0, 60 and 180 degrees all get exercised.
  options.creaseAngleDegrees = double(size % 181);
  options.readFile = [&](const std::filesystem::path& path) -> std::string {
    if (path.extension() == ".mtl") return mtl;
    return texture;
  };
  fuzz::expectOnlyProjectErrors([&] { (void)scene::parseObj(obj, "fuzz.obj", options); });
  return 0;
}
