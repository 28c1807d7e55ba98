#pragma once
// Helpers shared by the shape tests (test_ply, test_shapes, test_shape_sampling):
// creating shapes through the registry, a brute-force mesh tracer and error checks.
#include <catch2/catch.hpp>

#include "effigi/core/error.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/render/mesh.hpp"
#include "effigi/render/shape_base.hpp"

#include <cmath>
#include <cstdint>
#include <string>

namespace effigi::test {

inline Ref<IShape> makeShape(const std::string& type, Properties props) {
    Ref<IShape> s = query<IShape>(Registry::instance().create("shape", type, props));
    REQUIRE(s);
    return s;
}
inline Ref<IShape> makeShape(const std::string& type) { return makeShape(type, Properties("shape", type)); }

/// Brute-force ray/triangle intersection (Möller & Trumbore 1997) in double, reporting
/// Embree-style barycentrics: p = (1-u-v) p0 + u p1 + v p2.
inline bool intersectMesh(const TriangleMesh& m, const Ray& r, Hit& hit) {
    bool found = false;
    double best = r.tMax;
    for (std::size_t i = 0; i < m.triangleCount(); ++i) {
        Vector3d p0(m.positions[m.indices[3 * i]]), p1(m.positions[m.indices[3 * i + 1]]),
            p2(m.positions[m.indices[3 * i + 2]]), o(r.o), d(r.d);
        Vector3d e1 = p1 - p0, e2 = p2 - p0, pv = glm::cross(d, e2);
        double det = glm::dot(e1, pv);
        if (std::abs(det) < 1e-300) continue;
        Vector3d tv = o - p0;
        double u = glm::dot(tv, pv) / det;
        if (u < 0.0 || u > 1.0) continue;
        Vector3d qv = glm::cross(tv, e1);
        double v = glm::dot(d, qv) / det;
        if (v < 0.0 || u + v > 1.0) continue;
        double t = glm::dot(e2, qv) / det;
        if (t > 1e-9 && t < best) {
            best = t;
            hit.t = float(t);
            hit.prim = std::uint32_t(i);
            hit.uv = Point2f(float(u), float(v));
            hit.shape = 0;
            found = true;
        }
    }
    return found;
}

/// Closest hit on one shape, whichever kind it is.
inline bool trace(const IShape& s, const Ray& r, Hit& hit) {
    if (s.mesh()) return intersectMesh(*s.mesh(), r, hit);
    float t;
    Point2f uv;
    if (!s.intersect(r, t, uv)) return false;
    hit.t = t;
    hit.uv = uv;
    hit.shape = 0;
    hit.prim = 0;
    return true;
}

/// Runs f and checks it throws a one-line effigi::Error whose message contains needle.
template <typename F> void requireThrowsNaming(F&& f, const std::string& needle) {
    try {
        f();
        FAIL("no effigi::Error thrown; expected one naming " << needle);
    } catch (const Error& e) {
        INFO("message: " << e.what());
        CHECK(std::string(e.what()).find(needle) != std::string::npos);
        CHECK(std::string(e.what()).find('\n') == std::string::npos);  // one line
    }
}

} // namespace effigi::test
