// The analytic point-to-polygon form factor (Lambert 1760; Baum, Rushmeier & Winget 1989,
// "Improving radiosity solutions through the use of analytically determined
// form-factors"): the exact fraction of the light leaving a differential area that
// lands on a polygon, by Stokes' theorem a sum over the polygon's edges. Gibson 2003 §5
// computes the form factor from every source patch to every receiver vertex; the closed
// form is used there instead of the cos cos A / (pi r^2) point approximation because
// receiver vertices routinely sit right next to emitters (a wall vertex under a ceiling
// panel), where the point approximation is far off.
#pragma once

#include <span>
#include <vector>

#include <glm/glm.hpp>

namespace penumbra::lighting {

// Form factor from a differential area at `x` with unit normal `n` to the convex planar
// polygon `polygon` (vertices wound consistently, either way round):
//
//   F = 1/(2 pi) |sum_k beta_k (n . Gamma_k)|,
//
// beta_k the angle edge k subtends at x and Gamma_k the unit normal of the plane through
// x and that edge. The polygon is first clipped to the half-space in front of the
// receiver (n . (p - x) >= 0): the contour integral counts area behind the tangent plane
// with negative cosine, which a receiver cannot see. Purely geometric: the polygon emits
// from both sides here; one-sided emitters are the caller's test. Returns 0 for fewer
// than three vertices, a polygon wholly behind the receiver, or x on the polygon's plane.
double pointToPolygonFormFactor(const glm::dvec3& x, const glm::dvec3& n,
                                std::span<const glm::dvec3> polygon);

// The part of `polygon` with n . (p - x) >= 0 (Sutherland–Hodgman against one plane).
// Vertices on the plane are kept; the result may have fewer than three vertices.
std::vector<glm::dvec3> clipPolygonToHemisphere(const glm::dvec3& x, const glm::dvec3& n,
                                                std::span<const glm::dvec3> polygon);

}  // namespace penumbra::lighting
