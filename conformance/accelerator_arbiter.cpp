// The double-precision arbiter of the accelerator suite (accelerator_scenes.hpp): which
// answers the geometry allows for a ray on which two accelerators disagree.
#include "conformance/accelerator_scenes.hpp"

#include "effigi/interfaces/ishape.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace effigi::conform {

namespace {

constexpr double Unit = 0x1p-24;  // float unit roundoff
constexpr double K = 16.0;        // ulps of distance the float triangle tests may be off

/// How far off the triangle's plane a float test that computes the normal e₁ × e₂ (Möller–
/// Trumbore, Embree) may put the hit: the normal's relative error is about u κ, with
/// κ = e_max² / |e₁ × e₂| (the reciprocal sine of the smallest angle), which tilts the
/// plane about a corner by that angle over up to e_max. About K u e_max for well-shaped
/// triangles; large for slivers, whose hit distance such tests cannot compute better.
double planeError(const Vector3d& a, const Vector3d& b, const Vector3d& c) {
    double e = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    double n = glm::length(glm::cross(b - a, c - a));
    return n > 0.0 ? K * Unit * e * e * e / n : std::numeric_limits<double>::infinity();
}

/// Distance from the origin to the segment [a, b] (the line of sight is projected out
/// by the caller).
double distanceToSegment(const Vector3d& a, const Vector3d& b) {
    Vector3d ab = b - a;
    double l2 = glm::dot(ab, ab);
    double s = l2 > 0.0 ? std::clamp(-glm::dot(a, ab) / l2, 0.0, 1.0) : 0.0;
    return glm::length(a + s * ab);
}

/// One triangle as seen along a ray, in double precision.
struct TriangleView {
    Point3f corner[3];
    bool near = false;     // the ray passes within δ of it (seen along the ray)
    bool certain = false;  // pierced with margin δ on the edges marked ok, away from corners,
                           // at a t whose slack keeps it inside (0, tMax)
    bool edgeOk[3] = {};   // edge k = (corner k, corner k+1) cleared with margin δ
    int side[3] = {};      // the third corner's side of edge k, seen along the ray
    double t = 0.0, slack = std::numeric_limits<double>::infinity();
};

TriangleView view(const Ray& ray, const Point3f& c0, const Point3f& c1, const Point3f& c2) {
    TriangleView tv;
    tv.corner[0] = c0, tv.corner[1] = c1, tv.corner[2] = c2;
    const Vector3d o(ray.o), d(ray.d);
    const double dl = glm::length(d);
    const Vector3d dn = d / dl;
    auto proj = [&](const Vector3d& v) { return v - glm::dot(v, dn) * dn; };
    const Vector3d v[3] = {Vector3d(c0) - o, Vector3d(c1) - o, Vector3d(c2) - o};
    const double L = std::max({glm::length(v[0]), glm::length(v[1]), glm::length(v[2])});
    const double delta = K * Unit * L;
    double e[3], len[3];
    for (int k = 0; k < 3; ++k) {
        e[k] = glm::dot(glm::cross(v[k], v[(k + 1) % 3]), dn);
        len[k] = glm::length(proj(v[(k + 1) % 3] - v[k]));
        double s = glm::dot(glm::cross(v[(k + 1) % 3] - v[k], v[(k + 2) % 3] - v[k]), dn);
        tv.side[k] = s > 0.0 ? 1 : (s < 0.0 ? -1 : 0);
    }
    const double area2 = e[0] + e[1] + e[2];
    if (area2 == 0.0) {  // seen exactly edge on: near when the line passes within δ of an edge
        const Vector3d q[3] = {proj(v[0]), proj(v[1]), proj(v[2])};
        tv.near = std::min({distanceToSegment(q[0], q[1]), distanceToSegment(q[1], q[2]), distanceToSegment(q[2], q[0])}) <= delta;
        return tv;
    }
    const double sgn = area2 > 0.0 ? 1.0 : -1.0;
    tv.near = true;
    for (int k = 0; k < 3; ++k) {
        double m = len[k] > 0.0 ? sgn * e[k] / len[k] : 0.0;
        tv.near &= m >= -delta;
        tv.edgeOk[k] = m > delta;
    }
    if (!tv.near) return tv;
    const Vector3d n = glm::cross(v[1] - v[0], v[2] - v[0]);
    const double nl = glm::length(n), cosT = glm::dot(dn, n) / nl, h = glm::dot(v[0], n) / nl;
    if (!(nl > 0.0) || cosT == 0.0) return tv;  // degenerate or parallel: any t along it
    tv.t = h / cosT / dl;
    tv.slack = (delta + planeError(v[0], v[1], v[2])) / (dl * std::abs(cosT)) + 8.0 * Unit * std::abs(tv.t);
    const bool cornersClear = glm::length(proj(v[0])) > delta && glm::length(proj(v[1])) > delta &&
                              glm::length(proj(v[2])) > delta;
    tv.certain = cornersClear && std::abs(h) > delta && tv.t - tv.slack > 0.0 && tv.t + tv.slack < double(ray.tMax);
    return tv;
}

} // namespace

