// A shadow-map size per source cluster (issue 17), from how large that cluster's shadow of
// the product looks on screen.
//
// Gibson 2003 §7.2 gives every pass one map size. But the map is fitted around the product's
// bounding sphere (shadow/light_frustum.h), so what a texel covers on screen depends on the
// light: its shadow lands on the receivers magnified by their distance from the light over the
// product's, stretched where it falls obliquely, and then seen by the camera from near or far.
// A cluster overhead casts a small, sharp shadow at the product's foot; one low to the side
// throws a long one across the floor. Sizing each pass by its own shadow puts the texels where
// the camera can see them.
//
// The measure. The map spans the window of half-width h = D tan(fov / 2) at distance D along
// its axis (the light towards the sphere's centre). Take D where that axis leaves the room's
// box, X the exit point on the box face with normal n. Across the axis within the face (e2,
// perpendicular to both the axis and n) the window lands unstretched: X ± h e2. Along the
// tilt (e1, the window's direction perpendicular to the axis and e2) its edges hit the face
// where the rays from the light through X ± h e1 meet it. The window's footprint on screen
// is the longer of the two projected spans, P pixels, and a map of N texels has texels of
// P / N pixels along that span. Why the box face: receivers inside the room (a desk) are
// nearer the light than the wall or floor behind them, so their part of the shadow is less
// magnified; the box gives the largest footprint along the axis and so the larger map (the
// bound is conservative).
#pragma once

#include <cstdint>

#include <glm/glm.hpp>

#include "raster/frame_trace.h"
#include "scene/patch_mesh.h"
#include "shadow/light_frustum.h"

namespace penumbra::shadow {

// The smallest map a cluster gets (below it a map holds too few texels to show the
// product's outline at all).
inline constexpr uint32_t kMinClusterMapSize = 32;

// P of the header, in pixels of `view`, for the perspective `frustum` cast from `light` over
// the room's box `room`; +inf where a footprint point is behind the camera or the tilt makes
// the rays graze the face (the cluster then gets the frame's whole map). Double arithmetic
// with a fixed order: the same value on every machine.
double shadowFootprintPx(const raster::StaticView& view, const LightFrustum& frustum,
                         const glm::dvec3& light, const scene::Aabb& room);

// The cluster's map: `texelsPerPixel` texels per footprint pixel, rounded up to a multiple of
// 16, at least kMinClusterMapSize and at most `frameSize` (the frame's map, a multiple of 16:
// the bundle's setting or what the frame-rate controller left of it). texelsPerPixel <= 0 or
// an infinite footprint: frameSize.
uint32_t clusterMapSize(double footprintPx, double texelsPerPixel, uint32_t frameSize);

}  // namespace penumbra::shadow
