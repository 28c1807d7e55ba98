#pragma once
// The boundary of a csg solid along a ray (components/shape/csg.cpp): every crossing of
// each part's closed surface, classified as entering or leaving that part, merged in t
// order, with the boolean operation deciding which crossings are the result's boundary.
//
// A leaf part (a sphere, a capped cylinder, a closed mesh, any closed shape that is not
// a csg) has its crossings enumerated through its ordinary closest-hit query, restarted
// on the ray a small step past the previous crossing: IShape::intersect for analytic
// shapes, a private `bvh` over the mesh alone for triangle meshes. No interface of the
// shapes changes for this. A crossing enters the part where the ray runs against the
// part's outward normal (its own normal times its orientation, found when the csg is
// built). Parts closer together along the ray than the step (1e-6 of the part's size
// plus a few float roundings of the coordinates) are below what the walk resolves.
//
// A nested csg part is walked the same way: its own Walker yields the crossings of its
// result, so csg trees nest to any depth. This is the classic interval-classification
// ray tracing of CSG trees (S. D. Roth, "Ray Casting for Modeling Solids", Computer
// Graphics and Image Processing 18(2), 1982), evaluated lazily: only as many crossings
// are found as it takes to reach the first one of the result.
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/iintersect.hpp"
#include "effigi/interfaces/ishape.hpp"

#include <algorithm>
#include <memory>
#include <optional>
#include <vector>

namespace effigi::csg {

enum class Op { Union, Intersection, Difference };

/// A closed part that is not itself a csg.
struct Leaf {
    const IShape* shape = nullptr;
    Ref<IIntersect> accel;        // triangle meshes: a bvh over the mesh alone
    float orient = 1.f;           // -1: the shape's normals point into the solid it bounds
    const IBSDF* bsdf = nullptr;  // the part's own <bsdf>; null when it has the default one
    double radius = 1.0;          // bounding radius of its box: scales the step between crossings
};

struct Node;

/// One operand of a csg: a leaf or a nested csg's node.
struct Part {
    const Leaf* leaf = nullptr;
    const Node* node = nullptr;
};

/// A csg's solid: the boolean combination of its parts (difference: the first minus
/// the union of the others).
struct Node {
    Op op = Op::Union;
    std::vector<Part> parts;
    const IBSDF* bsdf = nullptr;  // the csg's own <bsdf> (null: none), for parts without one
    double radius = 1.0;          // bounding radius: crossings closer than 1e-6 of it are one event

    /// Whether a point is inside the result, given in(k): whether it is inside part k.
    template <typename In> bool combine(In in) const {
        const std::size_t n = parts.size();
        switch (op) {
        case Op::Union:
            for (std::size_t k = 0; k < n; ++k)
                if (in(k)) return true;
            return false;
        case Op::Intersection:
            for (std::size_t k = 0; k < n; ++k)
                if (!in(k)) return false;
            return true;
        case Op::Difference:
            if (!in(0)) return false;
            for (std::size_t k = 1; k < n; ++k)
                if (in(k)) return false;
            return true;
        }
        return false;
    }
};

/// A crossing of a solid's boundary along a ray.
struct Crossing {
    double t = 0.0;               // along the caller's ray, in its units of d
    int dir = 0;                  // +1 entering the solid, -1 leaving it, 0 unknown (grazing)
    const Leaf* leaf = nullptr;   // whose surface is crossed
    Ray ray;                      // the query that found it: leaf->shape->interaction(ray, hit)
    Hit hit;
    bool flip = false;            // the solid's outward normal is minus the leaf's normal
    const IBSDF* bsdf = nullptr;  // the innermost explicit BSDF so far (null: none yet)
};

/// Float rounding of coordinates of magnitude m, as a length.
inline double roundoff(double m) { return 8.0 * 0x1p-24 * m; }

/// The crossings of one leaf's surface along a ray, nearest first.
class LeafCursor {
public:
    LeafCursor(const Leaf& leaf, const Ray& ray) : m_leaf(&leaf), m_ray(ray) {}

    bool next(Crossing& c) {
        const Vector3d o(m_ray.o), d(m_ray.d);
        const double dl = glm::length(d);
        for (int tries = 0; tries < 8 && m_count < MaxCrossings; ++tries) {
            Ray r{m_from > 0.0 ? Point3f(o + m_from * d) : m_ray.o, m_ray.d, Infinity, m_ray.time};
            Hit h;
            if (!query(r, h)) return false;
            const double t = m_from + double(h.t);
            const double step = (1e-6 * m_leaf->radius + roundoff(maxAbsComponent(Point3f(o + t * d)))) / dl;
            if (m_count > 0 && h.prim == m_lastPrim && t <= m_lastT + 2.0 * step) {
                m_from = t + double(4 << tries) * step;  // the previous crossing found again
                continue;
            }
            m_from = t + step;
            m_lastT = t;
            m_lastPrim = h.prim;
            ++m_count;
            c = Crossing{t, direction(r, h), m_leaf, r, h, m_leaf->orient < 0.f, m_leaf->bsdf};
            return true;
        }
        return false;
    }

private:
    static constexpr int MaxCrossings = 1024;

