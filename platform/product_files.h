// Product models read from files on the kiosk (issue 6 faults: "a corrupt product model at
// start-up (or hot-swapped): refuse it, keep the last good one, say why"). A shop replaces a
// product's model by dropping a new file on the board; a truncated copy, a NaN vertex or a
// model too heavy to shade must never reach the screen: the kiosk keeps showing the model it
// had (the bundle's, or the last accepted file), the LED goes degraded and the log and HUD
// name the file and the reason until a good file replaces it.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>

#include "platform/status.h"
#include "shadow/scene_bundle.h"

namespace penumbra::platform {

class ProductFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The most triangles a product file may have: its own mesh is also its shadow proxy (the
// offline `penumbra precompute` simplifies to 100-500, Gibson 2003 §7.2; the board has no
// simplifier), and validateProducts() refuses proxies above this.
constexpr size_t kMaxProductFileTriangles = 5000;

// Reads `file` (OBJ, PLY; glTF/GLB in builds with tinygltf) as a new model for `current`,
// whose name and material it keeps. Placed as `penumbra precompute` places products
// (scene/scene_file.h): metres, y up, bounding box centred on x = z = 0, lowest point at
// y = 0. Throws ProductFileError "FILE: reason": unreadable, truncated or malformed (the
// loader's own message), a non-finite vertex, no triangles, too many triangles, or larger
// than 10 m.
shadow::ProductModel loadProductFile(const std::filesystem::path& file,
                                     const shadow::ProductModel& current);

struct ProductFile {
  std::string product;  // the product's name in the bundle
  std::filesystem::path file;
};

// Replaces the named product of `bundle` by the model in `swap.file`, or refuses it and
// keeps the current model. Logs either way at `nowNs` (error with the reason on refusal).
// Returns the refusal reason, empty when the model was replaced. Throws ProductFileError when
// the bundle has no product of that name (a configuration error, not a bad file).
std::string swapProductFile(shadow::SceneBundle& bundle, const ProductFile& swap, KioskLog& log,
                            int64_t nowNs);

}  // namespace penumbra::platform
