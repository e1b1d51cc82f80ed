// A hand-built room for the shaft hierarchy and the source clusters (Gibson 2003 §6, §8):
// their unit tests and their benchmark (bench/shadow_bench.cpp) share it.
#pragma once

#include "scene/patch_mesh.h"
#include "shadow/light_transport.h"
#include "shadow/shaft_hierarchy.h"  // kNoIndex

namespace penumbra::shadow::testing {

// A 4 m x 2.5 m x 4 m room built by hand (the real transfers are computed elsewhere):
// receivers are a floor of floorCells^2 patches (plus, with `wallAndWindow`, a back wall
// z = 0 of 6 x 4 patches); sources are a lightCols x lightRows panel of ceiling patches
// of varied brightness, or all equally bright with `equalSources` (plus a 2 x 2 window in
// the wall x = 0). Transfers follow §5 without visibility: reflectance x point-to-patch
// form factor x emission.
void buildTestRoom(int floorCells, int lightCols, int lightRows, bool wallAndWindow,
                   scene::PatchMesh& mesh, SourceReceiverSets& sets, RadianceTransfers& t,
                   bool equalSources = false);

}  // namespace penumbra::shadow::testing
