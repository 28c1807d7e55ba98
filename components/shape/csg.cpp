// csg — constructive solid geometry: the union, intersection or difference of closed
// shapes, intersected exactly.
//
// Parameters: operation (union | intersection | difference: the first part minus the
// union of the others), two or more nested <shape>s (the parts), bsdf, interior,
// exterior, flip_normals. Parts are spheres, cylinders with caps = true, cubes, closed
// triangle meshes (obj, ply, serialized) and csgs, to any depth: any shape whose surface
// is closed. A mesh must be closed and consistently oriented (checked on its welded
// edges), an analytic shape is checked on its area samples (Gauss's theorem); a part
// that is not closed (a rectangle, a disk, a cylinder without caps) is an error. A part's
// flip_normals changes nothing: inside is inside (the orientation is found from the
// part's signed volume). A csg has no to_world: transform the parts, or instance it.
//
// Intersection: the crossings of each part's surface along the ray are classified as
// entering or leaving it and merged in t order; the operation decides which are the
// result's boundary, and the first of those in (0, tMax) is the hit (csg_walk.hpp, after
// Roth 1982). The normal at a hit is the part's own, turned around where the part's
// inside is the result's outside (the wall of a hole cut by a difference); the BSDF is
// the part's own, or, for a part without a <bsdf>, the innermost enclosing csg's, else
// the default diffuse. The csg is the surface's shape (si.shape: its interior/exterior
// media apply); per-vertex mesh attributes of parts are not available (no mesh).
//
// Emitters: refused, on the csg and on its parts. The visible boundary is the parts'
// surfaces minus what the operation hides; its area and uniform samples are estimated
// (below), so a light's pdf would not be exact. area() and samplePosition() exist for
// the shape checks: the area is a quasi-Monte Carlo estimate (2^15 Hammersley samples
// of each part's surface, kept where they lie on the result's boundary; about 1e-3
// relative for two spheres, tests/test_csg.cpp), computed on first use; samples are
// drawn from a part picked by its estimated share of the boundary and retried until
// they land on the boundary, pdf = 1 / area().
//
// Reference: S. D. Roth, "Ray Casting for Modeling Solids", Computer Graphics and Image
// Processing 18(2), 1982; A. A. G. Requicha, "Representations for Rigid Solids", ACM
// Computing Surveys 12(4), 1980.
#include "csg_checks.hpp"
#include "csg_walk.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/render/shape_base.hpp"

#include <atomic>
#include <cstring>
#include <mutex>

namespace effigi {
namespace {

/// What a csg shows another csg it is a part of (only this module knows it).
class ICsgSolid : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("effigi::csg::ICsgSolid");
    static constexpr const char* Tag = "shape";
    virtual const csg::Node& solid() const = 0;
    /// A uniform point of the solid's boundary with its outward normal (flip_normals not applied).
    virtual PositionSample sampleSolid(const Point2f& u) const = 0;
};

using Params = std::vector<std::pair<std::string, PropertyValue>>;

class Csg final : public ShapeBase, public ICsgSolid {
public:
    static Schema schema() {
        Schema s("shape", "csg", "Union, intersection or difference of closed shapes (constructive solid geometry).");
        s.cite("S. D. Roth, Ray Casting for Modeling Solids, Computer Graphics and Image Processing 18(2), 1982");
        s.string("operation", "union", "union, intersection, or difference (the first part minus the others)")
            .oneOf({"union", "intersection", "difference"});
        s.children("shape", "The parts: two or more closed shapes (sphere, cylinder with caps, cube, closed meshes, csg)");
        s.child("bsdf", "bsdf", "Surface scattering of the parts without their own <bsdf> (default: diffuse)");
        s.child("emitter", "emitter", "Not supported: a csg cannot be an emitter (an error names it)");
        s.child("medium", "interior", "Participating medium inside the solid (optional)");
        s.child("medium", "exterior", "Participating medium outside the solid (optional)");
        s.boolean("flip_normals", false, "Normals point into the solid");
        addConformanceConfigs(s);
        return s;
    }

