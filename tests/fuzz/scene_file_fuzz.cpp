// Scene files (scene/scene_file.h), as `penumbra precompute` reads them, then the room's
// patch mesh built from them (scene/patch_mesh.h), the first thing precompute does with a
// scene. Values are mutated through the JSON structure (json_mutator.cpp). Model paths
// resolve against data/showroom/ (through a link in the scratch folder, fuzz_support.h), so
// the seeds' products load their real models.
#include "scene/patch_mesh.h"
#include "scene/scene_file.h"
#include "tests/fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace penumbra;
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  static const std::filesystem::path anchor =
      fuzz::linkIntoScratch("showroom", std::filesystem::path(PENUMBRA_DATA_DIR) / "showroom") /
      "fuzzed-scene.json";
  fuzz::expectOnlyProjectErrors([&] {
    const scene::SceneDescription scene = scene::parseSceneFile(text, anchor);
    (void)scene::buildPatchMesh(scene.room, scene.patchSize);
  });
  return 0;
}
