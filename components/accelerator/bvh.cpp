// accelerator "bvh" — a bounding volume hierarchy built with the binned surface area heuristic.
//
// Models nothing physical: it answers the same closest-hit and any-hit queries as
// bruteforce, faster. The build follows Wald 2007: at each node the primitives'
// centroids are sorted into `bins` equal bins along each axis, the SAH cost
//   C = C_trav + (A_L N_L + A_R N_R) / A
// is evaluated at every bin boundary in one sweep per axis, and the cheapest boundary
// splits the node (a leaf is made instead when no split beats intersecting everything,
// N ≤ max_leaf, or the centroids coincide). Nodes are stored depth first in one flat
// array (the left child follows its parent), so traversal allocates nothing: a small
// fixed stack holds the farther child while the nearer one is visited (front to back),
// and a popped node whose entry distance lies beyond the closest hit so far is skipped.
// Triangles go through the same watertight test as bruteforce (effigi/math/intersect.hpp),
// analytic shapes through IShape::intersect, one primitive each.
//
// Parameters:
//   max_leaf  integer (default 4)   nodes with at most this many primitives become leaves
//   bins      integer (default 16)  SAH candidate bins per axis
//
// Reference: I. Wald, "On fast Construction of SAH-based Bounding Volume Hierarchies",
// IEEE Symposium on Interactive Ray Tracing 2007; traversal bounds after T. Ize,
// "Robust BVH Ray Traversal", JCGT 2(2), 2013.
#include "primitives.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iintersect.hpp"

#include <algorithm>
#include <array>

namespace effigi {
namespace {

using accel::Primitive;

class Bvh final : public Implements<IIntersect> {
public:
    static Schema schema() {
        Schema s("accelerator", "bvh", "Binned-SAH bounding volume hierarchy (own implementation).");
        s.cite("I. Wald, On fast Construction of SAH-based Bounding Volume Hierarchies, IEEE RT 2007");
        s.integer("max_leaf", 4, "Nodes with at most this many primitives become leaves").range(1, 64);
        s.integer("bins", 16, "SAH candidate bins per axis").range(2, 64);
        s.addConformance({"default", {}});
        s.addConformance({"leaf 1, 4 bins", {{"max_leaf", std::int64_t(1)}, {"bins", std::int64_t(4)}}});
        return s;
    }

    explicit Bvh(const Properties& p) : m_maxLeaf(int(p.getInt("max_leaf"))), m_bins(int(p.getInt("bins"))) {}

    void build(std::span<const IShape* const> shapes) override {
        m_shapes.assign(shapes.begin(), shapes.end());
        std::vector<Primitive> prims = accel::gatherPrimitives(m_shapes);
        std::vector<BuildPrim> bp(prims.size());
        for (std::uint32_t i = 0; i < prims.size(); ++i) {
            bp[i].box = accel::primitiveBounds(prims[i], m_shapes);
            bp[i].centroid = bp[i].box.center();
            bp[i].index = i;
            m_bbox.expand(bp[i].box);
        }
        m_nodes.clear();
        if (!bp.empty()) {
            m_nodes.reserve(2 * bp.size() / std::size_t(m_maxLeaf) + 1);
            buildNode(bp, 0, bp.size(), 0);
        }
        m_prims.resize(prims.size());
        for (std::size_t i = 0; i < bp.size(); ++i) m_prims[i] = prims[bp[i].index];  // leaf order
    }

    bool intersect(const Ray& ray, Hit& hit) const override { return trace<false>(ray, &hit); }
    bool occluded(const Ray& ray) const override { return trace<true>(ray, nullptr); }
    BBox3f bbox() const override { return m_bbox; }

private:
    struct BuildPrim {
        BBox3f box;
        Point3f centroid;
        std::uint32_t index;
    };
    /// 32 bytes: bounds, then either the first primitive and count (leaf) or the index of
    /// the second child (interior, count = 0; the first child is the next node).
    struct Node {
        Point3f min, max;
        std::uint32_t offset;
        std::uint32_t count;
    };
    static constexpr int MaxDepth = 100;     // beyond: object-median splits (depth ≤ 100 + log₂ N)
    static constexpr int StackSize = 160;
    static constexpr float TraversalCost = 1.f;  // relative to one primitive test