    explicit Csg(const Properties& p) : ShapeBase(p) {
        if (m_emitter)
            failAt(p.whereOf("emitter"), "csg shapes cannot be emitters (the visible boundary's area and samples are "
                                         "only estimated); put the emitter on an ordinary shape");
        const std::string op = p.has("operation") ? p.getString("operation") : "union";
        m_node.op = op == "intersection" ? csg::Op::Intersection : op == "difference" ? csg::Op::Difference : csg::Op::Union;
        m_node.bsdf = hasDefaultBsdf() ? nullptr : m_bsdf.get();
        for (const Properties::Entry& e : p.entries()) {
            const auto* c = std::get_if<ComponentValue>(&e.value);
            if (c && c->tag == "shape") addPart(p, e, *c);
        }
        if (m_node.parts.size() < 2)
            failAt(p.where(), "{}: a csg needs two or more nested shapes, got {}", p.describe(), m_node.parts.size());
        // Bounds: of all parts (union), of their common part (intersection; a point where
        // there is none, which nothing hits), of the first (difference).
        for (std::size_t k = 0; k < m_node.parts.size(); ++k) {
            BBox3f b = m_partShapes[k]->bbox();
            if (k == 0 || m_node.op == csg::Op::Union) {
                m_bbox.expand(b);
            } else if (m_node.op == csg::Op::Intersection) {
                m_bbox.min = glm::max(m_bbox.min, b.min);
                m_bbox.max = glm::max(glm::min(m_bbox.max, b.max), m_bbox.min);
            }
        }
        m_node.radius = std::max(double(m_bbox.boundingRadius()), 1e-30);
        // The BSDF the scene asks about (whether any surface can be crossed): a part's
        // pass-through one if there is such, else the csg's own.
        m_representative = m_bsdf.get();
        for (const IShape* s : m_partShapes)
            if (const IBSDF* b = s->bsdf(); b && b->hasNull()) m_representative = b;
    }

    void* query(InterfaceId iid) override {
        if (iid == ICsgSolid::IID) return static_cast<ICsgSolid*>(this);
        return ShapeBase::query(iid);
    }

    BBox3f bbox() const override { return m_bbox; }
    const IBSDF* bsdf() const override { return m_representative; }
    const csg::Node& solid() const override { return m_node; }

    bool intersect(const Ray& ray, float& t, Point2f& uv) const override {
        csg::Crossing c;
        if (!csg::Walker(m_node, ray).next(c)) return false;
        float tc = float(c.t);
        if (!(tc > 0.f) || !(tc < ray.tMax)) return false;
        t = tc;
        uv = Point2f(0.f);
        Recent& r = recent();
        r = Recent{m_serial, ray.o, ray.d, tc, c};
        return true;
    }

    SurfaceInteraction interaction(const Ray& ray, const Hit& hit) const override {
        // The walk is deterministic: its first crossing is the one intersect() reported,
        // kept by this thread unless another csg of the same slot was hit since.
        csg::Crossing c;
        const Recent& r = recent();
        bool found = r.serial == m_serial && r.o == ray.o && r.d == ray.d && r.t == hit.t;
        if (found) c = r.crossing;
        else found = csg::Walker(m_node, ray).next(c);
        SurfaceInteraction si;
        if (!found) {  // not expected; a facing point, not garbage
            si.t = hit.t;
            si.p = ray(hit.t);
            si.n = -normalize(ray.d);
            si.shading = Frame(si.n);
        } else {
            si = c.leaf->shape->interaction(c.ray, c.hit);
            if (c.flip != m_flipNormals) {
                si.n = -si.n;
                si.shading = Frame(si.shading.s, -si.shading.t, -si.shading.n);
            }
            si.t = hit.t;
        }
        si.wo = normalize(-ray.d);
        si.shape = this;
        si.bsdf = c.bsdf ? c.bsdf : c.leaf ? c.leaf->shape->bsdf() : m_bsdf.get();
        si.emitter = nullptr;
        return si;
    }

    float area() const override { return float(sampling().total); }

    PositionSample samplePosition(const Point2f& u) const override {
        PositionSample ps = sampleSolid(u);
        if (m_flipNormals) ps.n = -ps.n;
        return ps;
    }

