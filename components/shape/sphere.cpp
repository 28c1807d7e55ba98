// sphere — an analytic sphere, intersected exactly rather than tessellated.
//
// Parameters: center (point, default 0,0,0), radius (default 1), to_world (applied to
// the center; it may rotate, translate and scale uniformly, the radius is multiplied by
// the scale), flip_normals (normals point inward), nested bsdf and emitter.
// uv = (φ / 2π, θ / π) in the sphere's object frame (z is the polar axis).
// Seen from outside, points are sampled uniformly in the cone of directions the sphere
// subtends, which makes small or distant spherical lights nearly noise-free; from inside,
// by area.
// Reference: Mitsuba 3 documentation, "Sphere (sphere)"; cone sampling after J. Shirley,
// C. Wang, K. Zimmerman, "Monte Carlo Techniques for Direct Lighting Calculations", ACM TOG 1996;
// intersection after Haines et al., "Precision Improvements for Ray/Sphere Intersection",
// Ray Tracing Gems, ch. 7, 2019.
#include "effigi/core/registry.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/render/shape_base.hpp"

namespace effigi {
namespace {

class Sphere final : public ShapeBase {
public:
    static Schema schema() {
        Schema s("shape", "sphere", "Analytic sphere; sampled by solid angle as seen from outside.");
        s.cite("Haines et al., Precision Improvements for Ray/Sphere Intersection, Ray Tracing Gems ch. 7, 2019");
        s.point("center", Point3f(0.f), "Center in object space");
        s.real("radius", 1.0, "Radius in object space").withUnit("scene units");
        addCommonParams(s);
        // effigi-conform: tiny and huge radii, inward normals, far from the origin (rotated).
        s.addConformance({"default", {}});
        s.addConformance({"small", {{"radius", 1e-3}}});
        s.addConformance({"large", {{"radius", 1e4}}});
        s.addConformance({"flipped", {{"flip_normals", true}}});
        s.addConformance({"far", {{"radius", 0.5}, {"to_world", Transform::translate({1e3f, -2e3f, 5e2f}) *
                                                                   Transform::rotate({1.f, 2.f, 3.f}, 40.f)}}});
        return s;
    }

    explicit Sphere(const Properties& p) : ShapeBase(p) {
        float r = p.has("radius") ? p.getFloat("radius") : 1.f;
        Point3f c = p.has("center") ? p.getPoint("center") : Point3f(0.f);
        if (!(r > 0.f) || !std::isfinite(r))
            failAt(p.whereOf("radius"), "{}: parameter 'radius' must be a positive number, got {}", p.describe(), r);

        // to_world must be a similarity (rotation · uniform scale · translation): only then
        // is the image of a sphere a sphere.
        const glm::mat4& m = m_toWorld.matrix();
        glm::mat3 lin(m);
        float scale = std::cbrt(std::abs(glm::determinant(lin)));
        bool similarity = m_toWorld.isFinite() && scale > 0.f && std::isfinite(scale) && m[0][3] == 0.f &&
                          m[1][3] == 0.f && m[2][3] == 0.f && m[3][3] == 1.f;
        for (int i = 0; similarity && i < 3; ++i)
            for (int j = 0; j < 3; ++j) {
                float expect = i == j ? scale * scale : 0.f;
                if (std::abs(dot(lin[i], lin[j]) - expect) > 1e-4f * scale * scale) similarity = false;
            }
        if (!similarity)
            failAt(p.whereOf("to_world"),
                   "{}: parameter 'to_world' must be a rotation, uniform scale and translation "
                   "(a sphere cannot be scaled non-uniformly; use an ellipsoid mesh instead)",
                   p.describe());
        m_rotation = lin / scale;
        m_center = m_toWorld.point(c);
        m_radius = r * scale;
        if (!isFinite(m_center) || !std::isfinite(m_radius) || !(m_radius > 0.f))
            failAt(p.whereOf("to_world"), "{}: center or radius is not finite after 'to_world'", p.describe());
        attachEmitter();
    }

