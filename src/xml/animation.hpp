#pragma once
// Shapes that move: a <shape> whose to_world is an <animation> with more than one key is
// built at rest (without to_world) and placed by an `instance` of a shapegroup holding it
// alone, whose to_world is the animation (components/shape/instance.cpp): one code path
// for the motion of every kind of shape, on every accelerator.
#include "effigi/core/registry.hpp"

#include <optional>

namespace effigi::xml::detail {

struct ShapeMotion {
    AnimatedTransform animation;
    SourceLocation where;
};

/// A shape's moving to_world, taken out of its properties (none if it does not move).
std::optional<ShapeMotion> takeShapeMotion(Properties& props);

/// The shape (built without its to_world) placed by the motion; an emitter on it is an
/// error (its light would have to move too).
Ref<IComponent> placeMoving(Registry& registry, const Ref<IComponent>& shape, const ShapeMotion& motion,
                            const Properties& shapeProps);

} // namespace effigi::xml::detail
