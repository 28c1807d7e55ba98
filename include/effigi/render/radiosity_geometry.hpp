#pragma once
// Geometry shared by the radiosity components: an element as a small polygon, uniform
// points on it, the analytic differential-area-to-polygon form factor, and visibility
// between two surface points through an IIntersect.
#include "effigi/interfaces/imesh.hpp"
#include "effigi/math/vector.hpp"

#include <array>

namespace effigi {

class IIntersect;

/// A convex planar polygon of up to MaxCorners corners, counter-clockwise about its
/// front normal (clipping a quad by a plane gives at most 5).
struct Polygon {
    static constexpr int MaxCorners = 8;
    std::array<Vector3d, MaxCorners> p{};
    int count = 0;
};

/// The corners of element i.
Polygon elementPolygon(const IMesh& mesh, std::uint32_t i);

/// A point of element i, uniform by area, from u ∈ [0,1)².
Point3f sampleElement(const IMesh& mesh, std::uint32_t i, const Point2f& u);

/// False when elements i and j cannot exchange light whatever lies between them: i = j,
/// or one lies wholly on or behind the other's plane (elements are one-sided).
bool canExchange(const IMesh& mesh, std::uint32_t i, std::uint32_t j);

/// Form factor from a differential area at x with unit normal nx to the polygon (front
/// normal npoly): F = (1/2π) Σ_k γ_k (Γ_k · nx) over the polygon's edges (Lambert 1760),
/// with γ_k the angle an edge subtends at x and Γ_k the unit normal of the plane through
/// x and the edge. The polygon is first clipped to the half-space in front of x (the
/// formula needs the whole polygon above x's tangent plane: Baum, Rushmeier & Winget,
/// "Improving Radiosity Solutions Through the Use of Analytically Determined
/// Form-Factors", SIGGRAPH 1989) and is zero when x lies behind it (one-sided elements).
/// No occlusion. Bounded by 1 however close x is to the polygon.
double pointToPolygonFormFactor(const Vector3d& x, const Vector3d& nx, const Polygon& poly, const Vector3d& npoly);

/// Whether the segment between two surface points (each with its front normal) is free
/// of geometry. Both ends are pushed off their surfaces (offsetRayOrigin) and the ray
/// stops ShadowEpsilon short of the target, so the two surfaces themselves never block.
bool mutuallyVisible(const IIntersect& accel, const Point3f& x, const Normal3f& nx, const Point3f& y,
                     const Normal3f& ny);

} // namespace effigi