    PositionSample sampleSolid(const Point2f& u) const override {
        const Sampling& s = sampling();
        if (!(s.total > 0.0)) return {};
        // The part by its share of the boundary, then what is left of u.x within it.
        double target = double(u.x) * s.total;
        std::size_t j = std::min<std::size_t>(std::size_t(std::upper_bound(s.cdf.begin(), s.cdf.end(), target) - s.cdf.begin()),
                                              s.cdf.size() - 1);
        while (j > 0 && s.cdf[j] == s.cdf[j - 1]) --j;  // never a part without boundary
        double lo = j ? s.cdf[j - 1] : 0.0, width = s.cdf[j] - lo;
        Point2f uu(width > 0.0 ? std::clamp(float((target - lo) / width), 0.f, OneMinusEpsilon) : 0.f, u.y);
        // Retries, until a sample lands on the boundary, from a generator keyed by u.
        std::uint32_t bits[2];
        std::memcpy(bits, &u, sizeof bits);
        PCG32 rng(mixBits((std::uint64_t(bits[0]) << 32) | bits[1]), 0x5bd1e995u);
        const int tries = int(std::clamp(16.0 * s.partArea[j] / std::max(s.cdf[j] - lo, 1e-300), 64.0, 65536.0));
        for (int i = 0; i < tries; ++i, uu = Point2f(rng.nextFloat(), rng.nextFloat())) {
            PositionSample ps = samplePart(j, uu);
            bool innerInside;
            if (!(ps.pdf > 0.f) || !onBoundary(j, ps.p, innerInside)) continue;
            if (!innerInside) ps.n = -ps.n;
            ps.pdf = float(1.0 / s.total);
            return ps;
        }
        return {};
    }

private:
    /// The last crossing this thread's intersect() reported for a csg, in one of a few
    /// slots chosen by the csg's address: interaction() then need not walk the ray again.
    /// The csg is named by a serial number, never reused (its address may be).
    struct Recent {
        std::uint64_t serial = 0;
        Point3f o;
        Vector3f d;
        float t = 0.f;
        csg::Crossing crossing;
    };
    Recent& recent() const {
        thread_local Recent slots[8];
        return slots[(reinterpret_cast<std::uintptr_t>(this) >> 6) & 7u];
    }

    struct Sampling {
        std::vector<double> cdf, partArea;  // cumulative boundary area by part; each part's area
        double total = 0.0;
    };

    void addPart(const Properties& p, const Properties::Entry& e, const ComponentValue& c) {
        const std::string& type = c.object->typeName();
        Ref<IShape> shape = effigi::query<IShape>(c.object);
        if (!shape)
            failAt(e.where, "{}: nested '{}' is not a shape (a shapegroup is placed by an instance)", p.describe(), type);
        if (shape->emitter())
            failAt(e.where, "csg shapes cannot be emitters (part '{}' of {} carries one); put the emitter on an "
                            "ordinary shape", type, p.describe());
        if (shape->isMediumTransition())
            failAt(e.where, "{}: part '{}' has an interior or exterior medium; give media to the csg itself",
                   p.describe(), type);
        csg::Part part;
        if (auto* nested = effigi::query<ICsgSolid>(c.object.get())) {
            part.node = &nested->solid();
        } else {
            auto leaf = std::make_unique<csg::Leaf>();
            leaf->shape = shape.get();
            const auto* base = dynamic_cast<const ShapeBase*>(shape.get());
            leaf->bsdf = base && base->hasDefaultBsdf() ? nullptr : shape->bsdf();
            leaf->radius = std::max(double(shape->bbox().boundingRadius()), 1e-30);
            double volume = 0.0;
            std::string problem;
            if (const TriangleMesh* mesh = shape->mesh()) {
                problem = csg::meshSolidProblem(*mesh, volume);
                Properties ap("accelerator", "bvh", e.where);
                leaf->accel = effigi::query<IIntersect>(Registry::instance().create("accelerator", "bvh", ap));
                const IShape* one[] = {shape.get()};
                if (leaf->accel) leaf->accel->build(one);
            } else {
                problem = csg::sampledSolidProblem(*shape, volume);
            }
            if (!problem.empty())
                failAt(e.where, "{}: part '{}' is not a closed solid: {}{}", p.describe(), type, problem,
                       type == "shape/cylinder" ? " (set <boolean name=\"caps\" value=\"true\"/> to close a cylinder)" : "");
            leaf->orient = volume < 0.0 ? -1.f : 1.f;
            part.leaf = leaf.get();
            m_leaves.push_back(std::move(leaf));
        }
        m_node.parts.push_back(part);
        m_partShapes.push_back(shape.get());
        m_owned.push_back(shape);
    }

    /// A uniform point of part j's surface with the normal pointing out of the part.
    PositionSample samplePart(std::size_t j, const Point2f& u) const {
        const csg::Part& part = m_node.parts[j];
        if (part.node) return effigi::query<ICsgSolid>(m_owned[j].get())->sampleSolid(u);
        PositionSample ps = part.leaf->shape->samplePosition(u);
        ps.n *= part.leaf->orient;
        return ps;
    }

    /// Whether p, on part j's surface, is on the result's boundary; innerInside: the
    /// result's inside is on the part's inner side.
    bool onBoundary(std::size_t j, const Point3f& p, bool& innerInside) const {
        std::vector<char> in(m_node.parts.size());
        for (std::size_t k = 0; k < in.size(); ++k)
            if (k != j) in[k] = csg::insidePart(m_node.parts[k], p);
        auto inside = [&](std::size_t k) { return in[k] != 0; };
        in[j] = 1;
        innerInside = m_node.combine(inside);
        in[j] = 0;
        return innerInside != m_node.combine(inside);
    }

