#pragma once
#include "effigi/math/vector.hpp"

#include <cstdint>

namespace effigi {

struct Ray {
    Point3f o{0.f};
    Vector3f d{0.f, 0.f, 1.f};
    float tMax = Infinity;
    /// The instant the ray samples (shutter time, in the scene's units): animated shapes
    /// are intersected where they are at this time. Rays spawned from a surface keep it.
    float time = 0.f;

    Point3f operator()(float t) const { return o + t * d; }
};

/// What an accelerator reports: distance, which shape and primitive, and the
/// primitive's own hit coordinates (barycentrics for triangles).
struct Hit {
    static constexpr std::uint32_t None = 0xffffffffu;
    float t = Infinity;
    std::uint32_t shape = None;
    std::uint32_t prim = 0;
    Point2f uv{0.f};

    bool valid() const { return shape != None; }
};

/// Origin for a ray leaving a surface point p (normal n) in direction d, pushed off the
/// surface along n by an amount relative to the coordinates' magnitude so that float
/// round-off cannot make the ray re-hit its own surface at any scene scale. `scale` is
/// the magnitude of the values p was computed from (a triangle's vertices, a sphere's
/// centre plus radius): p's rounding error is a few ulps of it, which near the world
/// origin is far more than a few ulps of p itself (a mirror through the origin).
inline Point3f offsetRayOrigin(const Point3f& p, const Normal3f& n, const Vector3f& d, float scale = 0.f) {
    constexpr float RelativeEps = 0x1p-17f;  // ~7.6e-6: a few ulps of |p| with margin
    float offset = RelativeEps * std::max(std::max(maxAbsComponent(p), scale), 0x1p-60f);
    Vector3f o = offset * n;
    return dot(d, n) < 0.f ? p - o : p + o;
}

/// Shadow rays stop short of their target by this relative amount.
inline constexpr float ShadowEpsilon = 1e-4f;

} // namespace effigi
