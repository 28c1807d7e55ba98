#pragma once
// What an `instance` needs from a `shapegroup` (Mitsuba 3 geometry instancing): the
// group's shapes, in their own (group) space, and one ray-query structure built over
// them once. Only components/shape/shapegroup.cpp and instance.cpp include this; the
// two are separate modules, so they meet through this small interface rather than a
// shared class.
#include "effigi/interfaces/iintersect.hpp"
#include "effigi/interfaces/ishape.hpp"

#include <span>

namespace effigi {

class IShapeGroup : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IShapeGroup");
    static constexpr const char* Tag = "shapegroup";

    /// The member shapes; Hit::shape from intersector() indexes this span.
    virtual std::span<const IShape* const> shapes() const = 0;
    /// Closest-hit / any-hit queries in group space, built once over shapes().
    virtual const IIntersect& intersector() const = 0;
    /// Bounds of the members in group space (invalid for an empty group).
    virtual BBox3f bbox() const = 0;
    /// A member BSDF with a pass-through (null) lobe, else the first member's BSDF, else
    /// null: the scene asks each shape for its BSDF to learn whether any can be crossed.
    virtual const IBSDF* representativeBsdf() const = 0;
};

} // namespace effigi
