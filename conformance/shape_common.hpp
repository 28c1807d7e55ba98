#pragma once
// What the shape suite's files share (shape_suite.cpp: set-up, position samples, extreme
// references; shape_measure.cpp: intersections, area and sampling density against ray
// casting; shape_directions.cpp: direction sampling): the shape under test with the
// intersector that sees it, its scale, ray casting that enumerates every crossing of a
// line with the surface, and the bounding box's surface that lines and directions aim at.
#include "conformance/conformance.hpp"
#include "effigi/interfaces/iintersect.hpp"
#include "effigi/interfaces/ishape.hpp"

#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace effigi::conform::shape {

/// One shape ready to probe. Lengths scale with R, the radius of the bounding box's
/// bounding sphere, so that tiny and huge configurations are judged alike.
struct Setup {
    Ref<IShape> shape;
    Ref<IIntersect> accel;  // the shape alone, as a scene's accelerator sees it
    Point3f centre{0.f};
    double radius = 1.0;    // R
    bool samples = false;   // samplePosition() gives points (pdf > 0)
    /// A documented approximation of the area and of uniform sampling by area (sdfgrid):
    /// the relative slack granted to the statistical area checks, and why.
    double areaSlack = 1e-3;
    std::string approximate;

    /// Closeness asked of two computations of one surface point: 1e-5 of the shape's
    /// size plus a few float roundings of the point's coordinates.
    double tolerance(const Point3f& p) const { return 1e-5 * radius + 64.0 * 0x1p-24 * double(maxAbsComponent(p)); }
};

/// Every crossing of the line o + t d (t > 0) with the surface, nearest first (at most
/// 32). Each query restarts on the line itself, a small step past the last crossing
/// (offsetRayOrigin would leave the line by its offset along the normal, which moves a
/// grazing second crossing by offset / cos θ); the same primitive found again at the same
/// point is stepped over, so that two sheets closer than the step still count twice.
inline std::vector<SurfaceInteraction> traceAll(const Setup& s, const Ray& ray) {
    std::vector<SurfaceInteraction> out;
    const Vector3d o(ray.o), d(ray.d);
    const double dl = glm::length(d);
    double t = 0.0, step = 1e-6 * s.radius / dl;
    std::uint32_t prim = Hit::None;
    for (int k = 0; k < 64 && out.size() < 32; ++k) {
        Ray r{Point3f(o + t * d), ray.d, Infinity};
        Hit h;
        if (!s.accel->intersect(r, h)) break;
        SurfaceInteraction si = s.shape->interaction(r, h);
        if (!isFinite(si.p)) {
            out.push_back(si);
            break;
        }
        const double at = t + double(h.t);
        // A few roundings of the coordinates bound how finely the line can be walked.
        const double minStep = (1e-6 * s.radius + 4.0 * 0x1p-24 * double(maxAbsComponent(si.p))) / dl;
        if (!out.empty() && h.prim == prim && glm::length(Vector3d(si.p) - Vector3d(out.back().p)) <= s.tolerance(si.p)) {
            step = std::max(4.0 * step, minStep);  // the same crossing again
        } else {
            out.push_back(si);
            step = minStep;
        }
        prim = h.prim;
        t = at + step;
    }
    return out;
}

/// The crossing at p of a short ray toward p along w, from 1e-4 R before it (or 256u·|p|,
/// clear of the rounding of p's coordinates), if there is one within the tolerance; for a
/// point within rounding of a rim, a ray aimed δ = 1e-5 R + 256u·|p| beside p (across n)
/// that meets the surface within the tolerance + 2δ of p also counts.
inline std::optional<SurfaceInteraction> crossingAt(const Setup& s, const Point3f& p, const Normal3f& n,
                                                   const Vector3f& w) {
    const double round = 256.0 * 0x1p-24 * double(maxAbsComponent(p));
    const double h = std::max(1e-4 * s.radius, round), delta = 1e-5 * s.radius + round;
    Frame f(n);
    for (int k = 0; k < 5; ++k) {
        Vector3d aim(p);
        if (k > 0) aim += delta * (k & 1 ? 1.0 : -1.0) * Vector3d(k < 3 ? f.s : f.t);
        Ray r{Point3f(aim - h * Vector3d(w)), w, Infinity};
        for (const SurfaceInteraction& x : traceAll(s, r)) {
            double along = glm::dot(Vector3d(x.p) - Vector3d(r.o), Vector3d(w));
            if (along > 3.0 * h) break;
            if (glm::length(Vector3d(x.p) - Vector3d(p)) <= s.tolerance(p) + (k > 0 ? 2.0 * delta : 0.0)) return x;
        }
    }
    return std::nullopt;
}