    BBox3f bbox() const override { return {m_center - Vector3f(m_radius), m_center + Vector3f(m_radius)}; }
    float area() const override { return 4.f * Pi * m_radius * m_radius; }

    bool intersect(const Ray& ray, float& t, Point2f& uv) const override {
        double th;
        if (!hitDistance(ray, th)) return false;
        t = float(th);
        if (!(t > 0.f) || !(t < ray.tMax)) return false;
        Vector3d w = Vector3d(ray.o) - Vector3d(m_center) + th * Vector3d(ray.d);
        uv = param(Vector3f(glm::normalize(w)));
        return true;
    }

    SurfaceInteraction interaction(const Ray& ray, const Hit& hit) const override {
        SurfaceInteraction si;
        // Reproject onto the surface: o + t·d is off by the rounding of t.
        Vector3d wd = Vector3d(ray.o) - Vector3d(m_center) + double(hit.t) * Vector3d(ray.d);
        double l = glm::length(wd);
        Vector3f w = l > 0.0 ? Vector3f(wd / l) : Vector3f(0.f, 0.f, 1.f);
        si.p = Point3f(Vector3d(m_center) + double(m_radius) * Vector3d(w));
        si.t = hit.t;
        si.prim = 0;
        fillSurface(w, si.n, si.shading, si.uv);
        // ∂p/∂u, ∂p/∂v of uv = (φ/2π, θ/π) for bump maps; left zero at the poles.
        Vector3f q = glm::transpose(m_rotation) * w;
        float sinTheta = std::sqrt(q.x * q.x + q.y * q.y);
        if (sinTheta > 1e-6f) {
            si.dpdu = m_rotation * Vector3f(-q.y, q.x, 0.f) * (2.f * Pi * m_radius);
            si.dpdv = m_rotation * Vector3f(q.z * q.x / sinTheta, q.z * q.y / sinTheta, -sinTheta) * (Pi * m_radius);
        }
        finish(si, ray);
        return si;
    }

    /// n = ±(p − center) / radius, so ∂n/∂u = ±(∂p/∂u) / radius (likewise v): curvature
    /// 1/r in every direction, negative with flip_normals. objectP: ShapeBase's inverse
    /// of to_world.
    LocalGeometry localGeometry(const SurfaceInteraction& si) const override {
        LocalGeometry g = ShapeBase::localGeometry(si);
        const float k = (m_flipNormals ? -1.f : 1.f) / m_radius;
        g.dndu = si.dpdu * k;
        g.dndv = si.dpdv * k;
        return g;
    }

    PositionSample samplePosition(const Point2f& u) const override {
        PositionSample ps;
        Vector3f w = warp::squareToUniformSphere(u);
        ps.p = m_center + m_radius * w;
        Frame f;
        fillSurface(w, ps.n, f, ps.uv);
        ps.pdf = 1.f / area();
        return ps;
    }

    DirectionSample sampleDirection(const Point3f& ref, const Point2f& u) const override {
        Cone cone;
        if (!visibleCone(ref, cone)) return IShape::sampleDirection(ref, u);
        // Direction at angle θ from the axis ref -> center, uniform in the cone.
        double oneMinusCos = double(u.x) * cone.oneMinusCosMax;
        double sin2 = oneMinusCos * (2.0 - oneMinusCos), cosT = 1.0 - oneMinusCos;
        // The nearer hit of that direction, as the angle α at the center between the
        // axis toward ref and the hit point (law of sines in the triangle ref, center, hit).
        double cosAlpha = sin2 / cone.sinMax + cosT * std::sqrt(std::max(0.0, 1.0 - sin2 / cone.sin2Max));
        double sinAlpha = std::sqrt(std::max(0.0, 1.0 - cosAlpha * cosAlpha));
        double phi = 2.0 * double(Pi) * double(u.y);
        Vector3f s, t;
        coordinateSystem(cone.axis, s, t);
        Vector3f w = normalize(float(sinAlpha * std::cos(phi)) * s + float(sinAlpha * std::sin(phi)) * t +
                               float(cosAlpha) * cone.axis);

        DirectionSample ds;
        ds.p = m_center + m_radius * w;
        Frame f;
        fillSurface(w, ds.n, f, ds.uv);
        Vector3f d = ds.p - ref;
        ds.dist = length(d);
        ds.wi = ds.dist > 0.f ? d / ds.dist : -cone.axis;
        ds.pdf = cone.pdf;
        return ds;
    }