    /// The boundary's share of each part, estimated once on first use (see the file comment).
    const Sampling& sampling() const {
        std::call_once(m_samplingOnce, [this] {
            constexpr std::uint32_t N = 1u << 15;
            double sum = 0.0;
            for (std::size_t j = 0; j < m_node.parts.size(); ++j) {
                std::uint32_t kept = 0;
                for (std::uint32_t i = 0; i < N; ++i) {
                    PositionSample ps = samplePart(j, {(float(i) + 0.5f) / float(N), fixedToFloat(vanDerCorput(i))});
                    bool inner;
                    if (ps.pdf > 0.f && onBoundary(j, ps.p, inner)) ++kept;
                }
                double a = double(m_partShapes[j]->area());
                m_sampling.partArea.push_back(a);
                sum += std::isfinite(a) ? a * double(kept) / double(N) : 0.0;
                m_sampling.cdf.push_back(sum);
            }
            m_sampling.total = sum;
        });
        return m_sampling;
    }

    static void addConformanceConfigs(Schema& s);

    inline static std::atomic<std::uint64_t> s_serials{0};
    const std::uint64_t m_serial = ++s_serials;
    csg::Node m_node;
    std::vector<std::unique_ptr<csg::Leaf>> m_leaves;
    std::vector<const IShape*> m_partShapes;
    std::vector<Ref<IShape>> m_owned;
    BBox3f m_bbox;
    const IBSDF* m_representative = nullptr;
    mutable std::once_flag m_samplingOnce;
    mutable Sampling m_sampling;
};

/// A shape for the conformance configurations, through the registry.
PropertyValue make(const std::string& type, const Params& params) {
    Properties p("shape", type);
    for (const auto& [name, value] : params) p.set(name, value);
    return ComponentValue{"shape", Registry::instance().create("shape", type, p)};
}
PropertyValue sphere(Point3f c, double r) { return make("sphere", {{"center", PointValue{c}}, {"radius", r}}); }
PropertyValue capped(Point3f a, Point3f b, double r) {
    return make("cylinder", {{"p0", PointValue{a}}, {"p1", PointValue{b}}, {"radius", r}, {"caps", true}});
}
/// A csg made here (the registry cannot make one while it asks for this schema).
PropertyValue nested(const std::string& op, const Params& parts) {
    Properties p("shape", "csg");
    p.set("operation", op);
    for (const auto& [name, value] : parts) p.set(name, value);
    auto c = std::make_shared<Csg>(p);
    c->setIdentity("shape/csg", "");
    return ComponentValue{"shape", Ref<IComponent>(c)};
}

void Csg::addConformanceConfigs(Schema& s) {
    // effigi-conform: a sphere with a bite out of it, a lens, a cube pierced by a tilted
    // capped cylinder, the textbook CSG tree (cube ∩ sphere minus three cylinders) and a
    // lens far from the origin. Left out if a module cannot be made.
    try {
        using T = Transform;
        s.addConformance({"bitten sphere", {{"operation", std::string("difference")}, {"a", sphere({0, 0, 0}, 1.0)},
                                            {"b", sphere({0.8f, 0.2f, 0}, 0.6)}}});
        s.addConformance({"lens", {{"operation", std::string("intersection")}, {"a", sphere({-0.5f, 0, 0}, 1.0)},
                                   {"b", sphere({0.5f, 0, 0}, 1.0)}}});
        s.addConformance({"cube and cylinder", {{"a", make("cube", {{"to_world", T::rotate({1, 1, 0}, 30.f) * T::scale(Vector3f(0.6f))}})},
                                                {"b", capped({-1.2f, -0.3f, -0.4f}, {1.1f, 0.5f, 0.3f}, 0.3)}}});
        Params axes;
        for (int a = 0; a < 3; ++a) {
            Point3f lo(0.f), hi(0.f);
            lo[a] = -1.5f, hi[a] = 1.5f;
            axes.emplace_back(fmt::format("c{}", a), capped(lo, hi, 0.45));
        }
        s.addConformance({"tree", {{"operation", std::string("difference")},
                                   {"a", nested("intersection", {{"a", make("cube", {})}, {"b", sphere({0, 0, 0}, 1.35)}})},
                                   {"b", nested("union", axes)}}});
        s.addConformance({"far lens", {{"operation", std::string("intersection")},
                                       {"a", sphere({1e2f - 0.25f, -2e2f, 50.f}, 0.5)},
                                       {"b", sphere({1e2f + 0.25f, -2e2f, 50.f}, 0.5)}}});
    } catch (const std::exception&) {
    }
}

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Csg)
