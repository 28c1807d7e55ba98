// accelerator "kdtree" — a kd-tree built with the surface area heuristic.
//
// Models nothing physical: it answers the same closest-hit and any-hit queries as
// bruteforce. The build is the O(N log N) algorithm of Wald & Havran 2006: each
// primitive's bounds in a cell give start, end and planar events on each axis, sorted
// once at the root; at every node one sweep over the events costs every event position
// with the SAH
//   C = λ (C_trav + C_isect (P_L N_L + P_R N_R)),  λ = 1 − empty_bonus if a side is empty,
// primitives lying in the plane going to whichever side is cheaper; the empty-space
// bonus makes the tree cut off empty space early. A node becomes a leaf when no split is
// cheaper than C_isect N, or at max_depth. A primitive straddling the chosen plane is
// referenced by both children, each with the bounds of its part clipped to that child
// ("perfect splits"; dropped from a child it misses); one touching the plane from one
// side only by that side; a planar one by the side the SAH chose. The children's event
// lists keep their order, so nothing is sorted again but the straddlers' new events.
//
// Traversal is front to back with a small fixed stack and no mailboxing: a primitive in
// several leaves may be tested more than once, which is harmless because the closest-hit
// bound only shrinks. Every cell's parametric interval [t_min, t_max] is widened by a
// relative 2⁻¹⁸ where it is cut by a split plane, so rounding of the plane distance
// never skips a cell the ray touches. A cell whose (widened) interval starts beyond the
// closest hit found so far is skipped: that hit lies in an earlier or the current
// interval, and nothing in the cell can be nearer. This is what keeps a hit from being
// taken before a nearer one in a later cell without mailboxing or per-cell hit checks:
// every primitive test runs with tMax = the closest hit so far. A ray lying in a split
// plane (zero direction component) visits both cells.
//
// Parameters:
//   intersection_cost  float (default 1.5)  cost of a primitive test relative to a traversal step
//   empty_bonus        float (default 0.2)  SAH discount for splits that cut off empty space
//   max_depth          integer (default 0)  depth limit; 0 = 8 + 1.3 log₂ N (at most 60)
//
// Reference: I. Wald, V. Havran, "On building fast kd-Trees for Ray Tracing, and on doing
// that in O(N log N)", IEEE Symposium on Interactive Ray Tracing 2006.
#include "primitives.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iintersect.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <numeric>

namespace effigi {
namespace {

using accel::Primitive;

class KdTree final : public Implements<IIntersect> {
public:
    static Schema schema() {
        Schema s("accelerator", "kdtree", "SAH kd-tree (own implementation), Wald & Havran 2006.");
        s.cite("I. Wald, V. Havran, On building fast kd-Trees for Ray Tracing, and on doing that in O(N log N), "
               "IEEE RT 2006");
        s.real("intersection_cost", 1.5, "Cost of one primitive test relative to one traversal step").range(0.01, 1000.0);
        s.real("empty_bonus", 0.2, "SAH discount for splits that leave one side empty").range(0.0, 0.99);
        s.integer("max_depth", 0, "Depth limit; 0 = 8 + 1.3 log2(N), at most 60").range(0, 60);
        s.addConformance({"default", {}});
        s.addConformance({"depth 12, no bonus", {{"max_depth", std::int64_t(12)}, {"empty_bonus", 0.0}}});
        return s;
    }

    explicit KdTree(const Properties& p)
        : m_isectCost(p.getFloat("intersection_cost")), m_emptyBonus(p.getFloat("empty_bonus")),
          m_maxDepth(int(p.getInt("max_depth"))) {}

    void build(std::span<const IShape* const> shapes) override {
        m_shapes.assign(shapes.begin(), shapes.end());
        m_prims = accel::gatherPrimitives(m_shapes);
        std::vector<Event> events;
        events.reserve(6 * m_prims.size());
        m_pad.resize(m_prims.size());
        for (std::uint32_t i = 0; i < m_prims.size(); ++i) {
            BBox3f b = accel::primitiveBounds(m_prims[i], m_shapes);
            m_pad[i] = std::max(maxAbsComponent(b.min), maxAbsComponent(b.max)) * 0x1p-21f;
            m_bbox.expand(b);
            addEvents(events, i, b);
        }
        if (m_prims.empty()) return;
        int depth = m_maxDepth > 0 ? m_maxDepth : int(std::lround(8.0 + 1.3 * std::log2(double(m_prims.size()))));
        m_depthLimit = std::min(depth, 60);
        std::sort(events.begin(), events.end());  // once: children inherit the order (§5.3)
        m_side.assign(m_prims.size(), Side::Both);
        m_box.resize(m_prims.size());
        buildNode(m_bbox, events, m_prims.size(), 0);
        m_pad = {}, m_side = {}, m_box = {};
    }

