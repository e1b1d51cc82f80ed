// The source and receiver sets of Gibson 2003 §4: every patch that is seen by the
// calibrated camera receives; the brightest emitting patches that together carry a
// chosen share of the emitted power are sources (typically 70%, which "accounts for all
// primary and important secondary sources of light").
#pragma once

#include <cstdint>
#include <span>

#include "scene/patch_mesh.h"
#include "shadow/light_transport.h"

namespace penumbra::shadow {

// Emitted power of a patch as §4 ranks it: luminance of its emitted radiance x its area
// (the constant pi of radiant exitance is common to every patch and dropped).
double patchPower(const scene::Patch& patch);

// §4. `patchVisible` holds one flag per patch (non-zero: seen by the camera, e.g. from
// lighting::patchesVisibleFromCamera). Sources: emitting patches sorted by decreasing
// patchPower (ties by patch index, so the order is total), the shortest prefix whose
// power is at least powerShare x the total; powerShare == 1 takes every emitter, even
// those too faint to move a double sum. Receivers: the visible patches in index order
// (a patch may be in both sets). Throws std::invalid_argument unless 0 < powerShare <= 1
// and patchVisible has one entry per patch.
SourceReceiverSets selectSourcesAndReceivers(const scene::PatchMesh& mesh,
                                             std::span<const uint8_t> patchVisible,
                                             double powerShare);

}  // namespace penumbra::shadow
