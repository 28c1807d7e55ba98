// instance — one placement of a shapegroup's shapes, under its own to_world.
//
// The instance is an analytic shape to whichever accelerator holds the scene: its
// intersect() carries the ray into group space with the inverse of to_world and asks the
// group's own ray-query structure (built once, shared by every instance of the group)
// for the closest hit. The ray direction is transformed but not renormalised, so the
// ray parameter t is the same in both spaces and needs no conversion.
//
// IShape::intersect can hand back only (t, uv), too little to name the member shape and
// primitive hit, so interaction() traces the group-space ray once more, with tMax just
// above t; the query is deterministic, so it finds the same closest hit. That second
// query runs once per hit the renderer shades, not once per candidate.
//
// The member's surface description is then carried back to world space as Mitsuba 3
// does: points and the tangents ∂p/∂u, ∂p/∂v with to_world, geometric and shading
// normals with its inverse transpose (renormalised), the shading tangent with to_world
// then re-orthogonalised against the new normal. The member's BSDF, uv, primitive and
// barycentrics are kept, so textures (mesh attributes included) behave as on the member.
// si.shape stays the member (its mesh, media, attributes) and si.instance names this
// instance (Mitsuba 3's si.instance), so a shader's localGeometry() query comes here: the
// hit is carried back to group space, the member answers, and its normal derivatives
// are carried to the world with the normals' matrix.
//
// Instances carry no emitter (shapegroup refuses emitting members, as Mitsuba does), so
// renderers never sample them; area() and samplePosition() exist for completeness and
// are exact for rotation, translation and uniform scale (for other transforms the area
// is the member area times |det|^(2/3), an approximation).
//
// Motion: to_world may be an <animation> (Mitsuba 0.6's keyframes, AnimatedTransform);
// each ray is then carried into group space with the pose at its time (Ray::time), and
// the bounds hold every pose. The loader places any shape with an animated to_world this
// way (as the only member of a group of its own), which gives rigid motion blur on every
// accelerator without a per-shape motion code path. Area and sampling use the first pose.
//
// Parameters: to_world (affine, invertible at every key; default identity; may be an
// <animation>) and exactly one nested or referenced shapegroup, whose members may be
// instances themselves (nested instancing). Reference: Mitsuba 3 documentation, "Instance
// (instance)".
#include "shapegroup.hpp"

#include "effigi/core/registry.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace effigi {
namespace {

class Instance final : public Implements<IShape> {
public:
    static Schema schema() {
        Schema s("shape", "instance", "A shapegroup placed in the scene under its own to_world.");
        s.cite("Mitsuba 3 documentation, Instance (instance)");
        s.transform("to_world", "Group-to-world transform (affine and invertible)");
        s.child("shape", "shapegroup", "The shapegroup to place (usually <ref id=\"...\"/>)").isRequired();
        // effigi-conform: a group of a sphere and a square, placed rotated, scaled and
        // moved, and mirrored at 1/100 scale.
        if (auto g = conformanceGroup()) {
            s.addConformance({"placed", {{"shapegroup", *g}, {"to_world", Transform::translate({0.3f, -0.2f, 0.1f}) *
                                                                              Transform::rotate({1.f, 1.f, 1.f}, 30.f) *
                                                                              Transform::scale(Vector3f(2.f))}}});
            s.addConformance({"mirrored small", {{"shapegroup", *g}, {"to_world", Transform::scale({-1e-2f, 1e-2f, 1e-2f})}}});
            // Moving: the suite's rays are at time 0, where the first pose holds.
            s.addConformance({"moving", {{"shapegroup", *g},
                                         {"to_world", AnimatedTransform({{0.f, Transform::rotate({0.f, 1.f, 0.f}, 20.f)},
                                                                         {1.f, Transform::translate({1.f, 0.5f, 0.f})}})}}});
        }
        return s;
    }

    /// The group of the conformance configurations, made through the registry; absent
    /// if a module cannot be made (the configurations are then left out).
    static std::optional<PropertyValue> conformanceGroup() {
        try {
            Registry& reg = Registry::instance();
            Properties sphere("shape", "sphere"), square("shape", "rectangle"), group("shape", "shapegroup");
            sphere.set("center", PointValue{{1.5f, 0.f, 0.f}});
            sphere.set("radius", 0.5);
            group.set("sphere", ComponentValue{"shape", reg.create("shape", "sphere", sphere)});
            group.set("square", ComponentValue{"shape", reg.create("shape", "rectangle", square)});
            return ComponentValue{"shape", reg.create("shape", "shapegroup", group)};
        } catch (const std::exception&) {
            return std::nullopt;
        }
    }

