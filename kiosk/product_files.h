// Product models read from files on the kiosk (issue 6 faults: "a corrupt product model at
// start-up (or hot-swapped): refuse it, keep the last good one, say why"). A shop replaces a
// product's model by dropping a new file on the board; a truncated copy, a NaN vertex or a
// model too heavy to shade must never reach the screen: the kiosk keeps showing the model it
// had (the bundle's, or the last accepted file), the LED goes degraded and the log and HUD
// name the file and the reason until a good file replaces it.
#pragma once

#include <filesystem>
#include <future>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/error.h"
#include "kiosk/status.h"
#include "shadow/scene_bundle.h"

namespace penumbra::kiosk {

class ProductFileError : public core::Error {
 public:
  using core::Error::Error;
};

// The most triangles a product file may have: its own mesh is also its shadow proxy (the
// offline `penumbra precompute` simplifies to 100-500, Gibson 2003 §7.2; the board has no
// simplifier), and validateProducts() refuses proxies above this.
constexpr size_t kMaxProductFileTriangles = 5000;

// Reads `file` (OBJ, PLY; glTF/GLB in builds with tinygltf) as a new model for `current`,
// whose name and material it keeps. Placed as `penumbra precompute` places products
// (scene/scene_file.h): metres, y up, bounding box centred on x = z = 0, lowest point at
// y = 0. The file's normals come with it (as exported, or split by crease angle: the 60
// degree default of scene/mesh_io.h), and its colours when it has some (OBJ materials, glTF
// base colour); without colours the product keeps its material's one reflectance. Throws
// ProductFileError "FILE: reason": unreadable, truncated or malformed (the loader's own
// message), a non-finite vertex, no triangles, too many triangles, or larger than 10 m.
// `warnings` (optional) receives what is not refused but should be seen, each naming the
// file: the loader's (an undecodable texture) and an implausible size (scene/product_size.h:
// a file in millimetres, centimetres or inches; product files are read in metres).
shadow::ProductModel loadProductFile(const std::filesystem::path& file,
                                     const shadow::ProductModel& current,
                                     std::vector<std::string>* warnings = nullptr);

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

// The HUD's text while a product's file is refused ("MODEL REFUSED: chair").
std::string productFileFault(const std::string& product);

// On the board: the configured product files, polled (by modification time, so a file
// copied over an old one is noticed) and applied to the bundle when they change.
//
// Loading never blocks the display (issue 18: a hostile PLY hung the frame loop): a changed
// file is read on a worker thread (std::async) while the frame loop keeps drawing the old
// model, and the result is applied between two frames by collect() once it is ready: the
// new model, or one log line saying why the file was refused with the old model kept. The
// work of one load is bounded by the loaders' limits (scene/mesh_io.h), so a worker always
// ends. Only the frame thread touches the bundle; a worker gets a copy of the product.
//
// Virtual time: the simulator (firmware-sim) has no wall-clock duration for a load, so it
// loads a scripted file synchronously between frames (swapProductFile, or poll() with
// kUntilLoaded): the model changes at the first frame at or after its scripted time on any
// machine, and replays keep their hashes.
class ProductFileWatcher {
 public:
  explicit ProductFileWatcher(std::vector<ProductFile> files);
  ~ProductFileWatcher();  // waits for loads still running (each bounded)

  enum class Wait { kNo, kUntilLoaded };

  struct Change {
    uint32_t product = 0;  // index in the bundle
    bool replaced = false;
    std::string refusal;  // empty when replaced
  };
  // Starts loading every file that is new or changed since the last poll (all of them at
  // the first; a file whose load is still running is looked at again once it is applied),
  // then collect()s; a file that cannot be stat'ed counts as refused. Throws
  // ProductFileError for a product name the bundle does not have.
  std::vector<Change> poll(shadow::SceneBundle& bundle, KioskLog& log, int64_t nowNs,
                           Wait wait = Wait::kUntilLoaded);
  // Applies the loads that have finished (all of them with kUntilLoaded) to the bundle, as
  // swapProductFile() would, and returns what changed, for KioskLoop::setFault /
  // productReplaced. Cheap when nothing is ready: call it between frames.
  std::vector<Change> collect(shadow::SceneBundle& bundle, KioskLog& log, int64_t nowNs,
                              Wait wait = Wait::kNo);
  // Whether a load is running.
  bool loading() const;

  // A load's outcome: the new model, or why the file was refused.
  struct Loaded {
    shadow::ProductModel model;
    std::string refusal;
    std::vector<std::string> warnings;  // logged as warnings when the model is applied
  };

 private:
  struct Watched {
    ProductFile file;
    std::filesystem::file_time_type seen{};
    bool polled = false;
    std::future<Loaded> load;  // valid while a load runs or waits to be applied
  };
  std::vector<Watched> files_;
};

}  // namespace penumbra::kiosk
