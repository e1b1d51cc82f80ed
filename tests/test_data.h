// Where the bundled data lives, for tests anywhere in the tree.
#pragma once

#include <filesystem>

namespace penumbra::testing {

// data/ of the source tree: from the build (PENUMBRA_DATA_DIR), else beside this header.
inline std::filesystem::path dataDir() {
#ifdef PENUMBRA_DATA_DIR
  return PENUMBRA_DATA_DIR;
#else
  return std::filesystem::path(__FILE__).parent_path().parent_path() / "data";
#endif
}

// Debian's blender-data light probes (CC0): real OpenEXR files, skipped when not installed.
inline const std::filesystem::path& blenderProbeDir() {
  static const std::filesystem::path dir = "/usr/share/blender/datafiles/studiolights/world";
  return dir;
}

}  // namespace penumbra::testing
