#pragma once
// The scene's bounding sphere as the emitters at infinity (directional, envmap) see
// it: direct-lighting samples put a stand-in light point beyond it, and emission
// samples start rays on a disk just outside it so that parallel rays cover the scene.
#include "effigi/math/bbox.hpp"
#include "effigi/math/frame.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/render/ray.hpp"

#include <algorithm>
#include <cmath>

namespace effigi {

struct SceneSphere {
    Point3f center{0.f};
    float radius = 1.f;

    /// The sphere around `bounds`; a scene of one point (or none) still gets a sphere
    /// of positive radius to aim emission at.
    static SceneSphere around(const BBox3f& bounds) {
        SceneSphere s;
        if (bounds.valid() && isFinite(bounds.min) && isFinite(bounds.max)) {
            s.center = bounds.center();
            s.radius = bounds.boundingRadius();
        }
        if (!(s.radius > 0.f) || !std::isfinite(s.radius)) s.radius = std::max(1.f, 1e-3f * maxAbsComponent(s.center));
        return s;
    }

    /// A point along `wi` from `ref` that lies beyond everything in the scene.
    Point3f beyond(const Point3f& ref, const Vector3f& wi) const {
        return ref + wi * (2.f * radius + length(ref - center));
    }

    /// A ray of direction d (unit) starting on the disk of the sphere's radius,
    /// perpendicular to d, one radius behind the centre: every such origin lies on or
    /// outside the sphere. Its position density is 1 / area().
    Ray parallelRay(const Vector3f& d, const Point2f& uPos) const {
        Point2f disk = warp::squareToUniformDiskConcentric(uPos);
        Frame frame(d);
        Point3f o = center + radius * (frame.toWorld(Vector3f(disk.x, disk.y, 0.f)) - d);
        return Ray{o, d, Infinity};
    }

    /// Area of the sphere's cross-section, π r².
    float area() const { return Pi * radius * radius; }
};

} // namespace effigi
