// cylinder — an analytic open cylinder (a tube without end caps), Mitsuba's `cylinder`;
// with caps = true it is closed by two end disks and bounds a solid (what `csg` needs).
//
// Parameters: p0, p1 (object-space end points of the axis, default (0,0,0) and (0,0,1)),
// radius (default 1), caps (default false, as Mitsuba's cylinder has none), to_world,
// flip_normals, nested bsdf and emitter.
// In its own frame the cylinder is x² + y² = 1, 0 <= z <= 1; the object-to-world map
// is to_world · translate(p0) · frame(p1 - p0) · scale(radius, radius, |p1 - p0|), and it
// must keep the cross-section a circle and the axis perpendicular to it (rotations,
// translations, scales that are uniform across the axis; the length may scale freely).
// uv = (φ / 2π, z) with dp/du = 2π (-y, x, 0), dp/dv = (0, 0, 1) mapped to the world, as
// in Mitsuba. Normals point away from the axis (inward with flip_normals).
// Caps (an effigi extension): the disks z = 0 (normal −axis) and z = 1 (normal +axis),
// uv = (φ / 2π, ρ) with ρ the distance from the axis over the radius.
// Sampled uniformly by area: z and φ are uniform, the area element is constant; with
// caps, u.x first picks the tube or a cap by area, a cap point is a concentric-map sample.
// Reference: Mitsuba 3 documentation, "Cylinder (cylinder)"; M. Pharr, W. Jakob,
// G. Humphreys, Physically Based Rendering, 4th ed., §6.3 (cylinders).
#include "effigi/core/registry.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/render/shape_base.hpp"

namespace effigi {
namespace {

class Cylinder final : public ShapeBase {
public:
    static Schema schema() {
        Schema s("shape", "cylinder",
                 "Analytic cylinder between p0 and p1: an open tube (as Mitsuba's), closed by end disks with caps.");
        s.cite("Mitsuba 3 documentation, Cylinder; Pharr, Jakob, Humphreys, PBRT 4th ed., §6.3");
        s.point("p0", Point3f(0.f), "Object-space start of the axis");
        s.point("p1", Point3f(0.f, 0.f, 1.f), "Object-space end of the axis (distinct from p0)");
        s.real("radius", 1.0, "Radius in object space (> 0)").atLeast(0.0).withUnit("scene units");
        s.boolean("caps", false, "Close both ends with disks: a solid, e.g. for csg (not in Mitsuba)");
        addCommonParams(s);
        // effigi-conform: a needle, a wide squat ring, inward normals, a tilted axis; closed
        // by caps, upright and tilted.
        s.addConformance({"default", {}});
        s.addConformance({"thin", {{"radius", 1e-3}}});
        s.addConformance({"wide", {{"radius", 1e3}}});
        s.addConformance({"flat ring", {{"radius", 10.0}, {"p1", PointValue{{0.f, 0.f, 1e-3f}}}}});
        s.addConformance({"tilted flipped", {{"p0", PointValue{{1.f, -1.f, 0.5f}}}, {"p1", PointValue{{-2.f, 3.f, 1.f}}},
                                             {"radius", 0.3}, {"flip_normals", true}}});
        s.addConformance({"capped", {{"caps", true}}});
        s.addConformance({"capped tilted", {{"p0", PointValue{{1.f, -1.f, 0.5f}}}, {"p1", PointValue{{-4.f, 5.f, 1.f}}},
                                            {"radius", 0.5}, {"caps", true}}});
        return s;
    }

