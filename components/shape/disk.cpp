// disk — an analytic disk: unit radius, centred at the origin in the z = 0 plane,
// normal +z (inverse transpose of to_world in world space).
//
// Parameters: to_world (any affine map: a non-uniform scale gives an ellipse),
// flip_normals, nested bsdf and emitter. uv = (r, φ / 2π) in object space.
// Sampled uniformly by area (concentric map, Shirley & Chiu 1997).
// Reference: Mitsuba 3 documentation, "Disk (disk)".
#include "effigi/core/registry.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/render/shape_base.hpp"

namespace effigi {
namespace {

class Disk final : public ShapeBase {
public:
    static Schema schema() {
        Schema s("shape", "disk", "Analytic unit disk in the z = 0 plane with normal +z.");
        s.cite("P. Shirley, K. Chiu, A Low Distortion Map Between Disk and Square, JGT 2(3), 1997");
        addCommonParams(s);
        // effigi-conform: a needle-thin ellipse, tiny and huge, mirrored with inward normals.
        s.addConformance({"default", {}});
        s.addConformance({"thin ellipse", {{"to_world", Transform::scale({1e-3f, 10.f, 1.f})}}});
        s.addConformance({"tiny", {{"to_world", Transform::scale(Vector3f(1e-4f))}}});
        s.addConformance({"huge", {{"to_world", Transform::scale(Vector3f(1e4f))}}});
        s.addConformance({"mirrored flipped", {{"to_world", Transform::rotate({1.f, 1.f, 0.f}, 60.f) *
                                                                Transform::scale({-1.f, 1.f, 1.f})},
                                               {"flip_normals", true}}});
        return s;
    }

    explicit Disk(const Properties& p) : ShapeBase(p) {
        const glm::mat4& m = m_toWorld.matrix();
        m_center = Point3f(m[3]);
        m_ex = Vector3f(m[0]);
        m_ey = Vector3f(m[1]);
        Vector3f c = cross(m_ex, m_ey);
        float cl = length(c);
        bool ok = isFinite(m_center) && isFinite(m_ex) && isFinite(m_ey) && m[0][3] == 0.f && m[1][3] == 0.f && m[2][3] == 0.f && m[3][3] == 1.f &&
                  cl > 0.f && std::isfinite(cl);
        if (!ok)
            failAt(p.whereOf("to_world"), "{}: parameter 'to_world' must be an affine map that keeps the disk "
                                          "two-dimensional", p.describe());
        // (The inverse of to_world is not needed: a flat scale z = 0 is fine here.)
        // Normals map with the inverse transpose, whose image of +z is cross(ex, ey)/det:
        // a mirroring to_world turns the normal around, as for meshes.
        float det = glm::determinant(glm::mat3(m));
        m_normal = (det < 0.f ? -1.f : 1.f) * c / cl;
        if (m_flipNormals) m_normal = -m_normal;
        m_area = Pi * cl;
        // Inverse of the Gram matrix of (ex, ey): world offsets in the plane -> (x, y).
        double xx = glm::dot(Vector3d(m_ex), Vector3d(m_ex)), xy = glm::dot(Vector3d(m_ex), Vector3d(m_ey)),
               yy = glm::dot(Vector3d(m_ey), Vector3d(m_ey));
        double g = xx * yy - xy * xy;
        m_gramInv[0] = yy / g;
        m_gramInv[1] = -xy / g;
        m_gramInv[2] = xx / g;
        attachEmitter();
    }

    BBox3f bbox() const override {
        // Exact bounds of an ellipse: half-extent sqrt(ex_i² + ey_i²) along each axis.
        Vector3f h = glm::sqrt(m_ex * m_ex + m_ey * m_ey);
        return {m_center - h, m_center + h};
    }
    float area() const override { return m_area; }

    bool intersect(const Ray& ray, float& t, Point2f& uv) const override {
        Vector3d o = Vector3d(ray.o) - Vector3d(m_center), d(ray.d), n(m_normal);
        double dn = glm::dot(d, n);
        if (dn == 0.0) return false;
        double th = -glm::dot(o, n) / dn;
        if (!(th > 0.0) || !(th < double(ray.tMax))) return false;
        double x, y;
        local(o + th * d, x, y);
        if (x * x + y * y > 1.0) return false;
        t = float(th);
        if (!(t > 0.f) || !(t < ray.tMax)) return false;
        uv = param(x, y);
        return true;
    }

    SurfaceInteraction interaction(const Ray& ray, const Hit& hit) const override {
        SurfaceInteraction si;
        double x, y;
        local(Vector3d(ray.o) - Vector3d(m_center) + double(hit.t) * Vector3d(ray.d), x, y);
        si.p = point(x, y);  // back onto the plane
        si.t = hit.t;
        si.prim = 0;
        fillSurface(x, y, si.n, si.shading, si.uv);
        // ∂p/∂u, ∂p/∂v of uv = (r, φ/2π) for bump maps; left zero at the centre.
        if (double r = std::sqrt(x * x + y * y); r > 1e-7) {
            si.dpdu = float(x / r) * m_ex + float(y / r) * m_ey;
            si.dpdv = (2.f * Pi) * (float(-y) * m_ex + float(x) * m_ey);
        }
        finish(si, ray);
        return si;
    }

    PositionSample samplePosition(const Point2f& u) const override {
        PositionSample ps;
        Point2f q = warp::squareToUniformDiskConcentric(u);
        ps.p = point(q.x, q.y);
        Frame f;
        fillSurface(q.x, q.y, ps.n, f, ps.uv);
        ps.pdf = 1.f / m_area;  // an affine map scales every area by the same factor
        return ps;
    }

private:
    /// Object-space (x, y) of a world offset from the center, projected onto the plane.
    void local(const Vector3d& q, double& x, double& y) const {
        double a = glm::dot(Vector3d(m_ex), q), b = glm::dot(Vector3d(m_ey), q);
        x = m_gramInv[0] * a + m_gramInv[1] * b;
        y = m_gramInv[1] * a + m_gramInv[2] * b;
    }
    Point3f point(double x, double y) const {
        return Point3f(Vector3d(m_center) + x * Vector3d(m_ex) + y * Vector3d(m_ey));
    }
    static Point2f param(double x, double y) {
        float v = float(std::atan2(y, x) / (2.0 * double(Pi)));
        if (v < 0.f) v += 1.f;
        return {float(std::sqrt(x * x + y * y)), std::min(v, OneMinusEpsilon)};
    }
    void fillSurface(double x, double y, Normal3f& n, Frame& frame, Point2f& uv) const {
        uv = param(x, y);
        n = m_normal;
        Vector3f s = float(-y) * m_ex + float(x) * m_ey;  // dp/dφ
        s -= n * dot(n, s);
        float s2 = dot(s, s);
        frame = s2 > 1e-12f * m_area ? Frame(s / std::sqrt(s2), cross(n, s / std::sqrt(s2)), n) : Frame(n);
    }

    Point3f m_center{0.f};
    Vector3f m_ex{1.f, 0.f, 0.f}, m_ey{0.f, 1.f, 0.f};
    Normal3f m_normal{0.f, 0.f, 1.f};
    float m_area = Pi;
    double m_gramInv[3] = {1.0, 0.0, 1.0};
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Disk)