    bool intersect(const Ray& ray, Hit& hit) const override { return trace<false>(ray, &hit); }
    bool occluded(const Ray& ray) const override { return trace<true>(ray, nullptr); }
    BBox3f bbox() const override { return m_bbox; }

private:
    /// 8 bytes: word = split position (interior, as float bits) or first leaf reference;
    /// bits = axis (0–2) or 3 (leaf) in the low two bits, above-child index or count above.
    struct Node {
        std::uint32_t word, bits;
        bool leaf() const { return (bits & 3u) == 3u; }
    };
    struct Split {
        float cost = Infinity, pos = 0.f;
        int axis = -1;
        bool planarLeft = false;
    };
    /// A primitive's bounds in a cell seen along one axis: where they start and end, or
    /// one planar event when they are flat in that axis.
    struct Event {
        float pos;
        std::uint32_t prim;
        std::uint8_t axis, type;  // type 0 end, 1 planar, 2 start: their order at one position
        bool operator<(const Event& o) const {
            if (axis != o.axis) return axis < o.axis;
            return pos < o.pos || (pos == o.pos && type < o.type);
        }
    };
    enum class Side : std::uint8_t { Below, Above, Both };
    static constexpr float TraversalCost = 1.f;
    static constexpr float Widen = 0x1p-18f;  // relative widening of cell intervals at split planes

    static BBox3f clipped(const BBox3f& b, const BBox3f& cell) {
        BBox3f c;
        c.min = glm::max(b.min, cell.min);
        c.max = glm::min(b.max, cell.max);
        return c;
    }

    /// Bounds of the part of primitive p inside `cell`, within its bounds `b` so far: a
    /// triangle is clipped to the cell (Havran's "perfect splits", which Wald & Havran
    /// use), so a long thin triangle is not referenced by every cell its bounding box
    /// touches. The clip is against the cell grown by the primitive's padding and its
    /// bounds are padded again, so that rounding cannot drop a part the triangle test would
    /// hit; an empty result means the triangle misses the cell. Analytic shapes keep their
    /// box, clipped.
    BBox3f cellBounds(std::uint32_t p, const BBox3f& b, const BBox3f& cell) const {
        BBox3f c = clipped(b, cell);
        const Primitive& prim = m_prims[p];
        if (prim.prim == Primitive::Analytic || !c.valid()) return c;
        const double pad = double(m_pad[p]);
        std::array<Vector3d, 9> poly{Vector3d(prim.p0), Vector3d(prim.p1), Vector3d(prim.p2)}, next;
        int n = 3;
        for (int a = 0; a < 3 && n > 0; ++a)
            for (int side = 0; side < 2 && n > 0; ++side) {  // Sutherland–Hodgman against one face
                double bound = side ? double(cell.max[a]) + pad : double(cell.min[a]) - pad;
                auto inside = [&](const Vector3d& v) { return side ? v[a] <= bound : v[a] >= bound; };
                int m = 0;
                for (int k = 0; k < n; ++k) {
                    const Vector3d &u = poly[std::size_t(k)], &v = poly[std::size_t((k + 1) % n)];
                    if (inside(u)) next[std::size_t(m++)] = u;
                    if (inside(u) != inside(v)) next[std::size_t(m++)] = u + (v - u) * ((bound - u[a]) / (v[a] - u[a]));
                }
                poly = next;
                n = m;
            }
        if (n == 0) return BBox3f();
        Vector3d lo = poly[0], hi = poly[0];
        for (int k = 1; k < n; ++k) lo = glm::min(lo, poly[std::size_t(k)]), hi = glm::max(hi, poly[std::size_t(k)]);
        return clipped(BBox3f(Point3f(lo - pad), Point3f(hi + pad)), c);
    }