    explicit Cylinder(const Properties& p) : ShapeBase(p), m_caps(p.getBool("caps")) {
        float r = p.getFloat("radius");
        if (!(r > 0.f) || !std::isfinite(r))
            failAt(p.whereOf("radius"), "{}: parameter 'radius' must be a positive number, got {}", p.describe(), r);
        Point3f p0 = p.getPoint("p0"), p1 = p.getPoint("p1");
        Vector3f axis = p1 - p0;
        float len = length(axis);
        if (!(len > 0.f) || !std::isfinite(len))
            failAt(p.whereOf("p1"), "{}: parameters 'p0' and 'p1' must be distinct finite points", p.describe());
        Frame f(axis / len);
        glm::mat4 local(1.f);  // unit cylinder -> object space
        local[0] = glm::vec4(f.s * r, 0.f);
        local[1] = glm::vec4(f.t * r, 0.f);
        local[2] = glm::vec4(axis, 0.f);
        local[3] = glm::vec4(p0, 1.f);
        glm::mat4 m = m_toWorld.matrix() * local;
        m_center = Point3f(m[3]);
        m_ex = Vector3f(m[0]);
        m_ey = Vector3f(m[1]);
        m_ez = Vector3f(m[2]);
        m_radius = length(m_ex);
        m_length = length(m_ez);
        // A circle stays a circle and the axis stays perpendicular to it only if the
        // three columns are orthogonal and the first two equally long (Mitsuba rejects
        // the other transforms as well).
        float tol = 1e-4f;
        bool ok = isFinite(m_center) && isFinite(m_ex) && isFinite(m_ey) && isFinite(m_ez) && m_radius > 0.f &&
                  m_length > 0.f && std::isfinite(m_radius * m_radius * m_length) && m[0][3] == 0.f &&
                  m[1][3] == 0.f && m[2][3] == 0.f && m[3][3] == 1.f &&
                  std::abs(length(m_ey) - m_radius) <= tol * m_radius &&
                  std::abs(dot(m_ex, m_ey)) <= tol * m_radius * m_radius &&
                  std::abs(dot(m_ex, m_ez)) <= tol * m_radius * m_length &&
                  std::abs(dot(m_ey, m_ez)) <= tol * m_radius * m_length;
        if (!ok)
            failAt(p.whereOf("to_world"), "{}: parameter 'to_world' must keep the cylinder circular and upright "
                                          "(no shear, equal scale across the axis)", p.describe());
        attachEmitter();
    }

    BBox3f bbox() const override {
        // The two end circles bound the tube; a circle's half-extent along axis i is
        // sqrt(ex_i² + ey_i²).
        Vector3f h = glm::sqrt(m_ex * m_ex + m_ey * m_ey);
        Point3f c1 = m_center + m_ez;
        return {glm::min(m_center, c1) - h, glm::max(m_center, c1) + h};
    }
    float area() const override { return tubeArea() + (m_caps ? 2.f * capArea() : 0.f); }

    bool intersect(const Ray& ray, float& t, Point2f& uv) const override {
        double th;
        Vector3d q;
        if (!hitDistance(ray, th, q)) return false;
        t = float(th);
        if (!(t > 0.f) || !(t < ray.tMax)) return false;
        uv = param(q);
        return true;
    }

    SurfaceInteraction interaction(const Ray& ray, const Hit& hit) const override {
        SurfaceInteraction si;
        Vector3d q = toLocal(Vector3d(ray.o) + double(hit.t) * Vector3d(ray.d));
        si.t = hit.t;
        si.prim = 0;
        double rl = std::sqrt(q.x * q.x + q.y * q.y);
        if (int cap = nearestCap(q, rl); cap >= 0) {
            if (rl > 1.0) q.x /= rl, q.y /= rl;  // back onto the disk
            q.z = double(cap);
            fillCap(q, si);
            finish(si, ray);
            return si;
        }
        // Back onto the surface: o + t·d is off by the rounding of t.
        if (rl > 0.0) q.x /= rl, q.y /= rl;
        else q.x = 1.0, q.y = 0.0;
        q.z = std::clamp(q.z, 0.0, 1.0);
        fill(q, si.p, si.n, si.uv);
        si.dpdu = 2.f * Pi * (float(-q.y) * m_ex + float(q.x) * m_ey);
        si.dpdv = m_ez;
        si.primUV = si.uv;
        Vector3f s = normalize(si.dpdu);
        si.shading = Frame(s, cross(si.n, s), si.n);
        finish(si, ray);
        return si;
    }