/// The surface of the bounding box K, sampled uniformly by area: where the lines of the
/// area checks enter K, and the targets of the directions that measure solid angles.
struct BoxSurface {
    Vector3d lo, ext;
    double faces[3], S;
    explicit BoxSurface(const BBox3f& b) : lo(b.min), ext(Vector3d(b.max) - Vector3d(b.min)) {
        faces[0] = ext.y * ext.z, faces[1] = ext.z * ext.x, faces[2] = ext.x * ext.y;
        S = 2.0 * (faces[0] + faces[1] + faces[2]);
    }
    /// A uniform point of the surface, on the face across `axis` (`upper` or lower).
    Vector3d sample(PCG32& rng, int& axis, bool& upper) const {
        double pick = rng.nextDouble() * 0.5 * S;
        axis = pick < faces[0] ? 0 : pick < faces[0] + faces[1] ? 1 : 2;
        upper = rng.nextFloat() < 0.5f;
        Vector3d q = lo + Vector3d(rng.nextDouble(), rng.nextDouble(), rng.nextDouble()) * ext;
        q[axis] = lo[axis] + (upper ? ext[axis] : 0.0);
        return q;
    }
    /// Solid-angle density, seen from ref, of the direction to a uniform surface point:
    /// Σ d² / (S |cos|) over where the ray ref + t w (t > 0) crosses the box's surface.
    double directionPdf(const Vector3d& ref, const Vector3d& w) const {
        double tIn = -HUGE_VAL, tOut = HUGE_VAL;
        int aIn = 0, aOut = 0;
        for (int a = 0; a < 3; ++a) {
            if (w[a] == 0.0) {
                if (ref[a] < lo[a] || ref[a] > lo[a] + ext[a]) return 0.0;
                continue;
            }
            double t0 = (lo[a] - ref[a]) / w[a], t1 = (lo[a] + ext[a] - ref[a]) / w[a];
            if (t0 > t1) std::swap(t0, t1);
            if (t0 > tIn) tIn = t0, aIn = a;
            if (t1 < tOut) tOut = t1, aOut = a;
        }
        if (!(tOut >= tIn) || !(tOut > 0.0)) return 0.0;
        double sum = tOut * tOut / std::abs(w[aOut]);
        if (tIn > 0.0) sum += tIn * tIn / std::abs(w[aIn]);
        return sum / S;
    }
};

inline Point2f uniform2(PCG32& rng) { return {rng.nextFloat(), rng.nextFloat()}; }

inline std::string str(const Point3f& p) { return fmt::format("({:.7g}, {:.7g}, {:.7g})", p.x, p.y, p.z); }

/// Two independent estimates of one quantity (means with standard errors) agree up to a
/// relative slack: two-sided z-test of |a − b| ≤ slack · |b| (p = 1 inside the band).
double agreementPValue(double a, double seA, double b, double seB, double slack);

/// A deterministic check's row; for a shape whose sampling is a documented approximation
/// (Setup::approximate) the checks of where its samples lie are reported, not judged.
inline void judge(Target& t, const Setup& s, const std::string& check, bool ok, std::string figure, std::string detail) {
    if (s.approximate.empty()) t.expect(check, ok, std::move(figure), std::move(detail));
    else t.info(check, std::move(figure), detail + "; not judged: " + s.approximate);
}

/// Intersections, area and sampling density against ray casting (shape_measure.cpp).
void checkArea(Target& t, const Setup& s, std::optional<double> analytic);
/// sampleDirection() from reference points: pdf values, E[1/pdf], chi-square (shape_directions.cpp).
void checkDirections(Target& t, const Setup& s);

} // namespace effigi::conform::shape
