// accelerator "bruteforce" — tests every ray against every primitive.
//
// The slowest possible accelerator and the simplest to trust: the reference the others
// are checked against. Triangles use the watertight test of Woop et al. 2013; analytic
// shapes answer through IShape::intersect. No parameters.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iintersect.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/math/intersect.hpp"

#include <vector>

namespace effigi {
namespace {

class BruteForce final : public Implements<IIntersect> {
public:
    static Schema schema() {
        return Schema("accelerator", "bruteforce",
                      "Tests every primitive for every ray: the reference for accelerator equivalence.");
    }
    explicit BruteForce(const Properties&) {}

    void build(std::span<const IShape* const> shapes) override {
        m_shapes.assign(shapes.begin(), shapes.end());
        for (const IShape* s : m_shapes) m_bbox.expand(s->bbox());
    }

    bool intersect(const Ray& ray, Hit& hit) const override { return trace(ray, &hit); }
    bool occluded(const Ray& ray) const override { return trace(ray, nullptr); }
    BBox3f bbox() const override { return m_bbox; }

private:
    // Closest hit when `hit` is given, otherwise stop at the first one.
    bool trace(const Ray& ray, Hit* hit) const {
        WatertightRay wr(ray.o, ray.d);
        float tMax = ray.tMax;
        bool found = false;
        for (std::uint32_t s = 0; s < m_shapes.size(); ++s) {
            const IShape* shape = m_shapes[s];
            if (const TriangleMesh* mesh = shape->mesh()) {
                const auto& P = mesh->positions;
                const auto& I = mesh->indices;
                for (std::uint32_t tri = 0; tri < mesh->triangleCount(); ++tri) {
                    float t, b1, b2;
                    if (!intersectTriangle(wr, P[I[3 * tri]], P[I[3 * tri + 1]], P[I[3 * tri + 2]], tMax, t, b1, b2))
                        continue;
                    if (!hit) return true;
                    tMax = t;
                    *hit = Hit{t, s, tri, {b1, b2}};
                    found = true;
                }
            } else {
                Ray r = ray;
                r.tMax = tMax;
                float t;
                Point2f uv;
                if (!shape->intersect(r, t, uv)) continue;
                if (!hit) return true;
                tMax = t;
                *hit = Hit{t, s, 0, uv};
                found = true;
            }
        }
        return found;
    }

    std::vector<const IShape*> m_shapes;
    BBox3f m_bbox;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::BruteForce)
