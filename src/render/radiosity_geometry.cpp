// Polygon helpers of the radiosity components (effigi/render/radiosity_geometry.hpp).
#include "effigi/render/radiosity_geometry.hpp"

#include "effigi/interfaces/iintersect.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/render/ray.hpp"

#include <cmath>

namespace effigi {

Polygon elementPolygon(const IMesh& mesh, std::uint32_t i) {
    const MeshElement& e = mesh.elements()[i];
    std::span<const Point3f> v = mesh.vertices();
    Polygon poly;
    poly.count = e.corners();
    for (int k = 0; k < poly.count; ++k) poly.p[k] = Vector3d(v[e.vertices[k]]);
    return poly;
}

Point3f sampleElement(const IMesh& mesh, std::uint32_t i, const Point2f& u) {
    const MeshElement& e = mesh.elements()[i];
    std::span<const Point3f> v = mesh.vertices();
    const Point3f& p0 = v[e.vertices[0]];
    if (e.corners() == 4)  // a parallelogram: p0 + s (p1 − p0) + t (p3 − p0)
        return p0 + u.x * (v[e.vertices[1]] - p0) + u.y * (v[e.vertices[3]] - p0);
    Point2f b = warp::squareToUniformTriangle(u);
    return b.x * p0 + b.y * v[e.vertices[1]] + (1.f - b.x - b.y) * v[e.vertices[2]];
}

bool canExchange(const IMesh& mesh, std::uint32_t i, std::uint32_t j) {
    if (i == j) return false;
    const MeshElement& a = mesh.elements()[i];
    const MeshElement& b = mesh.elements()[j];
    std::span<const Point3f> v = mesh.vertices();
    // A tolerance of 1e-5 element sizes keeps coplanar neighbours (round-off) out.
    auto anyInFront = [&](const MeshElement& of, const MeshElement& plane) {
        float eps = 1e-5f * std::sqrt(plane.area);
        for (int k = 0; k < of.corners(); ++k)
            if (dot(v[of.vertices[k]] - plane.centre, plane.n) > eps) return true;
        return false;
    };
    return anyInFront(b, a) && anyInFront(a, b);
}

namespace {

/// Sutherland–Hodgman: the part of the polygon where dot(p − x, n) ≥ 0.
Polygon clipAbove(const Polygon& in, const Vector3d& x, const Vector3d& n) {
    Polygon out;
    for (int k = 0; k < in.count; ++k) {
        const Vector3d& a = in.p[k];
        const Vector3d& b = in.p[(k + 1) % in.count];
        double da = glm::dot(a - x, n), db = glm::dot(b - x, n);
        if (da >= 0.0 && out.count < Polygon::MaxCorners) out.p[out.count++] = a;
        if ((da >= 0.0) != (db >= 0.0) && out.count < Polygon::MaxCorners) {
            double t = da / (da - db);
            out.p[out.count++] = a + t * (b - a);
        }
    }
    return out;
}

} // namespace

double pointToPolygonFormFactor(const Vector3d& x, const Vector3d& nx, const Polygon& poly, const Vector3d& npoly) {
    if (poly.count < 3) return 0.0;
    // One-sided: x must lie strictly in front of the polygon's plane.
    if (!(glm::dot(x - poly.p[0], npoly) > 0.0)) return 0.0;
    Polygon c = clipAbove(poly, x, nx);
    if (c.count < 3) return 0.0;
    double sum = 0.0;
    for (int k = 0; k < c.count; ++k) {
        Vector3d a = c.p[k] - x, b = c.p[(k + 1) % c.count] - x;
        double la = glm::length(a), lb = glm::length(b);
        if (!(la > 0.0 && lb > 0.0)) continue;  // a corner on x: that edge adds nothing
        a /= la;
        b /= lb;
        Vector3d cr = glm::cross(a, b);
        double s = glm::length(cr);
        if (!(s > 1e-300)) continue;  // edge on a line through x: no area swept
        double gamma = std::atan2(s, glm::dot(a, b));
        sum += gamma * glm::dot(cr, nx) / s;
    }
    // Corners counter-clockwise about a front normal facing x make Σ point away from the
    // polygon, hence the minus sign; the clamp removes round-off beyond [0, 1].
    double f = -sum / (2.0 * 3.14159265358979323846);
    return std::clamp(f, 0.0, 1.0);
}

bool mutuallyVisible(const IIntersect& accel, const Point3f& x, const Normal3f& nx, const Point3f& y,
                     const Normal3f& ny) {
    Vector3f d = y - x;
    Point3f o = offsetRayOrigin(x, nx, d);
    Point3f t = offsetRayOrigin(y, ny, -d);
    Ray ray{o, t - o, 1.f - ShadowEpsilon};
    return !accel.occluded(ray);
}

} // namespace effigi
