#pragma once
// IIntersect — ray queries against the scene's shapes: closest hit and any hit, for one
// ray or a batch. The base batch methods loop; vectorising accelerators (Embree) override
// them with packet queries. Embree is the default; the others are equivalence references.
#include "effigi/core/component.hpp"
#include "effigi/math/bbox.hpp"
#include "effigi/render/ray.hpp"

#include <cstdint>
#include <span>

namespace effigi {

class IShape;

class IIntersect : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IIntersect");
    static constexpr const char* Tag = "accelerator";

    /// Build over shapes; hit.shape indexes this span. Called once.
    virtual void build(std::span<const IShape* const> shapes) = 0;

    /// Closest hit in (0, ray.tMax); false and hit untouched on a miss.
    virtual bool intersect(const Ray& ray, Hit& hit) const = 0;
    /// Whether anything is hit in (0, ray.tMax).
    virtual bool occluded(const Ray& ray) const = 0;

    virtual void intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
        for (std::size_t i = 0; i < rays.size(); ++i) {
            hits[i] = Hit{};
            intersect(rays[i], hits[i]);
        }
    }
    /// occluded[i] = 1 if rays[i] is blocked.
    virtual void occluded(std::span<const Ray> rays, std::span<std::uint8_t> occluded) const {
        for (std::size_t i = 0; i < rays.size(); ++i) occluded[i] = this->occluded(rays[i]) ? 1 : 0;
    }

    virtual BBox3f bbox() const = 0;
};

} // namespace effigi
