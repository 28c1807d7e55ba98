// cube — the axis-aligned cube [-1,1]³ as 12 triangles wound outward.
//
// Parameters: to_world, flip_normals, face_normals, nested bsdf and emitter.
// Each face has its own 4 vertices (24 in all) carrying the outward face normal and a
// [0,1]² uv parametrisation, so edges stay sharp under vertex-normal shading.
// Reference: Mitsuba 3 plugin documentation, "Cube (cube)".
#include "effigi/core/registry.hpp"
#include "effigi/render/shape_base.hpp"

namespace effigi {
namespace {

class Cube final : public MeshShape {
public:
    static Schema schema() {
        Schema s("shape", "cube", "Axis-aligned cube [-1,1]³, 12 triangles with outward normals.");
        s.cite("Mitsuba 3 documentation, cube shape");
        addMeshParams(s);
        // effigi-conform: a thin slab, a huge far box, inward normals.
        s.addConformance({"default", {}});
        s.addConformance({"slab", {{"to_world", Transform::scale({1.f, 2.f, 1e-4f})}}});
        s.addConformance({"huge far", {{"to_world", Transform::translate({3e4f, 0.f, -1e4f}) * Transform::scale(Vector3f(1e4f))}}});
        s.addConformance({"flipped", {{"flip_normals", true}}});
        return s;
    }

    explicit Cube(const Properties& p) : MeshShape(p) {
        TriangleMesh m;
        const Vector3f axes[3] = {{1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}, {0.f, 0.f, 1.f}};
        for (int axis = 0; axis < 3; ++axis) {
            for (float sign : {-1.f, 1.f}) {
                Normal3f n = sign * axes[axis];
                // s, t with cross(s, t) = n: a counter-clockwise quad seen from outside.
                Vector3f s = axes[(axis + 1) % 3];
                Vector3f t = cross(n, s);
                auto base = std::uint32_t(m.positions.size());
                const float corners[4][2] = {{-1.f, -1.f}, {1.f, -1.f}, {1.f, 1.f}, {-1.f, 1.f}};
                for (const auto& c : corners) {
                    m.positions.push_back(n + c[0] * s + c[1] * t);
                    m.normals.push_back(n);
                    m.uvs.emplace_back(0.5f * (c[0] + 1.f), 0.5f * (c[1] + 1.f));
                }
                for (std::uint32_t i : {0u, 1u, 2u, 2u, 3u, 0u}) m.indices.push_back(base + i);
            }
        }
        setMesh(std::move(m), p.describe());
    }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Cube)
