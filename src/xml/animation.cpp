// Moving shapes placed by instances (src/xml/animation.hpp).
#include "animation.hpp"

#include "effigi/interfaces/ishape.hpp"

namespace effigi::xml::detail {

std::optional<ShapeMotion> takeShapeMotion(Properties& props) {
    if (!props.has("to_world") || props.type() == "instance") return std::nullopt;
    const SourceLocation where = props.whereOf("to_world");
    AnimatedTransform a = props.getAnimatedTransform("to_world");
    if (!a.isAnimated()) return std::nullopt;
    props.remove("to_world");
    return ShapeMotion{std::move(a), where};
}

Ref<IComponent> placeMoving(Registry& registry, const Ref<IComponent>& shape, const ShapeMotion& motion,
                            const Properties& shapeProps) {
    const Ref<IShape> s = query<IShape>(shape);
    if (s && s->emitter())
        failAt(motion.where, "{}: an animated shape cannot be an emitter (moving lights are not supported)",
               shapeProps.describe());
    if (s && s->isMediumTransition())
        failAt(motion.where, "{}: an animated shape cannot bound a medium (moving media are not supported)",
               shapeProps.describe());
    Properties group("shape", "shapegroup", shapeProps.where());
    group.set("shape", ComponentValue{"shape", shape}, shapeProps.where());
    Properties instance("shape", "instance", shapeProps.where());
    instance.set("shapegroup", ComponentValue{"shape", registry.create("shape", "shapegroup", group)},
                 shapeProps.where());
    instance.set("to_world", motion.animation, motion.where);
    return registry.create("shape", "instance", instance);
}

} // namespace effigi::xml::detail
