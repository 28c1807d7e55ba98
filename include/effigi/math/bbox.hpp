#pragma once
#include "effigi/math/vector.hpp"

namespace effigi {

/// Axis-aligned bounding box; empty when min > max.
struct BBox3f {
    Point3f min{Infinity, Infinity, Infinity};
    Point3f max{-Infinity, -Infinity, -Infinity};

    BBox3f() = default;
    BBox3f(const Point3f& a, const Point3f& b) : min(glm::min(a, b)), max(glm::max(a, b)) {}

    bool valid() const { return min.x <= max.x && min.y <= max.y && min.z <= max.z; }
    void expand(const Point3f& p) { min = glm::min(min, p); max = glm::max(max, p); }
    void expand(const BBox3f& b) { min = glm::min(min, b.min); max = glm::max(max, b.max); }
    Point3f center() const { return 0.5f * (min + max); }
    Vector3f extents() const { return max - min; }
    /// Bounding sphere radius about center().
    float boundingRadius() const { return valid() ? 0.5f * length(extents()) : 0.f; }
    float surfaceArea() const {
        Vector3f d = extents();
        return 2.f * (d.x * d.y + d.y * d.z + d.z * d.x);
    }
};

} // namespace effigi