    /// SAH cost of splits of one cell along one axis.
    struct Sah {
        float lo, hi, n, cross, perim, scale, emptyFactor;
        Sah(const BBox3f& cell, int a, float n_, float isectCost, float emptyBonus)
            : lo(cell.min[a]), hi(cell.max[a]), n(n_), emptyFactor(1.f - emptyBonus) {
            Vector3f e = cell.extents();
            cross = e[(a + 1) % 3] * e[(a + 2) % 3];
            perim = e[(a + 1) % 3] + e[(a + 2) % 3];
            scale = 2.f * isectCost / cell.surfaceArea();
        }
        float operator()(float pos, float nl, float nr) const {
            // A split at the cell's face leaves one child equal to the cell: it must at
            // least shed primitives there, or the recursion makes no progress.
            if ((pos <= lo && nr >= n) || (pos >= hi && nl >= n)) return Infinity;
            float al = cross + (pos - lo) * perim, ar = cross + (hi - pos) * perim;
            float c = TraversalCost + scale * (al * nl + ar * nr);
            return nl == 0.f || nr == 0.f ? emptyFactor * c : c;
        }
    };

    static void addEvents(std::vector<Event>& out, std::uint32_t prim, const BBox3f& b) {
        for (std::uint8_t a = 0; a < 3; ++a) {
            if (b.min[a] == b.max[a]) {
                out.push_back({b.min[a], prim, a, 1});
            } else {
                out.push_back({b.min[a], prim, a, 2});
                out.push_back({b.max[a], prim, a, 0});
            }
        }
    }

    /// The SAH sweep of Wald & Havran (§4.2): every event position on every axis, the
    /// counts of primitives below, in and above the plane updated event by event.
    Split findSplit(const BBox3f& cell, const std::vector<Event>& events, std::size_t count) const {
        Split best;
        const float n = float(count);
        for (std::size_t i = 0; i < events.size();) {
            const int a = events[i].axis;
            const Sah sah(cell, a, n, m_isectCost, m_emptyBonus);
            float nl = 0.f, nr = n;
            while (i < events.size() && events[i].axis == a) {
                const float pos = events[i].pos;
                float ends = 0.f, planar = 0.f, starts = 0.f;
                auto at = [&](int type) { return i < events.size() && events[i].axis == a && events[i].pos == pos && events[i].type == type; };
                for (; at(0); ++i) ends += 1.f;
                for (; at(1); ++i) planar += 1.f;
                for (; at(2); ++i) starts += 1.f;
                nr -= planar + ends;
                float left = sah(pos, nl + planar, nr), right = sah(pos, nl, nr + planar);
                if (left < best.cost) best = Split{left, pos, a, true};
                if (right < best.cost) best = Split{right, pos, a, false};
                nl += starts + planar;
            }
        }
        return best;
    }

    /// Builds the subtree of `cell` over the `count` primitives whose events (sorted) are
    /// given; the events are consumed. The children's event lists keep the order: events
    /// of primitives on one side are copied in order, only those of primitives straddling
    /// the plane are made anew (from their clipped parts), sorted and merged in (§5.3).
    void buildNode(const BBox3f& cell, std::vector<Event>& events, std::size_t count, int depth) {
        std::uint32_t index = std::uint32_t(m_nodes.size());
        m_nodes.push_back({});
        Split s;
        if (count > 0 && depth < m_depthLimit && cell.surfaceArea() > 0.f) s = findSplit(cell, events, count);
        if (!(s.cost < m_isectCost * float(count))) {
            m_nodes[index] = Node{std::uint32_t(m_refs.size()), std::uint32_t(count) << 2 | 3u};
            for (const Event& e : events)  // each primitive starts or is planar once on axis 0
                if (e.axis == 0 && e.type != 0) m_refs.push_back(e.prim);
            events = {};
            return;
        }
        // Classify (§5.1): a primitive ending at or below the plane is below it, one
        // starting at or above it above, one lying in it where the SAH put it; the rest
        // straddle it. Straddlers' bounds are gathered from their events meanwhile.
        for (const Event& e : events) {
            if (e.axis == 0 && e.type != 0) m_side[e.prim] = Side::Both;
            BBox3f& b = m_box[e.prim];
            if (e.type != 0) b.min[e.axis] = e.pos;
            if (e.type != 2) b.max[e.axis] = e.pos;
            if (e.axis != s.axis) continue;
            if (e.type == 0 && e.pos <= s.pos) m_side[e.prim] = Side::Below;
            else if (e.type == 2 && e.pos >= s.pos) m_side[e.prim] = Side::Above;
            else if (e.type == 1)
                m_side[e.prim] = e.pos < s.pos || (e.pos == s.pos && s.planarLeft) ? Side::Below : Side::Above;
        }
        BBox3f cb = cell, ca = cell;
        cb.max[s.axis] = s.pos;
        ca.min[s.axis] = s.pos;
        std::vector<Event> below, above, newBelow, newAbove;
        std::size_t nb = 0, na = 0;
        for (const Event& e : events) {
            Side side = m_side[e.prim];
            bool first = e.axis == 0 && e.type != 0;
            if (side == Side::Below) below.push_back(e), nb += first;
            else if (side == Side::Above) above.push_back(e), na += first;
            else if (first) {  // a straddler, once: its parts on either side, and neither part it misses
                BBox3f l = cellBounds(e.prim, m_box[e.prim], cb), r = cellBounds(e.prim, m_box[e.prim], ca);
                if (l.valid()) addEvents(newBelow, e.prim, l), ++nb;
                if (r.valid()) addEvents(newAbove, e.prim, r), ++na;
            }
        }
        events = {};
        auto merged = [](std::vector<Event>& kept, std::vector<Event>& added) {
            std::sort(added.begin(), added.end());
            std::vector<Event> out(kept.size() + added.size());
            std::merge(kept.begin(), kept.end(), added.begin(), added.end(), out.begin());
            kept = {}, added = {};
            return out;
        };
        below = merged(below, newBelow);
        above = merged(above, newAbove);
        buildNode(cb, below, nb, depth + 1);
        m_nodes[index] = Node{std::bit_cast<std::uint32_t>(s.pos), std::uint32_t(m_nodes.size()) << 2 | std::uint32_t(s.axis)};
        buildNode(ca, above, na, depth + 1);
    }