    bool query(const Ray& r, Hit& h) const {
        if (m_leaf->accel) return m_leaf->accel->intersect(r, h);
        float t;
        Point2f uv;
        if (!m_leaf->shape->intersect(r, t, uv)) return false;
        h = Hit{t, 0, 0, uv};
        return true;
    }

    /// +1 where the ray runs against the outward normal, -1 along it, 0 exactly across.
    int direction(const Ray& r, const Hit& h) const {
        Vector3f n;
        if (const TriangleMesh* m = m_leaf->shape->mesh()) {
            Point3f a, b, c;
            m->triangle(h.prim, a, b, c);
            n = cross(b - a, c - a);  // the winding normal, as MeshShape's geometric one
        } else {
            n = m_leaf->shape->interaction(r, h).n;
        }
        float dn = dot(n, r.d) * m_leaf->orient;
        return dn < 0.f ? 1 : (dn > 0.f ? -1 : 0);
    }

    const Leaf* m_leaf;
    Ray m_ray;
    double m_from = 0.0, m_lastT = 0.0;
    std::uint32_t m_lastPrim = Hit::None;
    int m_count = 0;
};

/// The crossings of a node's result along a ray, nearest first; inside() is whether the
/// ray is inside the result before the next one. One allocation per node walked.
class Walker {
public:
    Walker(const Node& node, const Ray& ray) : m_node(&node), m_ray(ray) {
        m_cursors.reserve(node.parts.size());
        for (const Part& part : node.parts) {
            Cursor& c = m_cursors.emplace_back();
            if (part.leaf) c.leaf.emplace(*part.leaf, ray);
            else c.node = std::make_unique<Walker>(*part.node, ray);
            bool before = c.node && c.node->inside();
            fetch(c);
            // Inside the part at the origin exactly when its first crossing leaves it.
            c.in = c.has ? c.pending.dir < 0 : before;
        }
        m_state = combine();
    }

    bool inside() const { return m_state; }

    bool next(Crossing& out) {
        const double dl = glm::length(Vector3d(m_ray.d)), om = double(maxAbsComponent(m_ray.o));
        for (;;) {
            for (Cursor& c : m_cursors) c.done = false;
            const Cursor* first = nearest(Infinity);
            if (!first) return false;
            // Crossings within the resolution of the first one are one event (coincident
            // surfaces of two parts): taken in t order, and only the net change of the
            // result counts, so that a face shared by two parts of a union makes no
            // crossing; the surface is the one whose crossing made the last change.
            const double t0 = first->pending.t;
            const double limit = t0 + (1e-6 * m_node->radius + roundoff(om + t0 * dl)) / dl;
            bool state = m_state, changed = false;
            while (Cursor* c = nearest(limit)) {
                Crossing x = c->pending;
                fetch(*c);
                c->done = true;  // its next crossing belongs to a later event
                if (x.dir == 0) x.dir = c->in ? -1 : 1;  // grazing: the part's state toggles
                c->in = x.dir > 0;
                const bool s = combine();
                if (s != state) out = x, changed = true;
                state = s;
            }
            if (!changed || state == m_state) continue;
            m_state = state;
            const int dir = state ? 1 : -1;
            out.flip = out.flip != (out.dir != dir);  // the part's inside is the result's outside
            out.dir = dir;
            if (!out.bsdf) out.bsdf = m_node->bsdf;
            return true;
        }
    }

private:
    struct Cursor {
        std::optional<LeafCursor> leaf;
        std::unique_ptr<Walker> node;
        Crossing pending;
        bool has = false, in = false, done = false;
    };
    static void fetch(Cursor& c) { c.has = c.leaf ? c.leaf->next(c.pending) : c.node->next(c.pending); }
    bool combine() const { return m_node->combine([&](std::size_t k) { return m_cursors[k].in; }); }

    /// The cursor with the nearest pending crossing at most `limit`, not yet in this event.
    Cursor* nearest(double limit) {
        Cursor* best = nullptr;
        for (Cursor& c : m_cursors)
            if (c.has && !c.done && c.pending.t <= limit && (!best || c.pending.t < best->pending.t)) best = &c;
        return best;
    }

    const Node* m_node;
    Ray m_ray;
    std::vector<Cursor> m_cursors;
    bool m_state = false;
};

/// Whether p is inside a part: the first crossing of a ray from p leaves it. The ray
/// runs along a fixed direction off every axis and diagonal.
inline bool insidePart(const Part& part, const Point3f& p) {
    const Ray r{p, normalize(Vector3f(0.3183099f, 0.5772157f, 0.7526712f)), Infinity};
    if (part.node) return Walker(*part.node, r).inside();
    LeafCursor lc(*part.leaf, r);
    Crossing c;
    return lc.next(c) && c.dir < 0;
}

} // namespace effigi::csg
