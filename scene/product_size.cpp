#include "scene/product_size.h"

#include "core/json_reader.h"

namespace penumbra::scene {

std::optional<std::string> productSizeWarning(const std::string& file, double largestMetres,
                                              double scale, bool gltf) {
  const auto m = [](double v) { return core::formatNumber(v) + " m"; };
  const bool small = largestMetres < kMinPlausibleProductSize;
  if (!small && !(largestMetres > kMaxPlausibleProductSize)) return std::nullopt;
  std::string w = file + ": measures " + m(largestMetres) + " across";
  if (scale != 1) w += " once scaled by " + core::formatNumber(scale);
  if (small) {
    w += ", smaller than the " + m(kMinPlausibleProductSize) + " a showroom product measures";
    if (gltf && scale != 1) {
      w += "; a glTF is in metres through its own node transforms, and the scene's scale " +
           core::formatNumber(scale) + " multiplies them (without it: " + m(largestMetres / scale) +
           ")";
    } else if (scale != 1) {
      w += "; a scale meant for a model in centimetres or millimetres on one in metres? " +
           std::string("(without it: ") + m(largestMetres / scale) + ")";
    } else {
      w += "; a model in kilometres or scaled down when exported? (x 100: " +
           m(largestMetres * 100) + ")";
    }
  } else {
    w += ", larger than the " + m(kMaxPlausibleProductSize) +
         " a showroom product measures; a model in millimetres, centimetres or inches read "
         "as metres? (it would measure " +
         m(largestMetres * 0.001) + ", " + m(largestMetres * 0.01) + " or " +
         m(largestMetres * 0.0254) + ")";
  }
  return w;
}

}  // namespace penumbra::scene
