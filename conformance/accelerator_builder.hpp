#pragma once
// What the accelerator suite's scene generators share (accelerator_scenes.cpp: ordinary
// scenes; accelerator_stiff_scenes.cpp: the stiff ones): a bare triangle-mesh shape and
// a builder that adds shapes and rays to a scene from one seeded generator.
#include "conformance/accelerator_scenes.hpp"

#include "effigi/core/error.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/math/rng.hpp"

#include <cmath>

namespace effigi::conform {

/// A bare triangle mesh: what the accelerators see of an obj or ply shape, without
/// going through a file.
class SuiteMesh final : public Implements<IShape> {
public:
    explicit SuiteMesh(TriangleMesh m) : m_mesh(std::move(m)), m_bbox(m_mesh.bbox()) {}
    BBox3f bbox() const override { return m_bbox; }
    const TriangleMesh* mesh() const override { return &m_mesh; }
    SurfaceInteraction interaction(const Ray& ray, const Hit& hit) const override {
        SurfaceInteraction si;
        si.t = hit.t;
        si.p = ray(hit.t);
        si.prim = hit.prim;
        si.shape = this;
        return si;
    }
    float area() const override { return 0.f; }
    PositionSample samplePosition(const Point2f&) const override { return {}; }
    const IBSDF* bsdf() const override { return nullptr; }
    const IEmitter* emitter() const override { return nullptr; }
    IEmitter* emitter() override { return nullptr; }

private:
    TriangleMesh m_mesh;
    BBox3f m_bbox;
};

struct Builder {
    AccelScene& scene;
    Registry& registry;
    PCG32 rng;

    float uniform(float lo, float hi) { return lo + (hi - lo) * rng.nextFloat(); }
    float logUniform(float lo, float hi) { return lo * std::pow(hi / lo, rng.nextFloat()); }
    Point3f inBox(float lo, float hi) { return {uniform(lo, hi), uniform(lo, hi), uniform(lo, hi)}; }
    Vector3f direction() {
        float z = 1.f - 2.f * rng.nextFloat(), phi = 2.f * Pi * rng.nextFloat(), r = safeSqrt(1.f - z * z);
        return {r * std::cos(phi), r * std::sin(phi), z};
    }
    /// A point strictly inside triangle (p0, p1, p2), barycentrics at least `margin`.
    Point3f interior(const Point3f& p0, const Point3f& p1, const Point3f& p2, float margin) {
        float b1 = uniform(margin, 1.f - 2.f * margin), b2 = uniform(margin, 1.f - margin - b1);
        return (1.f - b1 - b2) * p0 + b1 * p1 + b2 * p2;
    }

    void add(Ref<IShape> s) {
        scene.shapes.push_back(s.get());
        scene.owned.push_back(std::move(s));
    }
    void addMesh(TriangleMesh m) {
        if (m.triangleCount() > 0) add(std::make_shared<SuiteMesh>(std::move(m)));
    }
    Ref<IShape> create(const std::string& type, Properties p) {
        Ref<IShape> s = query<IShape>(registry.create("shape", type, p));
        if (!s) fail("accelerator suite: shape '{}' is not an IShape", type);
        return s;
    }
    void sphere(const Point3f& c, float r) {
        Properties p("shape", "sphere");
        p.set("center", PointValue{c});
        p.set("radius", double(r));
        add(create("sphere", std::move(p)));
    }
    void transformed(const std::string& type, const Transform& t) {
        Properties p("shape", type);
        p.set("to_world", t);
        add(create(type, std::move(p)));
    }
    static void triangle(TriangleMesh& m, const Point3f& a, const Point3f& b, const Point3f& c) {
        auto base = std::uint32_t(m.positions.size());
        m.positions.insert(m.positions.end(), {a, b, c});
        m.indices.insert(m.indices.end(), {base, base + 1, base + 2});
    }
    /// An indexed box (8 shared corners, 12 triangles, outward winding) through t.
    static TriangleMesh box(const Transform& t) {
        TriangleMesh m;
        for (int i = 0; i < 8; ++i)
            m.positions.push_back(t.point(Point3f(i & 1 ? 1.f : -1.f, i & 2 ? 1.f : -1.f, i & 4 ? 1.f : -1.f)));
        m.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                     2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
        return m;
    }
    /// A sphere of radius r(θ, φ) as one indexed mesh: poles as fans, 2 nφ (nθ − 1) triangles.
    template <typename Radius> static TriangleMesh sphereMesh(int nTheta, int nPhi, const Point3f& c, Radius radius) {
        TriangleMesh m;
        auto at = [&](float theta, float phi) {
            float r = radius(theta, phi);
            return c + r * Vector3f(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta));
        };
        m.positions.push_back(at(0.f, 0.f));
        for (int i = 1; i < nTheta; ++i)
            for (int j = 0; j < nPhi; ++j) m.positions.push_back(at(Pi * float(i) / float(nTheta), 2.f * Pi * float(j) / float(nPhi)));
        m.positions.push_back(at(Pi, 0.f));
        auto ring = [&](int i, int j) { return std::uint32_t(1 + (i - 1) * nPhi + (j % nPhi)); };
        auto south = std::uint32_t(m.positions.size() - 1);
        for (int j = 0; j < nPhi; ++j) {
            m.indices.insert(m.indices.end(), {0u, ring(1, j), ring(1, j + 1)});
            for (int i = 1; i + 1 < nTheta; ++i)
                m.indices.insert(m.indices.end(), {ring(i, j), ring(i + 1, j), ring(i + 1, j + 1), ring(i, j),
                                                   ring(i + 1, j + 1), ring(i, j + 1)});
            m.indices.insert(m.indices.end(), {ring(nTheta - 1, j), south, ring(nTheta - 1, j + 1)});
        }
        return m;
    }
    void ray(const Point3f& o, const Vector3f& d, float tMax = Infinity) { scene.rays.push_back(Ray{o, d, tMax}); }
};

/// Random triangles, spheres and a disk scaled by s (accelerator_scenes.cpp).
void soup(Builder& b, bool quick, float s);

/// The stiff scenes (accelerator_stiff_scenes.cpp); each states what its rays probe.
void slivers(Builder& b, bool quick);
void coplanar(Builder& b, bool quick);
void edgesAndVertices(Builder& b, bool quick);
void onSurface(Builder& b, bool quick);
void axisAligned(Builder& b, bool quick);
void tMaxAtHit(Builder& b, bool quick);
void grazing(Builder& b, bool quick);

} // namespace effigi::conform