    float pdfDirection(const Point3f& ref, const SurfaceInteraction& si) const override {
        Cone cone;
        if (!visibleCone(ref, cone)) return IShape::pdfDirection(ref, si);
        return cone.pdf;
    }

private:
    struct Cone {
        Vector3f axis;  // unit, from the center toward ref
        double sin2Max, sinMax, oneMinusCosMax;
        float pdf;
    };

    /// The cone of directions from ref that hit the sphere; false when ref is inside
    /// (or the cone is numerically degenerate), where area sampling takes over.
    bool visibleCone(const Point3f& ref, Cone& c) const {
        Vector3d toRef = Vector3d(ref) - Vector3d(m_center);
        double d2 = glm::dot(toRef, toRef), r2 = double(m_radius) * double(m_radius);
        if (!(d2 > r2)) return false;
        c.sin2Max = r2 / d2;
        c.sinMax = std::sqrt(c.sin2Max);
        // 1 - cos θmax without cancellation for distant spheres.
        c.oneMinusCosMax = c.sin2Max / (1.0 + std::sqrt(std::max(0.0, 1.0 - c.sin2Max)));
        double pdf = 1.0 / (2.0 * double(Pi) * c.oneMinusCosMax);
        if (!(pdf < double(std::numeric_limits<float>::max()))) return false;
        c.pdf = float(pdf);
        c.axis = Vector3f(toRef / std::sqrt(d2));
        return true;
    }

    /// Closest t in (0, tMax) with the stable quadratic form; the discriminant is taken
    /// as r² - |perpendicular offset|² (Ray Tracing Gems ch. 7), all in double.
    bool hitDistance(const Ray& ray, double& tHit) const {
        Vector3d o = Vector3d(ray.o) - Vector3d(m_center), d(ray.d);
        double a = glm::dot(d, d);
        if (!(a > 0.0)) return false;
        double b = glm::dot(o, d);  // half the linear coefficient
        double r2 = double(m_radius) * double(m_radius);
        double c = glm::dot(o, o) - r2;
        Vector3d perp = o - (b / a) * d;
        double disc = a * (r2 - glm::dot(perp, perp));
        if (disc < 0.0) return false;
        double q = -(b + std::copysign(std::sqrt(disc), b));
        if (q == 0.0) return false;  // tangent at the origin itself
        double t0 = c / q, t1 = q / a;
        if (t0 > t1) std::swap(t0, t1);
        double tMax = double(ray.tMax);
        if (t0 > 0.0 && t0 < tMax) tHit = t0;
        else if (t1 > 0.0 && t1 < tMax) tHit = t1;
        else return false;
        return true;
    }

    /// uv in the object frame from the outward unit direction w.
    Point2f param(const Vector3f& w) const {
        Vector3f l = glm::transpose(m_rotation) * w;
        float u = std::atan2(l.y, l.x) * Inv2Pi;
        if (u < 0.f) u += 1.f;
        return {std::min(u, OneMinusEpsilon), safeAcos(l.z) * InvPi};
    }

    /// Normal, shading frame (tangent along dp/dφ) and uv at the point in direction w.
    void fillSurface(const Vector3f& w, Normal3f& n, Frame& frame, Point2f& uv) const {
        uv = param(w);
        n = m_flipNormals ? -w : w;
        Vector3f l = glm::transpose(m_rotation) * w;
        Vector3f s = m_rotation * Vector3f(-l.y, l.x, 0.f);
        s -= n * dot(n, s);
        float s2 = dot(s, s);
        frame = s2 > 1e-12f ? Frame(s / std::sqrt(s2), cross(n, s / std::sqrt(s2)), n) : Frame(n);
    }

    Point3f m_center{0.f};
    float m_radius = 1.f;
    glm::mat3 m_rotation{1.f};  // object frame -> world (orthonormal)
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Sphere)
