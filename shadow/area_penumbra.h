// Area-light penumbrae: how wide the penumbra of one pass's light is, so that the map lookup
// (docs/pipeline-spec.md §7) can spread each pass's shadow edge over it.
//
// Gibson 2003 §7.2 casts each cluster's shadow map from one point. A cluster is light spread
// over an area (a 0.2 m ceiling patch, a window's column of patches), whose shadow edges are
// ramps, not steps; summed over the passes the steps still leave the penumbra too hard where
// one cluster carries much of the light. Measured at the desk corner of the showroom, every
// source a pass and 2048² maps: 0.876 levels of mean error against a reference whose lights
// are points (`penumbra accuracy --point-lights`), 1.200 against the real one
// (docs/accuracy.md).
//
// The width, from similar triangles. Let the light move by a distance Δ across the map's
// axis. A blocker edge at distance zb along the axis then moves its shadow on a receiver at
// zr by Δ (zr - zb) / zb, which the light sees under an angle (in tangent units of the map's
// window) of Δ (1 / zb - 1 / zr). Window depth is d = f / (f - n) (1 - n / z) for the
// frustum's near and far planes n, f (GL conventions), so 1 / z = 1 / n - d (f - n) / (f n)
// and
//     1 / zb - 1 / zr = (dr - db) (f - n) / (f n):
// the penumbra is linear in the window-depth difference. A map of `size` texels spans
// 2 tan(fov / 2) in tangent units, so a light of half-width ρ spreads an edge over a box of
// half-width
//     w = K (dr - db) texels,   K = ρ size (f - n) / (2 tan(fov / 2) f n).
// The box filter of half-width ρ is the exact penumbra of a uniform square light of side 2ρ
// seen along its normal; for any other light, ρ = sqrt(3 σ²) matches the variance σ² of
// its emitting area per axis across the view (a square of side a: σ² = a² / 12, ρ = a / 2).
#pragma once

#include <cstdint>
#include <span>

#include <glm/glm.hpp>

#include "shadow/light_frustum.h"
#include "shadow/scene_bundle.h"
#include "shadow/source_clusters.h"

namespace penumbra::shadow {

// The half-width ρ (metres) of the box light with the same spread across `axis` (a unit
// vector, the map's view direction) as the cluster's sources seen from `light`: each source
// a square patch of its area at its centre, weighted by its average transfer
// (sourceAverage); a source with no transfer counts with a tiny weight, so ρ is defined.
double clusterHalfWidth(const SceneBundle& bundle, const SourceCluster& cluster,
                        std::span<const uint32_t> sources, const glm::dvec3& light,
                        const glm::dvec3& axis);

// K of the header: texels of penumbra half-width per unit of window depth behind the
// blocker, for a light of half-width `halfWidth` and a map of `mapSize` texels fitted by
// fitLightFrustum (a perspective frustum).
double penumbraScale(const LightFrustum& frustum, double halfWidth, uint32_t mapSize);

}  // namespace penumbra::shadow
