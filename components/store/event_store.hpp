#pragma once
// What every event store (components/store/*.cpp) shares: the positions in insertion
// order with their validation, the "built?" bookkeeping, and the bounded max-heap of a
// k-nearest-neighbour query (Jensen 2001, §6.3: the k best candidates so far, the worst
// on top, whose distance shrinks the search radius).
//
// Exactness. Stores compare distances as eventDistance2() computes them and order by
// (d², index) (IEventStore). A subtree or cell may be skipped only when a lower bound of
// every computed d² inside it is *greater* than the current bound: candidates at exactly
// the bound can still win on their index. A lower bound from a split plane or a cell
// face is exact in floats: with |x − q| ≥ |s − q| on one axis, rounding is monotone, so
// fl(q − x)² ≥ fl(q − s)², and adding the other (non-negative) squares cannot lower it.
#include "effigi/core/error.hpp"
#include "effigi/core/properties.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ieventstore.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace effigi::store {

/// The k best (d², index) pairs seen so far with d² ≤ r², as a max-heap in the caller's
/// out[0..k) (no allocation). bound() is the squared search radius: r² until k are
/// found, then the worst of them.
struct KnnHeap {
    EventNeighbour* out;
    std::size_t k, n = 0;
    float r2;

    KnnHeap(EventNeighbour* o, std::size_t kk, float maxRadius) : out(o), k(kk), r2(maxRadius * maxRadius) {}

    float bound() const { return n == k ? out[0].dist2 : r2; }
    void push(float d2, std::uint32_t index) {
        if (!(d2 <= r2)) return;  // also refuses NaN (a NaN query point finds nothing)
        const EventNeighbour e{index, d2};
        if (n < k) {
            out[n++] = e;
            std::push_heap(out, out + n);
        } else if (e < out[0]) {
            std::pop_heap(out, out + k);
            out[k - 1] = e;
            std::push_heap(out, out + k);
        }
    }
    /// Sorts the heap ascending by (d², index); returns how many were found.
    std::size_t finish() {
        std::sort_heap(out, out + n);
        return n;
    }
};

/// The part of IEventStore that does not depend on the search structure.
class EventStoreBase : public Implements<IEventStore> {
public:
    explicit EventStoreBase(const Properties& p) : m_where(p.where()), m_name(p.describe()) {}

    void clear() override {
        m_points.clear();
        m_built = false;
    }
    void insert(std::span<const Point3f> positions) override {
        // All or nothing: a bad position leaves the store as it was.
        for (std::size_t i = 0; i < positions.size(); ++i) {
            const Point3f& q = positions[i];
            if (!(std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z)))
                failAt(m_where, "{}: event {} has a non-finite position ({}, {}, {})", m_name, m_points.size() + i,
                       q.x, q.y, q.z);
        }
        if (m_points.size() + positions.size() > std::numeric_limits<std::uint32_t>::max())
            failAt(m_where, "{}: more than 2^32 - 1 events (indices are 32-bit)", m_name);
        m_points.insert(m_points.end(), positions.begin(), positions.end());
        m_built = false;
    }
    std::size_t size() const override { return m_points.size(); }
    Point3f position(std::uint32_t i) const override { return m_points[i]; }

protected:
    /// Call at the end of build().
    void markBuilt() {
        m_built = true;
        m_builtSize = m_points.size();
    }
    /// Whether a query has anything to search; an error if events were inserted since
    /// the last build() (the structure would silently miss them).
    bool searchable() const {
        if (m_points.empty()) return false;
        if (!m_built || m_builtSize != m_points.size())
            failAt(m_where, "{}: queried with {} events inserted since the last build()", m_name,
                   m_points.size() - (m_built ? m_builtSize : 0));
        return true;
    }
    std::size_t pointBytes() const { return m_points.capacity() * sizeof(Point3f); }

    std::vector<Point3f> m_points;  ///< insertion order: event i is m_points[i]
    SourceLocation m_where;
    std::string m_name;

private:
    bool m_built = false;
    std::size_t m_builtSize = 0;
};

} // namespace effigi::store
