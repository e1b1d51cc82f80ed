// A sanity check on a product's size once scaled to metres (issue 15 item 6: a glTF whose
// scene-file scale multiplied its own node scale became a 1.6 cm teapot, shown without a
// word). A model's units are not in OBJ or PLY files, and glTF's metres are often undone by a
// scale meant for another file: a size no showroom product has is the one signal left.
// Not an error — a 4 cm figurine may be meant — but a warning naming the file, its size and
// the likely slip, printed by `penumbra precompute` and logged by the kiosk's product files.
#pragma once

#include <optional>
#include <string>

namespace penumbra::scene {

// Free-standing showroom products run from a vase or a lamp (10-30 cm) to a bed or a sofa
// (2-3 m). Below 5 cm (smaller than a coffee cup) a model is more likely metres scaled as
// centimetres or millimetres (x 0.01, x 0.001) or a glTF scaled twice; above 5 m (longer than
// a car, close to the bundled showroom's 6 m width) more likely a model in inches read as
// metres (x 39.4) that stayed under the 10 m a product may measure at all (kMaxProductSize).
inline constexpr double kMinPlausibleProductSize = 0.05;
inline constexpr double kMaxPlausibleProductSize = 5.0;

// nullopt when `largestMetres` (the largest bounding-box extent once scaled) lies within the
// plausible range; otherwise "FILE: measures L m across ...: likely cause". `scale` is the
// scale that was applied (1: none, as for the kiosk's product files); `gltf`: the model's own
// node transforms were applied before it.
std::optional<std::string> productSizeWarning(const std::string& file, double largestMetres,
                                              double scale, bool gltf);

}  // namespace penumbra::scene