    /// On the tube n = ±(x·ex + y·ey) / r, so ∂n/∂u = ±(∂p/∂u) / r and ∂n/∂v = 0 (curvature
    /// 1/r around, 0 along the axis); the caps are flat.
    LocalGeometry localGeometry(const SurfaceInteraction& si) const override {
        LocalGeometry g = ShapeBase::localGeometry(si);
        if (std::abs(dot(si.n, m_ez)) > 0.5f * m_length) return g;  // a cap: n along the axis
        g.dndu = si.dpdu * ((m_flipNormals ? -1.f : 1.f) / m_radius);
        return g;
    }

    PositionSample samplePosition(const Point2f& u) const override {
        PositionSample ps;
        ps.pdf = 1.f / area();
        float ux = u.x;
        if (m_caps) {
            // u.x picks the tube or a cap by area, and what is left of it places the point.
            double total = double(area()), x = double(u.x) * total, tube = double(tubeArea()), cap = double(capArea());
            if (x >= tube) {
                double c = std::min((x - tube) / cap, 2.0 - 1e-7);
                int which = c < 1.0 ? 0 : 1;
                Point2f d = warp::squareToUniformDiskConcentric(
                    {std::clamp(float(c - which), 0.f, OneMinusEpsilon), u.y});
                SurfaceInteraction si;
                fillCap(Vector3d(d.x, d.y, double(which)), si);
                ps.p = si.p, ps.n = si.n, ps.uv = si.uv;
                return ps;
            }
            ux = std::clamp(float(x / tube), 0.f, 1.f);
        }
        double phi = 2.0 * double(Pi) * double(u.y);
        fill(Vector3d(std::cos(phi), std::sin(phi), double(ux)), ps.p, ps.n, ps.uv);
        return ps;
    }

private:
    /// World -> unit-cylinder coordinates; exact for the orthogonal columns checked above.
    Vector3d toLocal(const Vector3d& w) const {
        Vector3d d = w - Vector3d(m_center);
        double r2 = double(m_radius) * double(m_radius), l2 = double(m_length) * double(m_length);
        return {glm::dot(d, Vector3d(m_ex)) / r2, glm::dot(d, Vector3d(m_ey)) / r2, glm::dot(d, Vector3d(m_ez)) / l2};
    }
    Vector3d toLocalDir(const Vector3d& v) const {
        double r2 = double(m_radius) * double(m_radius), l2 = double(m_length) * double(m_length);
        return {glm::dot(v, Vector3d(m_ex)) / r2, glm::dot(v, Vector3d(m_ey)) / r2, glm::dot(v, Vector3d(m_ez)) / l2};
    }

    float tubeArea() const { return 2.f * Pi * m_radius * m_length; }
    float capArea() const { return Pi * m_radius * m_radius; }

    /// With caps: the cap (0 or 1) nearer than the tube to the unit-frame point q (rl its
    /// distance from the axis), distances measured in the world; otherwise -1.
    int nearestCap(const Vector3d& q, double rl) const {
        if (!m_caps) return -1;
        double tube = std::abs(rl - 1.0) * double(m_radius), c0 = std::abs(q.z) * double(m_length),
               c1 = std::abs(q.z - 1.0) * double(m_length);
        if (std::min(c0, c1) >= tube && rl >= 1e-9) return -1;
        return c0 <= c1 ? 0 : 1;
    }

