#include "shadow/source_receiver_sets.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/colour.h"

namespace penumbra::shadow {

double patchPower(const scene::Patch& patch) {
  // In double: the ranking must not depend on float rounding of nearly equal emitters.
  return core::luminance(patch.emission) * patch.area;
}

SourceReceiverSets selectSourcesAndReceivers(const scene::PatchMesh& mesh,
                                             std::span<const uint8_t> patchVisible,
                                             double powerShare) {
  if (!(powerShare > 0 && powerShare <= 1)) {
    throw std::invalid_argument("selectSourcesAndReceivers: powerShare must be in (0, 1], got " +
                                std::to_string(powerShare));
  }
  if (patchVisible.size() != mesh.patches.size()) {
    throw std::invalid_argument("selectSourcesAndReceivers: patchVisible has " +
                                std::to_string(patchVisible.size()) + " entries for " +
                                std::to_string(mesh.patches.size()) + " patches");
  }
  SourceReceiverSets sets;
  sets.powerShare = powerShare;

  struct Ranked {
    double power;
    uint32_t patch;
  };
  std::vector<Ranked> emitters;
  for (uint32_t p = 0; p < mesh.patches.size(); ++p) {
    if (mesh.patches[p].emits()) emitters.push_back({patchPower(mesh.patches[p]), p});
  }
  std::sort(emitters.begin(), emitters.end(), [](const Ranked& a, const Ranked& b) {
    return a.power != b.power ? a.power > b.power : a.patch < b.patch;
  });
  // The total is summed in the same (sorted) order as the running prefix, so the last
  // prefix reproduces it exactly and the comparison below cannot fall short by rounding.
  double total = 0;
  for (const Ranked& r : emitters) total += r.power;
  const double goal = powerShare * total;
  double sum = 0;
  for (const Ranked& r : emitters) {
    if (powerShare < 1 && sum >= goal && !sets.sources.empty()) break;
    sets.sources.push_back(r.patch);
    sum += r.power;
  }

  for (uint32_t p = 0; p < patchVisible.size(); ++p) {
    if (patchVisible[p] != 0) sets.receivers.push_back(p);
  }
  return sets;
}

}  // namespace penumbra::shadow