    explicit Instance(const Properties& p) {
        Ref<IComponent> group = p.getComponent("shapegroup");
        m_group = query<IShapeGroup>(group);
        if (!m_group)
            failAt(p.whereOf("shapegroup"), "{}: the nested or referenced shape must be a shapegroup, got '{}'",
                   p.describe(), group ? group->typeName() : std::string("nothing"));
        if (p.has("to_world")) m_animation = p.getAnimatedTransform("to_world");
        for (const AnimatedTransform::Key& k : m_animation.keys()) {
            const glm::mat4& m = k.transform.matrix();
            bool affine = m[0][3] == 0.f && m[1][3] == 0.f && m[2][3] == 0.f && m[3][3] == 1.f;
            float det = glm::determinant(glm::mat3(m));
            if (!k.transform.isFinite() || !affine || !(std::abs(det) > 0.f) || !std::isfinite(det))
                failAt(p.whereOf("to_world"), "{}: parameter 'to_world' must be a finite, invertible affine transform{}",
                       p.describe(), m_animation.isAnimated() ? fmt::format(" (key at time {})", k.time) : "");
        }
        m_rest = Placement(m_animation.first());
        m_areaScale = std::pow(std::abs(glm::determinant(m_rest.linear)), 2.f / 3.f);

        // World bounds: the group's bounds carried through every pose.
        BBox3f b = m_group->bbox();
        // An empty group: a point box, so accelerators get finite bounds; it is never hit.
        if (!b.valid()) b.expand(Point3f(0.f));
        m_bbox = m_animation.motionBounds(b);

        m_members = m_group->shapes();
        m_nested = std::any_of(m_members.begin(), m_members.end(),
                               [](const IShape* s) { return dynamic_cast<const Instance*>(s) != nullptr; });
        for (const IShape* s : m_members) {
            m_memberArea += s->area();
            m_areaCdf.push_back(m_memberArea);
        }
    }

    BBox3f bbox() const override { return m_bbox; }

    bool intersect(const Ray& ray, float& t, Point2f& uv) const override {
        Hit h;
        // Only the pose's inverse is needed here, not a whole Placement (its normals' matrix).
        const Ray local = m_animation.isAnimated() ? rayInto(m_animation.at(ray.time), ray) : m_rest.toGroup(ray);
        if (!m_group->intersector().intersect(local, h)) return false;
        t = h.t;
        uv = Point2f(0.f);
        return true;
    }

    SurfaceInteraction interaction(const Ray& ray, const Hit& hit) const override {
        const Placement pose = placementAt(ray.time);
        Ray local = pose.toGroup(ray);
        // Just above hit.t, so the same closest hit is found again (see the file comment).
        local.tMax = std::nextafter(std::max(hit.t, 0.f), Infinity) * (1.f + 0x1p-20f);
        Hit h;
        SurfaceInteraction si;
        if (!m_group->intersector().intersect(local, h) || h.shape >= m_members.size()) {
            // Not expected; a plain facing point rather than garbage if it ever happens.
            si.t = hit.t;
            si.p = ray(hit.t);
            Vector3f d = normalize(ray.d);
            si.n = -d;
            si.shading = Frame(si.n);
            si.wo = -d;
            return si;
        }
        si = m_members[h.shape]->interaction(local, h);
        pose.toWorld(si);
        si.t = hit.t;
        si.wo = normalize(-ray.d);
        si.instance = this;  // si.shape stays the member (see the file comment)
        return si;
    }

    /// The member's local geometry, asked in group space and carried back: objectP is the
    /// member's own object-space point; the world normal is n = N n_g / |N n_g| (N the
    /// normals' matrix), so ∂n/∂u = (I − n nᵀ) N ∂n_g/∂u / |N n_g|, and likewise for v.
    LocalGeometry localGeometry(const SurfaceInteraction& si) const override {
        if (!si.shape || si.shape == this) return IShape::localGeometry(si);
        const Placement pose = placementAt(si.time);
        SurfaceInteraction g = pose.toGroup(si);
        // A member that is itself an instance answers through its own placement.
        g.instance = memberInstanceAt(g);
        LocalGeometry lg = g.instance ? g.instance->localGeometry(g) : g.shape->localGeometry(g);
        const Vector3f m = pose.normalMatrix * g.shading.n;
        const float len = length(m);
        if (!(len > 0.f) || !std::isfinite(len)) return LocalGeometry{lg.objectP, Vector3f(0.f), Vector3f(0.f)};
        const Vector3f n = m / len;
        auto carry = [&](const Vector3f& d) {
            Vector3f w = pose.normalMatrix * d;
            return (w - n * dot(n, w)) / len;
        };
        lg.dndu = carry(lg.dndu);
        lg.dndv = carry(lg.dndv);
        return lg;
    }

    float area() const override { return m_memberArea * m_areaScale; }

    PositionSample samplePosition(const Point2f& u) const override {
        PositionSample ps;
        if (!(m_memberArea > 0.f)) return ps;
        // Pick a member by its area, then reuse u.x within it.
        float target = u.x * m_memberArea;
        std::size_t i = std::min<std::size_t>(
            std::size_t(std::upper_bound(m_areaCdf.begin(), m_areaCdf.end(), target) - m_areaCdf.begin()),
            m_members.size() - 1);
        float lo = i ? m_areaCdf[i - 1] : 0.f, width = m_areaCdf[i] - lo;
        float ux = width > 0.f ? std::clamp((target - lo) / width, 0.f, OneMinusEpsilon) : 0.f;
        ps = m_members[i]->samplePosition({ux, u.y});
        ps.p = m_rest.transform.point(ps.p);
        ps.n = normalizeOr(m_rest.normalMatrix * ps.n, ps.n);
        ps.pdf = 1.f / area();
        return ps;
    }