    /// Surface of the cap point q (q.z = 0 or 1, x² + y² ≤ 1): outward normal along the
    /// axis, uv = (φ / 2π, ρ), ∂p/∂u around the axis and ∂p/∂v outward from it.
    void fillCap(const Vector3d& q, SurfaceInteraction& si) const {
        si.p = Point3f(Vector3d(m_center) + q.x * Vector3d(m_ex) + q.y * Vector3d(m_ey) + q.z * Vector3d(m_ez));
        si.n = (q.z > 0.5 ? 1.f : -1.f) * (m_ez / m_length);
        if (m_flipNormals) si.n = -si.n;
        double rho = std::sqrt(q.x * q.x + q.y * q.y);
        si.uv = Point2f(param(q).x, float(std::min(rho, 1.0)));
        si.primUV = si.uv;
        si.dpdu = 2.f * Pi * (float(-q.y) * m_ex + float(q.x) * m_ey);
        si.dpdv = rho > 0.0 ? float(q.x / rho) * m_ex + float(q.y / rho) * m_ey : m_ex;
        Vector3f s = length(si.dpdu) > 1e-6f * m_radius ? normalize(si.dpdu) : normalize(m_ex);
        si.shading = Frame(s, cross(si.n, s), si.n);
    }

    /// Closest t in (0, tMax) where the ray meets the tube (or, with caps, an end disk),
    /// in the unit frame (where t is the same as in the world), with the
    /// cancellation-free quadratic roots.
    bool hitDistance(const Ray& ray, double& tHit, Vector3d& q) const {
        Vector3d o = toLocal(Vector3d(ray.o)), d = toLocalDir(Vector3d(ray.d));
        double tMax = double(ray.tMax);
        bool found = false;
        if (m_caps && d.z != 0.0) {
            for (double z : {0.0, 1.0}) {
                double t = (z - o.z) / d.z;
                if (!(t > 0.0) || !(t < tMax)) continue;
                double x = o.x + t * d.x, y = o.y + t * d.y;
                if (x * x + y * y > 1.0) continue;
                tMax = tHit = t;
                q = Vector3d(x, y, z);
                found = true;
            }
        }
        double a = d.x * d.x + d.y * d.y;
        if (!(a > 0.0)) return found;  // parallel to the axis: never crosses the wall
        double b = o.x * d.x + o.y * d.y;  // half the linear coefficient
        // Discriminant as a·(1 − |perpendicular offset|²), stable for distant origins.
        double px = o.x - (b / a) * d.x, py = o.y - (b / a) * d.y;
        double disc = a * (1.0 - (px * px + py * py));
        if (disc < 0.0) return found;
        double c = o.x * o.x + o.y * o.y - 1.0;
        double qq = -(b + std::copysign(std::sqrt(disc), b));
        if (qq == 0.0) return found;  // grazing the wall exactly at the origin
        double t0 = c / qq, t1 = qq / a;
        if (t0 > t1) std::swap(t0, t1);
        for (double t : {t0, t1}) {
            if (!(t > 0.0) || !(t < tMax)) continue;
            double z = o.z + t * d.z;
            if (z < 0.0 || z > 1.0) continue;  // outside the finite tube: try the far root
            tHit = t;
            q = o + t * d;
            return true;
        }
        return found;
    }

    static Point2f param(const Vector3d& q) {
        float u = float(std::atan2(q.y, q.x) / (2.0 * double(Pi)));
        if (u < 0.f) u += 1.f;
        return {std::min(u, OneMinusEpsilon), float(std::clamp(q.z, 0.0, 1.0))};
    }

    /// Position, normal and uv of the unit-frame surface point q (x² + y² = 1).
    void fill(const Vector3d& q, Point3f& p, Normal3f& n, Point2f& uv) const {
        p = Point3f(Vector3d(m_center) + q.x * Vector3d(m_ex) + q.y * Vector3d(m_ey) + q.z * Vector3d(m_ez));
        // ex and ey are orthogonal and of length radius: the radial direction is the normal.
        n = normalize(float(q.x) * m_ex + float(q.y) * m_ey);
        if (m_flipNormals) n = -n;
        uv = param(q);
    }

    Point3f m_center{0.f};
    Vector3f m_ex{1.f, 0.f, 0.f}, m_ey{0.f, 1.f, 0.f}, m_ez{0.f, 0.f, 1.f};
    float m_radius = 1.f, m_length = 1.f;
    bool m_caps = false;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Cylinder)