    std::uint32_t buildNode(std::vector<BuildPrim>& bp, std::size_t begin, std::size_t end, int depth) {
        std::uint32_t index = std::uint32_t(m_nodes.size());
        m_nodes.push_back({});
        BBox3f box, centroids;
        for (std::size_t i = begin; i < end; ++i) box.expand(bp[i].box), centroids.expand(bp[i].centroid);
        std::size_t n = end - begin;
        auto leaf = [&] {
            m_nodes[index] = Node{box.min, box.max, std::uint32_t(begin), std::uint32_t(n)};
            return index;
        };
        if (n <= std::size_t(m_maxLeaf)) return leaf();

        Vector3f extent = centroids.extents();
        std::size_t mid = begin;
        if (extent.x <= 0.f && extent.y <= 0.f && extent.z <= 0.f) {
            // Coincident centroids: no plane separates them. Small sets become a leaf,
            // large ones are split by index (any split is correct, none is better).
            if (n <= 4 * std::size_t(m_maxLeaf)) return leaf();
            mid = begin + n / 2;
        } else if (depth >= MaxDepth) {
            int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
            mid = begin + n / 2;
            std::nth_element(bp.begin() + long(begin), bp.begin() + long(mid), bp.begin() + long(end),
                             [axis](const BuildPrim& a, const BuildPrim& b) { return a.centroid[axis] < b.centroid[axis]; });
        } else {
            // Wald 2007, §3: bin centroids, sweep bin boundaries from both sides.
            float bestCost = Infinity;
            int bestAxis = -1, bestSplit = 0;
            for (int axis = 0; axis < 3; ++axis) {
                if (!(extent[axis] > 0.f)) continue;
                std::array<BBox3f, 64> bounds{};
                std::array<std::size_t, 64> counts{};
                float k = float(m_bins) * (1.f - 0x1p-20f) / extent[axis];
                for (std::size_t i = begin; i < end; ++i) {
                    int b = std::clamp(int(k * (bp[i].centroid[axis] - centroids.min[axis])), 0, m_bins - 1);
                    ++counts[std::size_t(b)];
                    bounds[std::size_t(b)].expand(bp[i].box);
                }
                std::array<float, 64> rightCost{};
                BBox3f acc;
                std::size_t cnt = 0;
                for (int b = m_bins - 1; b > 0; --b) {
                    acc.expand(bounds[std::size_t(b)]);
                    cnt += counts[std::size_t(b)];
                    rightCost[std::size_t(b)] = cnt ? acc.surfaceArea() * float(cnt) : 0.f;
                }
                acc = BBox3f();
                cnt = 0;
                for (int b = 1; b < m_bins; ++b) {  // split between bins b-1 and b
                    acc.expand(bounds[std::size_t(b - 1)]);
                    cnt += counts[std::size_t(b - 1)];
                    if (cnt == 0 || cnt == n) continue;
                    float cost = acc.surfaceArea() * float(cnt) + rightCost[std::size_t(b)];
                    if (cost < bestCost) bestCost = cost, bestAxis = axis, bestSplit = b;
                }
            }
            float area = box.surfaceArea();
            float splitCost = area > 0.f ? TraversalCost + bestCost / area : Infinity;
            // The SAH prefers a leaf (or found no split): take it while the leaf stays small.
            if (!(splitCost < float(n)) && n <= 4 * std::size_t(m_maxLeaf)) return leaf();
            if (bestAxis < 0) {
                mid = begin + n / 2;
            } else {
                float k = float(m_bins) * (1.f - 0x1p-20f) / extent[bestAxis];
                float lo = centroids.min[bestAxis];
                auto it = std::partition(bp.begin() + long(begin), bp.begin() + long(end), [&](const BuildPrim& p) {
                    return std::clamp(int(k * (p.centroid[bestAxis] - lo)), 0, m_bins - 1) < bestSplit;
                });
                mid = std::size_t(it - bp.begin());
            }
        }
        buildNode(bp, begin, mid, depth + 1);
        std::uint32_t second = buildNode(bp, mid, end, depth + 1);
        m_nodes[index] = Node{box.min, box.max, second, 0};
        return index;
    }

    /// Closest hit (AnyHit = false) or the first hit found (AnyHit = true).
    template <bool AnyHit> bool trace(const Ray& ray, Hit* hit) const {
        if (m_nodes.empty()) return false;
        accel::SlabRay slab(ray);
        WatertightRay wr(ray.o, ray.d);
        float tMax = ray.tMax, tEnter;
        if (!slab.hit(m_nodes[0].min, m_nodes[0].max, tMax, tEnter)) return false;
        struct Entry {
            std::uint32_t node;
            float t;
        };
        std::array<Entry, StackSize> stack;
        int sp = 0;
        stack[sp++] = {0, tEnter};
        bool found = false;
        const float grow = 1.f + 2.f * accel::SlabRay::Gamma3;
        while (sp > 0) {
            Entry e = stack[std::size_t(--sp)];
            if (e.t > tMax * grow) continue;  // entered beyond the closest hit so far
            std::uint32_t idx = e.node;
            for (;;) {
                const Node& node = m_nodes[idx];
                if (node.count > 0) {
                    for (std::uint32_t i = node.offset; i < node.offset + node.count; ++i)
                        if (accel::intersectPrimitive(m_prims[i], ray, wr, m_shapes, tMax, hit)) {
                            if constexpr (AnyHit) return true;
                            found = true;
                        }
                    break;
                }
                std::uint32_t a = idx + 1, b = node.offset;
                float ta, tb;
                bool ha = slab.hit(m_nodes[a].min, m_nodes[a].max, tMax, ta);
                bool hb = slab.hit(m_nodes[b].min, m_nodes[b].max, tMax, tb);
                if (ha && hb) {
                    if (tb < ta) std::swap(a, b), std::swap(ta, tb);
                    stack[std::size_t(sp++)] = {b, tb};  // the farther child waits
                    idx = a;
                } else if (ha || hb) {
                    idx = ha ? a : b;
                } else {
                    break;
                }
            }
        }
        return found;
    }

    int m_maxLeaf, m_bins;
    std::vector<const IShape*> m_shapes;
    std::vector<Primitive> m_prims;
    std::vector<Node> m_nodes;
    BBox3f m_bbox;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Bvh)
