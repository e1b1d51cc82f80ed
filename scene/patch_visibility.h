// Which patches of the room's patch mesh the kiosk camera sees (issue 4 item 2): only
// those can take their radiance and reflectance from the photograph (Gibson & Chalmers
// 2003 §4.2); the others are filled in from the probe or by default.
//
// A patch counts as visible when its front side faces the camera and at least one of five
// sample points (the centre and the midpoints between the centre and its four corners)
// projects inside the image and reaches the camera unoccluded. Occlusion is the room's own
// ray cast (RoomDescription::intersect: every quad, walls and solid boxes); no Embree.
// Offline, O(patches x quads).
#pragma once

#include <cstdint>
#include <vector>

#include "scene/camera.h"
#include "scene/patch_mesh.h"

namespace penumbra::scene {

// One flag per patch of `mesh` (1 = visible). `room` is the description the mesh was built
// from; pass nullptr to skip the occlusion test (frustum and facing only). Throws
// std::invalid_argument for a non-positive image size.
std::vector<uint8_t> visiblePatches(const PatchMesh& mesh, const Camera& camera, int width,
                                    int height, const RoomDescription* room);

}  // namespace penumbra::scene
