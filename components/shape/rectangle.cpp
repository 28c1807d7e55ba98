// rectangle — the square [-1,1]² in the z = 0 plane, normal +z, as two triangles.
//
// Parameters: to_world (place, size and orient it: a scale of (w/2, h/2, 1) gives a
// w × h rectangle), flip_normals, face_normals, nested bsdf and emitter.
// uv = ((x+1)/2, (y+1)/2). Mitsuba 3's `rectangle` has the same geometry, so a scene
// renders alike in both.
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
    }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Rectangle)
