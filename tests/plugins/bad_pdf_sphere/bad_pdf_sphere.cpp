// shape "bad_pdf_sphere" — DELIBERATELY WRONG test plugin: an analytic sphere, sampled
// uniformly by area, whose samplePosition() reports the density 1/(4π r) where 1/(4π r²)
// is right (the radius is not squared).
//
// Intersection, normals, area() and the sampled points themselves are right, and at the
// default radius 1 the two densities agree, so the "default" configuration passes every
// check; only the configurations of other radii (0.25, 4) can see the bug. There the
// shape suite's "position pdf" must catch it (pdf · area() = r, not 1), and "sampling
// density" can (E[1/pdf] is 4π r against the 4π r² ray casting measures). Directions are
// sampled by IShape's default (area samples converted with this pdf, while
// pdfDirection() converts 1/area()), so "direction pdf" and "direction E[1/pdf]" may
// fail too (tests/plugins/run_plugin_tests.cmake).
#include "effigi/core/registry.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/render/shape_base.hpp"

#include <cmath>
#include <utility>

namespace {
using namespace effigi;

class BadPdfSphere final : public ShapeBase {
public:
    static Schema schema() {
        Schema s("shape", "bad_pdf_sphere", "Test plugin: a sphere whose area pdf is 1/(4π r), not 1/(4π r²).");
        s.point("center", Point3f(0.f), "Centre");
        s.real("radius", 1.0, "Radius r").range(1e-3, 1e3).withUnit("scene units");
        s.child("bsdf", "bsdf", "Surface scattering (default: a diffuse BSDF)");
        s.child("emitter", "emitter", "Area emitter that makes this sphere a light (optional)");
        s.addConformance({"default", {}});
        s.addConformance({"small", {{"radius", 0.25}}});
        s.addConformance({"large", {{"center", PointValue{Point3f(1.f, -2.f, 0.5f)}}, {"radius", 4.0}}});
        return s;
    }

    explicit BadPdfSphere(const Properties& p)
        : ShapeBase(p), m_center(p.getPoint("center")), m_radius(float(p.getFloat("radius"))) {
        attachEmitter();
    }

    BBox3f bbox() const override { return {m_center - Vector3f(m_radius), m_center + Vector3f(m_radius)}; }
    float area() const override { return 4.f * Pi * m_radius * m_radius; }

    /// The nearer root of |o + t d − c|² = r² in (0, tMax), in double with the stable
    /// form of the quadratic (Haines et al., Ray Tracing Gems ch. 7).
    bool intersect(const Ray& ray, float& t, Point2f& uv) const override {
        const Vector3d o = Vector3d(ray.o) - Vector3d(m_center), d(ray.d);
        const double a = glm::dot(d, d), b = glm::dot(o, d), r2 = double(m_radius) * double(m_radius);
        const Vector3d perp = o - (b / a) * d;
        const double disc = a * (r2 - glm::dot(perp, perp));
        if (!(a > 0.0) || disc < 0.0) return false;
        const double q = -(b + std::copysign(std::sqrt(disc), b));
        if (q == 0.0) return false;
        double t0 = (glm::dot(o, o) - r2) / q, t1 = q / a;
        if (t0 > t1) std::swap(t0, t1);
        for (double th : {t0, t1})
            if (float(th) > 0.f && float(th) < ray.tMax) {
                t = float(th), uv = Point2f(0.f);  // interaction() computes uv
                return true;
            }
        return false;
    }

    SurfaceInteraction interaction(const Ray& ray, const Hit& hit) const override {
        // Project o + t d onto the sphere: t carries a float rounding.
        Vector3d w = Vector3d(ray.o) - Vector3d(m_center) + double(hit.t) * Vector3d(ray.d);
        SurfaceInteraction si;
        fill(Vector3f(glm::normalize(w)), si.p, si.n, si.uv);
        si.shading = Frame(si.n);
        si.t = hit.t;
        finish(si, ray);
        return si;
    }

    PositionSample samplePosition(const Point2f& u) const override {
        PositionSample ps;
        fill(warp::squareToUniformSphere(u), ps.p, ps.n, ps.uv);
        ps.pdf = 1.f / (4.f * Pi * m_radius);  // the bug: 1 / (4π r²) is the uniform density
        return ps;
    }

private:
    /// Point, outward normal and (φ/2π, θ/π) of the unit direction w from the centre.
    void fill(const Vector3f& w, Point3f& p, Normal3f& n, Point2f& uv) const {
        p = m_center + m_radius * w;
        n = w;
        float phi = std::atan2(w.y, w.x) * Inv2Pi;
        uv = Point2f(phi < 0.f ? phi + 1.f : phi, std::acos(std::clamp(w.z, -1.f, 1.f)) * InvPi);
    }

    Point3f m_center;
    float m_radius;
};

} // namespace

EFFIGI_EXPORT_COMPONENT(BadPdfSphere)
