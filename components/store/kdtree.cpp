// store "kdtree" — a balanced kd-tree over event positions in an implicit array layout
// (Jensen 2001, §6.3–6.4; no pointers, no per-node allocation).
//
// Build: the events of a range [lo, hi) are split at their median m = (lo + hi)/2 along
// the axis of widest extent of the range's bounding box, with nth_element, so that
//   x[a] ≤ node[m][a] for i ∈ [lo, m)   and   x[a] ≥ node[m][a] for i ∈ (m, hi);
// node m is the split, [lo, m) and [m + 1, hi) its subtrees. The tree is therefore
// balanced (depth ⌈log₂(n / leaf_size)⌉ + 1) and held entirely in the order of one array:
// a range of at most leaf_size events is a leaf scanned linearly. O(n log n) time (one
// bounding box and one linear selection per level), O(n) memory: 29 bytes per event
// (the insertion-order position, a 16-byte node, one byte of split axis).
//
// knn: depth-first, nearer subtree first, the k best in a bounded max-heap (KnnHeap,
// ordered by (d², index)); the far subtree is skipped when its split-plane distance²
// exceeds the heap's bound — the squared search radius, which shrinks to the worst
// of the k once k are found (Jensen's "locate photons"). radius: the same descent with a
// fixed bound, collecting, then sorting by (d², index). Both are exact (event_store.hpp
// for why a plane bound is exact in floats) and allocate nothing beyond `out`.
//
// Parameters:
//   leaf_size  int (default 8, 1..64)  ranges at most this large are scanned linearly
//
// Reference: H. W. Jensen, "Realistic Image Synthesis Using Photon Mapping", 2001, §6.3
// (balanced kd-tree, locating the nearest photons); J. L. Bentley, "Multidimensional
// binary search trees used for associative searching", CACM 18(9), 1975.
#include "event_store.hpp"

#include <tbb/parallel_invoke.h>

namespace effigi {
namespace {

class KdTreeStore final : public store::EventStoreBase {
public:
    static Schema schema() {
        Schema s("store", "kdtree",
                 "Balanced kd-tree over event positions in an implicit array (median split on the widest axis); "
                 "exact k-nearest-neighbour and radius queries.");
        s.cite("H. W. Jensen, Realistic Image Synthesis Using Photon Mapping, 2001, §6.3");
        s.integer("leaf_size", 8, "Ranges of at most this many events are leaves, scanned linearly").range(1, 64);
        s.addConformance({"default", {}});
        s.addConformance({"leaf_size = 1", {{"leaf_size", std::int64_t(1)}}});
        s.addConformance({"leaf_size = 64", {{"leaf_size", std::int64_t(64)}}});
        return s;
    }

    explicit KdTreeStore(const Properties& p) : EventStoreBase(p), m_leafSize(std::uint32_t(p.getInt("leaf_size"))) {}

    void clear() override {
        EventStoreBase::clear();
        m_nodes.clear();
        m_axis.clear();
    }

    void build(float /*radiusHint: a kd-tree adapts to the data*/) override {
        const std::uint32_t n = std::uint32_t(m_points.size());
        m_nodes.resize(n);
        m_axis.assign(n, 0);
        for (std::uint32_t i = 0; i < n; ++i) m_nodes[i] = {m_points[i], i};
        buildRange(0, n);
        markBuilt();
    }

    std::size_t knn(const Point3f& p, std::size_t k, float maxRadius, EventNeighbour* out) const override {
        if (k == 0 || !searchable()) return 0;
        store::KnnHeap heap(out, k, maxRadius);
        traverse(p, [&](float d2, std::uint32_t i) { heap.push(d2, i); }, [&] { return heap.bound(); });
        return heap.finish();
    }

    void radius(const Point3f& p, float r, std::vector<EventNeighbour>& out) const override {
        out.clear();
        if (!searchable()) return;
        const float r2 = r * r;
        traverse(
            p, [&](float d2, std::uint32_t i) { if (d2 <= r2) out.push_back({i, d2}); }, [r2] { return r2; });
        std::sort(out.begin(), out.end());
    }

    std::size_t memoryBytes() const override {
        return sizeof(*this) + pointBytes() + m_nodes.capacity() * sizeof(Node) + m_axis.capacity();
    }

private:
    struct Node {
        Point3f p;
        std::uint32_t index;  ///< the event's insertion index
    };

    /// Median split of [lo, hi) on the widest axis, then its two halves (in parallel
    /// where they are large enough to pay for a task).
    void buildRange(std::uint32_t lo, std::uint32_t hi) {
        if (hi - lo <= m_leafSize) return;
        Point3f a = m_nodes[lo].p, b = a;
        for (std::uint32_t i = lo + 1; i < hi; ++i) {
            a = glm::min(a, m_nodes[i].p);
            b = glm::max(b, m_nodes[i].p);
        }
        const Point3f extent = b - a;
        const int axis = extent.x >= extent.y ? (extent.x >= extent.z ? 0 : 2) : (extent.y >= extent.z ? 1 : 2);
        const std::uint32_t m = lo + (hi - lo) / 2;
        std::nth_element(m_nodes.begin() + lo, m_nodes.begin() + m, m_nodes.begin() + hi,
                         [axis](const Node& u, const Node& v) { return u.p[axis] < v.p[axis]; });
        m_axis[m] = std::uint8_t(axis);
        if (hi - lo > 65536)
            tbb::parallel_invoke([&] { buildRange(lo, m); }, [&] { buildRange(m + 1, hi); });
        else {
            buildRange(lo, m);
            buildRange(m + 1, hi);
        }
    }

    /// Depth-first descent, nearer child first: visit(d², index) for every event not
    /// pruned; a far subtree is pruned when its plane distance² > bound() (strictly:
    /// events at exactly the bound may still win a tie on their index).
    template <typename Visit, typename Bound> void traverse(const Point3f& p, Visit&& visit, Bound&& bound) const {
        struct Pending {
            std::uint32_t lo, hi;
            float d2;  ///< lower bound of every d² in [lo, hi)
        };
        Pending stack[64];  // one entry per level at most; depth ≤ 33 for n < 2³²
        int top = 0;
        std::uint32_t lo = 0, hi = std::uint32_t(m_nodes.size());
        for (;;) {
            while (hi - lo > m_leafSize) {
                const std::uint32_t m = lo + (hi - lo) / 2;
                const Node& node = m_nodes[m];
                visit(eventDistance2(p, node.p), node.index);
                const int axis = m_axis[m];
                const float diff = p[axis] - node.p[axis], d2 = diff * diff;
                Pending far{lo, m, d2};
                if (diff < 0.f) {
                    far = {m + 1, hi, d2};
                    hi = m;
                } else {
                    lo = m + 1;
                }
                if (d2 <= bound()) stack[top++] = far;
            }
            for (std::uint32_t i = lo; i < hi; ++i) visit(eventDistance2(p, m_nodes[i].p), m_nodes[i].index);
            do {
                if (top == 0) return;
                --top;
            } while (stack[top].d2 > bound());
            lo = stack[top].lo;
            hi = stack[top].hi;
        }
    }

    std::uint32_t m_leafSize;
    std::vector<Node> m_nodes;         ///< the tree, in range order
    std::vector<std::uint8_t> m_axis;  ///< split axis of each inner node (by array position)
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::KdTreeStore)
