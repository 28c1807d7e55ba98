#pragma once
// Shared by the bvh and kdtree accelerators: the scene flattened into primitives (one per
// triangle, one per analytic shape), their conservative bounds, the robust ray/box slab
// test, and the primitive test itself — the same watertight triangle test as bruteforce
// (Woop et al. 2013), so that a tree that visits every box the ray touches gives
// bruteforce's answers exactly.
#include "effigi/interfaces/ishape.hpp"
#include "effigi/math/intersect.hpp"

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace effigi::accel {

/// One triangle, or one analytic shape (prim == Analytic; the corners are unused).
struct Primitive {
    Point3f p0, p1, p2;
    std::uint32_t shape, prim;
    static constexpr std::uint32_t Analytic = 0xffffffffu;
};

/// 4 float ulps of the largest coordinate: primitive boxes are padded by this so that
/// rounding in the box test or in the triangle test (whose vertices are rounded relative
/// to the ray origin) cannot cull a box whose primitive the triangle test would report.
inline BBox3f padded(BBox3f b) {
    float m = std::max(maxAbsComponent(b.min), maxAbsComponent(b.max));
    Vector3f pad(m * 0x1p-21f + std::numeric_limits<float>::min());
    b.min -= pad;
    b.max += pad;
    return b;
}

/// Every triangle of every mesh and every analytic shape, in shape order.
inline std::vector<Primitive> gatherPrimitives(std::span<const IShape* const> shapes) {
    std::vector<Primitive> out;
    for (std::uint32_t s = 0; s < shapes.size(); ++s) {
        if (const TriangleMesh* mesh = shapes[s]->mesh()) {
            for (std::uint32_t t = 0; t < mesh->triangleCount(); ++t) {
                Primitive p{};
                mesh->triangle(t, p.p0, p.p1, p.p2);
                p.shape = s;
                p.prim = t;
                out.push_back(p);
            }
        } else {
            out.push_back(Primitive{Point3f(0.f), Point3f(0.f), Point3f(0.f), s, Primitive::Analytic});
        }
    }
    return out;
}

inline BBox3f primitiveBounds(const Primitive& p, std::span<const IShape* const> shapes) {
    if (p.prim == Primitive::Analytic) return padded(shapes[p.shape]->bbox());
    BBox3f b(p.p0, p.p1);
    b.expand(p.p2);
    return padded(b);
}

/// The slab test with Ize's conservative bound (T. Ize, "Robust BVH Ray Traversal",
/// JCGT 2(2), 2013): the exit distance is enlarged by 1 + 2γ₃ so that a ray that touches
/// the box in exact arithmetic is never rejected by rounding. A zero direction component
/// gives ±∞ slab distances, and 0 · ∞ = NaN (a ray lying in a slab's plane) is ignored by
/// the comparisons, which treats the ray as inside that slab.
struct SlabRay {
    Point3f o;
    Vector3f inv;
    explicit SlabRay(const Ray& r) : o(r.o), inv(1.f / r.d.x, 1.f / r.d.y, 1.f / r.d.z) {}

    static constexpr float Gamma3 = 3.f * 0x1p-24f / (1.f - 3.f * 0x1p-24f);

    /// Whether the box is touched within [0, tMax]; [tEnter, tExit] is the (conservative)
    /// part of the ray inside it.
    bool clip(const Point3f& bmin, const Point3f& bmax, float tMax, float& tEnter, float& tExit) const {
        float tNear = 0.f, tFar = tMax;
        for (int a = 0; a < 3; ++a) {
            float t0 = (bmin[a] - o[a]) * inv[a], t1 = (bmax[a] - o[a]) * inv[a];
            if (t0 > t1) std::swap(t0, t1);
            tNear = t0 > tNear ? t0 : tNear;
            tFar = t1 < tFar ? t1 : tFar;
        }
        tEnter = tNear;
        tExit = tFar * (1.f + 2.f * Gamma3);
        return tNear <= tExit;
    }
    bool hit(const Point3f& bmin, const Point3f& bmax, float tMax, float& tEnter) const {
        float tExit;
        return clip(bmin, bmax, tMax, tEnter, tExit);
    }
};

/// Tests one primitive against the ray up to tMax; on a hit shrinks tMax and fills hit
/// (when given). Triangles exactly as bruteforce does; analytic shapes by IShape::intersect.
inline bool intersectPrimitive(const Primitive& p, const Ray& ray, const WatertightRay& wr,
                               std::span<const IShape* const> shapes, float& tMax, Hit* hit) {
    if (p.prim != Primitive::Analytic) {
        float t, b1, b2;
        if (!intersectTriangle(wr, p.p0, p.p1, p.p2, tMax, t, b1, b2)) return false;
        tMax = t;
        if (hit) *hit = Hit{t, p.shape, p.prim, {b1, b2}};
        return true;
    }
    Ray r{ray.o, ray.d, tMax, ray.time};
    float t;
    Point2f uv;
    if (!shapes[p.shape]->intersect(r, t, uv)) return false;
    tMax = t;
    if (hit) *hit = Hit{t, p.shape, 0, uv};
    return true;
}

} // namespace effigi::accel
