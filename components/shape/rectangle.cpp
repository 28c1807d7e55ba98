// rectangle — the square [-1,1]² in the z = 0 plane, normal +z, as two triangles.
//
// Parameters: to_world (place, size and orient it: a scale of (w/2, h/2, 1) gives a
// w × h rectangle), flip_normals, face_normals, nested bsdf and emitter.
// uv = ((x+1)/2, (y+1)/2). Mitsuba 3's `rectangle` has the same geometry, so a scene
// renders alike in both. Points are sampled as Mitsuba samples them, p = corner + u.x e1 +
// u.y e2 over the placed parallelogram (uniform, and one smooth map of u, so stratified
// samples stay stratified), instead of picking one of the two triangles: no search, no
// square root (a rectangular light is sampled at every bounce). Hits take the plane's
// constant normal, tangents and shading frame, computed once, instead of interpolating
// and normalising vertex normals at every hit (walls and lights are rectangles in most
// scenes). A to_world that is not affine leaves a quad that is no parallelogram; it is
// sampled and shaded as the mesh.
// Reference: Mitsuba 3 plugin documentation, "Rectangle (rectangle)".
#include "effigi/core/registry.hpp"
#include "effigi/render/shape_base.hpp"

namespace effigi {
namespace {

class Rectangle final : public MeshShape {
public:
    static Schema schema() {
        Schema s("shape", "rectangle", "Square [-1,1]² in the z = 0 plane with normal +z (two triangles).");
        s.cite("Mitsuba 3 documentation, rectangle shape");
        addMeshParams(s);
        // effigi-conform: a sliver, tiny and huge, rotated with inward normals.
        s.addConformance({"default", {}});
        s.addConformance({"sliver", {{"to_world", Transform::scale({1e2f, 1e-2f, 1.f})}}});
        s.addConformance({"tiny", {{"to_world", Transform::scale(Vector3f(1e-4f))}}});
        s.addConformance({"huge", {{"to_world", Transform::scale(Vector3f(1e4f))}}});
        s.addConformance({"rotated flipped", {{"to_world", Transform::rotate({0.3f, 1.f, 0.2f}, 75.f)}, {"flip_normals", true}}});
        return s;
    }

    explicit Rectangle(const Properties& p) : MeshShape(p) {
        TriangleMesh m;
        m.positions = {{-1.f, -1.f, 0.f}, {1.f, -1.f, 0.f}, {1.f, 1.f, 0.f}, {-1.f, 1.f, 0.f}};
        m.normals.assign(4, Normal3f(0.f, 0.f, 1.f));
        m.uvs = {{0.f, 0.f}, {1.f, 0.f}, {1.f, 1.f}, {0.f, 1.f}};
        // Both counter-clockwise seen from +z, so cross(p1-p0, p2-p0) points along +z.
        m.indices = {0, 1, 2, 2, 3, 0};
        setMesh(std::move(m), p.describe());
        // The placed corners 0, 1, 3 span the rectangle if corner 2 closes the parallelogram.
        const std::vector<Point3f>& q = m_mesh.positions;
        m_corner = q[0], m_e1 = q[1] - q[0], m_e2 = q[3] - q[0];
        const Vector3f gap = q[2] - (q[1] + m_e2);
        const float size = std::max(maxAbsComponent(m_e1), maxAbsComponent(m_e2));
        m_parallelogram = maxAbsComponent(gap) <= 1e-5f * size;
        // The normal of the first triangle's winding (flip_normals included), and
        // MeshShape's shading frame for it: dp/du = e1 (uv = (u, v) spans corner + u e1 +
        // v e2) made orthogonal to the normal. Both in double, computed once.
        const std::uint32_t* i = m_mesh.indices.data();
        const Vector3d ng = glm::cross(Vector3d(q[i[1]] - q[i[0]]), Vector3d(q[i[2]] - q[i[0]]));
        const Vector3d n = ng / glm::length(ng);
        const Vector3d sd = Vector3d(m_e1) - n * glm::dot(n, Vector3d(m_e1));
        const Vector3f t = Vector3f(sd / glm::length(sd));
        m_frame = Frame(t, cross(Vector3f(n), t), Vector3f(n));
        // Degenerate (zero area, a line): the mesh's rules.
        if (!(m_area > 0.f) || !isFinite(m_frame.n) || !isFinite(m_frame.s) || !isFinite(m_frame.t))
            m_parallelogram = false;
    }

    SurfaceInteraction interaction(const Ray& ray, const Hit& hit) const override {
        if (!m_parallelogram) return MeshShape::interaction(ray, hit);
        return planeInteraction(ray, hit);
    }

    PositionSample samplePosition(const Point2f& u) const override {
        if (!m_parallelogram) return MeshShape::samplePosition(u);
        PositionSample ps;
        ps.p = m_corner + u.x * m_e1 + u.y * m_e2;
        ps.n = m_frame.n;
        ps.uv = u;
        ps.pdf = 1.f / m_area;
        return ps;
    }

private:
    /// A separate function with one named result, so that it is built in the caller's
    /// return slot: with the fallback's return beside it in interaction() GCC built it on
    /// the stack and copied its 200 bytes out (a memcpy, then failed store forwarding in
    /// the caller; the memcpy alone was 1.9 % of a Cornell box profile).
    SurfaceInteraction planeInteraction(const Ray& ray, const Hit& hit) const {
        SurfaceInteraction si;
        hitPoint(hit, si);
        si.n = m_frame.n;
        si.dpdu = m_e1;
        si.dpdv = m_e2;
        si.shading = m_frame;
        finish(si, ray);
        return si;
    }

    Point3f m_corner;
    Vector3f m_e1, m_e2;
    Frame m_frame;
    bool m_parallelogram = false;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Rectangle)