    bool moves() const override {
        return m_animation.isAnimated() || std::any_of(m_members.begin(), m_members.end(),
                                                       [](const IShape* s) { return s->moves(); });
    }

    const IBSDF* bsdf() const override { return m_group->representativeBsdf(); }
    const IEmitter* emitter() const override { return nullptr; }
    IEmitter* emitter() override { return nullptr; }

private:
    static Vector3f normalizeOr(const Vector3f& v, const Vector3f& fallback) {
        float l2 = dot(v, v);
        return l2 > 0.f && std::isfinite(l2) ? v / std::sqrt(l2) : fallback;
    }

    /// The world ray in group space under the pose toWorld (direction not renormalised, so
    /// t is the same in both spaces).
    static Ray rayInto(const Transform& toWorld, const Ray& ray) {
        const glm::mat4& inv = toWorld.inverseMatrix();
        return Ray{Point3f(inv * glm::vec4(ray.o, 1.f)), Vector3f(inv * glm::vec4(ray.d, 0.f)), ray.tMax, ray.time};
    }

    /// One pose of the group: to_world, its linear part and the normals' matrix.
    struct Placement {
        Transform transform;
        glm::mat3 linear{1.f}, normalMatrix{1.f};
        Placement() = default;
        explicit Placement(const Transform& t)
            : transform(t), linear(t.matrix()), normalMatrix(glm::transpose(glm::inverse(linear))) {}

        Ray toGroup(const Ray& ray) const { return rayInto(transform, ray); }

        /// Carry a member's surface description from group space to world space.
        void toWorld(SurfaceInteraction& si) const {
            si.p = transform.point(si.p);
            si.n = normalizeOr(normalMatrix * si.n, si.n);
            Vector3f n = normalizeOr(normalMatrix * si.shading.n, si.n);
            // The member's tangent follows the surface; Gram-Schmidt against the new normal.
            Vector3f s = linear * si.shading.s;
            s -= n * dot(n, s);
            float s2 = dot(s, s);
            if (s2 > 1e-20f && std::isfinite(s2)) {
                s /= std::sqrt(s2);
                // Right-handed, like every other shape's frame (a mirroring to_world thus
                // mirrors the member's bitangent direction, not the frame's handedness).
                si.shading = Frame(s, cross(n, s), n);
            } else {
                si.shading = Frame(n);
            }
            si.dpdu = linear * si.dpdu;
            si.dpdv = linear * si.dpdv;
        }

        /// A world-space surface description (this pose's toWorld()) back in group space,
        /// as the member made it: for the member's localGeometry().
        SurfaceInteraction toGroup(const SurfaceInteraction& w) const {
            SurfaceInteraction si = w;
            const glm::mat3 inv(transform.inverseMatrix()), tr = glm::transpose(linear);
            si.p = transform.inverse().point(w.p);
            si.n = normalizeOr(tr * w.n, w.n);
            const Vector3f n = normalizeOr(tr * w.shading.n, si.n);
            Vector3f s = inv * w.shading.s;
            s -= n * dot(n, s);
            const float s2 = dot(s, s);
            si.shading = s2 > 1e-20f && std::isfinite(s2) ? Frame(s / std::sqrt(s2), cross(n, s / std::sqrt(s2)), n)
                                                           : Frame(n);
            si.dpdu = inv * w.dpdu;
            si.dpdv = inv * w.dpdv;
            si.wo = normalizeOr(inv * w.wo, w.wo);
            si.instance = nullptr;
            return si;
        }
    };

    /// The member instance (nested instancing) whose surface holds the group-space point
    /// g, or null: an SurfaceInteraction names only the outermost instance, so the member
    /// is found again by a short ray through g along its normal (a few ulps of |p| long).
    const IShape* memberInstanceAt(const SurfaceInteraction& g) const {
        if (!m_nested) return nullptr;
        const float off = 16.f * 0x1p-17f * std::max(std::max(maxAbsComponent(g.p), g.pScale), 0x1p-60f);
        Hit h;
        if (!m_group->intersector().intersect(Ray{g.p + Vector3f(g.n) * off, -Vector3f(g.n), 2.f * off, g.time}, h) ||
            h.shape >= m_members.size())
            return nullptr;
        const IShape* member = m_members[h.shape];
        return dynamic_cast<const Instance*>(member) ? member : nullptr;
    }

    Placement placementAt(float time) const {
        return m_animation.isAnimated() ? Placement(m_animation.at(time)) : m_rest;
    }

    Ref<IShapeGroup> m_group;
    std::span<const IShape* const> m_members;
    bool m_nested = false;  ///< some member is an instance (nested instancing)
    std::vector<float> m_areaCdf;  // cumulative member areas in group space
    float m_memberArea = 0.f;
    AnimatedTransform m_animation;
    Placement m_rest;  ///< the first pose (the only one of a still instance)
    float m_areaScale = 1.f;
    BBox3f m_bbox;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Instance)