double AccelArbiter::certainBound(const Ray& ray) const {
    const double dl = glm::length(Vector3d(ray.d)), tMax = double(ray.tMax);
    double bound = std::numeric_limits<double>::infinity();
    if (!(dl > 0.0)) return bound;
    std::vector<TriangleView> near;
    for (const IShape* shape : m_scene.shapes) {
        const TriangleMesh* mesh = shape->mesh();
        if (!mesh) {
            float t;
            Point2f uv;
            // Analytic shapes are asked through their own code, as every accelerator does;
            // only a hit at the origin or at tMax is in doubt.
            if (shape->intersect(ray, t, uv) && double(t) * dl > 1e-5 * (maxAbsComponent(ray.o) + double(t) * dl) &&
                double(t) * (1.0 + 1e-5) < tMax)
                bound = std::min(bound, double(t) * (1.0 + 1e-5));
            continue;
        }
        for (std::size_t i = 0; i < mesh->triangleCount(); ++i) {
            Point3f c[3];
            mesh->triangle(i, c[0], c[1], c[2]);
            TriangleView tv = view(ray, c[0], c[1], c[2]);
            if (tv.near) near.push_back(tv);
        }
    }
    // An edge the ray passes within δ of needs no margin when another triangle near the
    // ray shares it and lies on the other side of it: the surface continues there, and a
    // watertight test hits one of the two.
    for (const TriangleView& a : near) {
        if (!a.certain) continue;
        bool ok = true;
        for (int k = 0; k < 3 && ok; ++k) {
            if (a.edgeOk[k]) continue;
            const Point3f &p = a.corner[k], &q = a.corner[(k + 1) % 3];
            bool continued = false;
            for (const TriangleView& b : near)
                for (int j = 0; j < 3 && !continued; ++j) {
                    const Point3f &bp = b.corner[j], &bq = b.corner[(j + 1) % 3];
                    // Third corners on opposite sides of the directed edge p -> q.
                    if (bp == q && bq == p) continued = b.side[j] * a.side[k] > 0;
                    else if (bp == p && bq == q) continued = b.side[j] * a.side[k] < 0;
                }
            ok = continued;
        }
        if (ok) bound = std::min(bound, a.t + a.slack);
    }
    return bound;
}

bool AccelArbiter::possible(const Ray& ray, const Hit& h) const {
    if (h.shape >= m_scene.shapes.size() || !std::isfinite(h.t) || !(h.t > 0.f)) return false;
    if (double(h.t) > double(ray.tMax) * (1.0 + 8.0 * Unit)) return false;
    const IShape* shape = m_scene.shapes[h.shape];
    const TriangleMesh* mesh = shape->mesh();
    if (!mesh) {
        Ray r = ray;
        r.tMax = h.t * (1.f + 1e-5f);
        float t;
        Point2f uv;
        return h.prim == 0 && shape->intersect(r, t, uv) && std::abs(double(t) - double(h.t)) <= 1e-5 * double(h.t);
    }
    if (h.prim >= mesh->triangleCount()) return false;
    Point3f c[3];
    mesh->triangle(h.prim, c[0], c[1], c[2]);
    TriangleView tv = view(ray, c[0], c[1], c[2]);
    if (!tv.near || !(std::abs(double(h.t) - tv.t) <= tv.slack)) return false;
    // The barycentrics must name a point on the ray, up to their conditioning: an error
    // δ in the edge functions moves them by δ · (longest projected edge)² / (projected area).
    const Vector3d o(ray.o), d(ray.d), p0(c[0]), p1(c[1]), p2(c[2]);
    const double delta = K * Unit * std::max({glm::length(p0 - o), glm::length(p1 - o), glm::length(p2 - o)});
    const double b1 = h.uv.x, b2 = h.uv.y;
    if (!std::isfinite(b1) || !std::isfinite(b2)) return false;
    const Vector3d pb = (1.0 - b1 - b2) * p0 + b1 * p1 + b2 * p2;
    const Vector3d dn = d / glm::length(d);
    auto proj = [&](const Vector3d& v) { return v - glm::dot(v, dn) * dn; };
    double area2 = std::abs(glm::dot(glm::cross(p1 - p0, p2 - p0), dn));
    double edge = std::max({glm::length(proj(p1 - p0)), glm::length(proj(p2 - p1)), glm::length(proj(p0 - p2))});
    double tol = area2 > 0.0 ? delta * (1.0 + edge * edge / area2) : std::numeric_limits<double>::infinity();
    return glm::length(proj(pb - o)) <= tol;
}

bool AccelArbiter::acceptClosest(const Ray& ray, const AccelAnswer& a) const {
    if (a.returned != a.hit.valid()) return false;
    if (!a.hit.valid()) return std::isinf(certainBound(ray));
    return possible(ray, a.hit) && double(a.hit.t) <= certainBound(ray);
}

bool AccelArbiter::acceptAny(const Ray& ray, const AccelAnswer& a) const {
    if (a.occluded) return a.hit.valid() && possible(ray, a.hit);
    return std::isinf(certainBound(ray));
}

} // namespace effigi::conform
