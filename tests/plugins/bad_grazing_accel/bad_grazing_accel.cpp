// accelerator "bad_grazing_accel" — DELIBERATELY WRONG test plugin: answers closest-hit
// queries with another accelerator (embree by default), then drops every hit on a
// triangle that the ray meets at grazing incidence, |cos(ray, normal)| < 0.05, as a
// traversal with a careless epsilon in its triangle test would. Any-hit queries use the
// same faulty answer. Analytic shapes (spheres, disks) are answered correctly.
//
// effigi-conform must fail it on a "closest hit <scene>" check — surely on the suite's
// grazing scene, whose rays meet triangles at |cos θ| between 1e-3 and 1e-2
// (tests/plugins/run_plugin_tests.cmake).
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iintersect.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/render/mesh.hpp"

#include <vector>

namespace {
using namespace effigi;

constexpr float MissedCosine = 0.05f;  // the bug: hits below this |cos| are lost

class BadGrazingAccel final : public Implements<IIntersect> {
public:
    static Schema schema() {
        Schema s("accelerator", "bad_grazing_accel", "Test plugin: misses triangle hits with |cos(ray, normal)| < 0.05.");
        s.string("inner", "embree", "Accelerator whose answers it filters");
        return s;
    }

    explicit BadGrazingAccel(const Properties& p) {
        Properties q("accelerator", p.getString("inner"));
        m_inner = query<IIntersect>(Registry::instance().create("accelerator", p.getString("inner"), q));
        if (!m_inner) failAt(p.whereOf("inner"), "{}: '{}' is not an accelerator", p.describe(), p.getString("inner"));
    }

    void build(std::span<const IShape* const> shapes) override {
        m_shapes.assign(shapes.begin(), shapes.end());
        m_inner->build(shapes);
    }

    bool intersect(const Ray& ray, Hit& hit) const override {
        Hit h;
        if (!m_inner->intersect(ray, h) || grazing(ray, h)) return false;
        hit = h;
        return true;
    }
    bool occluded(const Ray& ray) const override {
        Hit h;
        return intersect(ray, h);
    }
    BBox3f bbox() const override { return m_inner->bbox(); }

private:
    bool grazing(const Ray& ray, const Hit& h) const {
        const TriangleMesh* mesh = m_shapes[h.shape]->mesh();
        if (!mesh) return false;
        const auto& P = mesh->positions;
        const auto& I = mesh->indices;
        const Point3f& a = P[I[3 * h.prim]];
        Vector3f n = cross(P[I[3 * h.prim + 1]] - a, P[I[3 * h.prim + 2]] - a);
        float c = dot(n, ray.d) / (length(n) * length(ray.d));
        return std::abs(c) < MissedCosine;  // NaN (degenerate triangle): kept
    }

    Ref<IIntersect> m_inner;
    std::vector<const IShape*> m_shapes;
};

} // namespace

EFFIGI_EXPORT_COMPONENT(BadGrazingAccel)
