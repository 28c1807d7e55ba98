// shapegroup — shapes declared once for geometry instancing, not rendered by themselves.
//
// The nested shapes (any number, any type except another shapegroup) live
// in the group's own space. The group builds one ray-query structure over them when it
// is created; every `instance` that references the group traces its rays, transformed
// into group space, through that one structure, so N instances share the group's
// triangles and acceleration data instead of copying them. The scene loader leaves a
// shapegroup out of the scene: only instances make its shapes visible.
//
// As in Mitsuba 3, member shapes keep their own BSDFs (an instance cannot change them),
// and members may not carry area emitters (an instanced light would need every instance
// to be sampled; Mitsuba refuses this too), nor be shapegroups themselves. Unlike in
// Mitsuba 3, a member may be an instance of another group: instancing nests (a forest of
// trees of instanced leaves), each level tracing through its own group's structure.
//
// Parameters: any number of nested <shape> (named or not).
// Reference: Mitsuba 3 documentation, "Shape group (shapegroup)" and "Instance (instance)".
#include "shapegroup.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"

#include <vector>

namespace effigi {
namespace {

/// Which accelerator holds a group's shapes. Embree, like the scene's default: Embree
/// permits tracing a second scene from inside a user-geometry callback, which is what an
/// instance inside the scene's Embree BVH does.
constexpr const char* GroupAccelerator = "embree";

class ShapeGroup final : public Implements<IShapeGroup> {
public:
    static Schema schema() {
        Schema s("shape", "shapegroup", "Shapes declared once for instancing; invisible until an instance references them.");
        s.cite("Mitsuba 3 documentation, Shape group (shapegroup)");
        s.children("shape", "Member shapes (not shapegroups or shapes with emitters; instances nest)");
        return s;
    }

    explicit ShapeGroup(const Properties& p) {
        for (const Properties::Entry& e : p.entries()) {
            const auto* c = std::get_if<ComponentValue>(&e.value);
            if (!c || c->tag != "shape") continue;
            const std::string& type = c->object->typeName();
            if (query<IShapeGroup>(c->object.get()))
                failAt(e.where, "{}: a shapegroup cannot contain another shapegroup (nested groups are not supported)",
                       p.describe());
            Ref<IShape> shape = query<IShape>(c->object);
            if (!shape) failAt(e.where, "{}: nested '{}' is not a shape", p.describe(), type);
            if (shape->emitter())
                failAt(e.where, "{}: shape '{}' carries an emitter; shapes in a shapegroup cannot be emitters "
                                "(as in Mitsuba 3: declare the light as an ordinary shape)",
                       p.describe(), type);
            m_shapes.push_back(shape);
            m_shapePtrs.push_back(shape.get());
            m_bbox.expand(shape->bbox());
        }

        Properties ap("accelerator", GroupAccelerator, p.where());
        m_accel = query<IIntersect>(Registry::instance().create("accelerator", GroupAccelerator, ap));
        if (!m_accel) failAt(p.where(), "{}: accelerator '{}' is not an accelerator", p.describe(), GroupAccelerator);
        m_accel->build(m_shapePtrs);

        for (const IShape* s : m_shapePtrs) {
            const IBSDF* b = s->bsdf();
            if (!m_bsdf) m_bsdf = b;
            if (b && b->hasNull()) {
                m_bsdf = b;
                break;
            }
        }
    }

    std::span<const IShape* const> shapes() const override { return m_shapePtrs; }
    const IIntersect& intersector() const override { return *m_accel; }
    BBox3f bbox() const override { return m_bbox; }
    const IBSDF* representativeBsdf() const override { return m_bsdf; }

private:
    std::vector<Ref<IShape>> m_shapes;  // ownership
    std::vector<const IShape*> m_shapePtrs;
    Ref<IIntersect> m_accel;
    BBox3f m_bbox;
    const IBSDF* m_bsdf = nullptr;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::ShapeGroup)
