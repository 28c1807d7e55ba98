#pragma once
// Triangles for the RIB primitives effigi has no analytic shape for: parametric grids
// (partial quadrics, cones, patches) and polygons (fans for convex ones, ear clipping for
// general ones).
#include "effigi/render/mesh.hpp"

#include <cstdint>
#include <functional>
#include <vector>

namespace effigi::rib {

/// Position and normal of a parametric surface at (u, v) in [0, 1]².
using SurfaceFn = std::function<void(double u, double v, Vector3d& p, Vector3d& n)>;

/// A (nu + 1) × (nv + 1) grid of vertices of f, two triangles per cell, uv = (u, v).
TriangleMesh gridMesh(int nu, int nv, const SurfaceFn& f);

/// Appends the triangles of the simple polygon `loop` (indices into `points`) to `out`,
/// keeping the loop's winding. Convex: a fan. Otherwise ear clipping in the plane of the
/// polygon's Newell normal (Eberly, "Triangulation by Ear Clipping", 2002); polygons of
/// more than 256 vertices, and any the clipping cannot finish (self-intersecting ones),
/// fall back to a fan.
void triangulate(const std::vector<Point3f>& points, const std::vector<std::uint32_t>& loop, bool convex,
                 std::vector<std::uint32_t>& out);

/// Makes the winding agree with the vertex normals where there are any (each triangle
/// whose edge cross product points against the mean of its normals is turned), then
/// reverses every triangle if `toWorld` mirrors space, so that the winding and the
/// normals still agree once MeshShape has applied it.
void orientTriangles(TriangleMesh& m, bool mirrored);

} // namespace effigi::rib