    /// Closest hit (AnyHit = false) or the first hit found (AnyHit = true).
    template <bool AnyHit> bool trace(const Ray& ray, Hit* hit) const {
        if (m_nodes.empty()) return false;
        accel::SlabRay slab(ray);
        float tMin, tMax;
        if (!slab.clip(m_bbox.min, m_bbox.max, ray.tMax, tMin, tMax)) return false;
        WatertightRay wr(ray.o, ray.d);
        float best = ray.tMax;
        bool found = false;
        struct Todo {
            std::uint32_t node;
            float tMin, tMax;
        };
        std::array<Todo, 64> stack;
        int sp = 0;
        std::uint32_t idx = 0;
        for (;;) {
            if (tMin <= best) {  // a cell entered beyond the closest hit cannot hold a nearer one
                const Node& node = m_nodes[idx];
                if (!node.leaf()) {
                    int a = int(node.bits & 3u);
                    float pos = std::bit_cast<float>(node.word), oa = ray.o[a], da = ray.d[a];
                    std::uint32_t below = idx + 1, above = node.bits >> 2;
                    bool belowFirst = oa < pos || (oa == pos && da <= 0.f);
                    std::uint32_t first = belowFirst ? below : above, second = belowFirst ? above : below;
                    if (da == 0.f) {
                        if (oa == pos) stack[std::size_t(sp++)] = {second, tMin, tMax};  // in the plane: both
                        idx = first;
                        continue;
                    }
                    float tSplit = (pos - oa) * slab.inv[a], widen = Widen * std::abs(tSplit);
                    if (tSplit <= 0.f || tSplit > tMax + widen) {
                        idx = first;
                    } else if (tSplit < tMin - widen) {
                        idx = second;
                    } else {
                        stack[std::size_t(sp++)] = {second, std::max(tMin, tSplit - widen), tMax};
                        idx = first;
                        tMax = std::min(tMax, tSplit + widen);
                    }
                    continue;
                }
                std::uint32_t first = node.word, count = node.bits >> 2;
                for (std::uint32_t i = first; i < first + count; ++i)
                    if (accel::intersectPrimitive(m_prims[m_refs[i]], ray, wr, m_shapes, best, hit)) {
                        if constexpr (AnyHit) return true;
                        found = true;
                    }
            }
            // Cells wait on the stack front to back, but their widened starts need not be
            // sorted exactly, so the rest are popped (and skipped) rather than dropped.
            if (sp == 0) break;
            const Todo& t = stack[std::size_t(--sp)];
            idx = t.node, tMin = t.tMin, tMax = t.tMax;
        }
        return found;
    }

    float m_isectCost, m_emptyBonus;
    int m_maxDepth, m_depthLimit = 0;
    std::vector<const IShape*> m_shapes;
    std::vector<Primitive> m_prims;
    // During the build only: each primitive's bounds padding, side of the current split
    // and bounds in the current cell.
    std::vector<float> m_pad;
    std::vector<Side> m_side;
    std::vector<BBox3f> m_box;
    std::vector<Node> m_nodes;
    std::vector<std::uint32_t> m_refs;
    BBox3f m_bbox;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::KdTree)
