// store "bad_neighbour_store" — DELIBERATELY WRONG test plugin: answers with another
// store (kdtree by default), except that one query in 10⁴ — chosen by a hash of the query
// (point, k or radius), as a rare numerical slip would be — comes back wrong by one
// neighbour: a knn answer has its last neighbour replaced by the next one (or, when
// there is no next one, dropped); a radius answer loses its last event.
//
// Every other promise holds (insertion order, errors, thread safety, cost), so
// effigi-conform must fail it on exactness checks only, and surely on "many queries":
// 10⁵ queries with about 8.5·10⁴ non-empty answers miss a fault in 1 of 10⁴ with
// probability (1 − 10⁻⁴)^85000 ≈ 2·10⁻⁴ (tests/plugins/run_plugin_tests.cmake; with the
// suite's fixed seed it is caught on 5 of the 10⁵ queries).
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ieventstore.hpp"

#include <bit>
#include <vector>

namespace {
using namespace effigi;

class BadNeighbourStore final : public Implements<IEventStore> {
public:
    static Schema schema() {
        Schema s("store", "bad_neighbour_store", "Test plugin: one query in 10^4 returns a wrong neighbour.");
        s.string("inner", "kdtree", "Store whose answers it spoils");
        return s;
    }

    explicit BadNeighbourStore(const Properties& p) {
        Properties q("store", p.getString("inner"));
        m_inner = query<IEventStore>(Registry::instance().create("store", p.getString("inner"), q));
        if (!m_inner) failAt(p.whereOf("inner"), "{}: '{}' is not a store", p.describe(), p.getString("inner"));
    }

    void clear() override { m_inner->clear(); }
    void insert(std::span<const Point3f> positions) override { m_inner->insert(positions); }
    std::size_t size() const override { return m_inner->size(); }
    Point3f position(std::uint32_t i) const override { return m_inner->position(i); }
    void build(float radiusHint) override { m_inner->build(radiusHint); }
    std::size_t memoryBytes() const override { return m_inner->memoryBytes(); }

    std::size_t knn(const Point3f& p, std::size_t k, float maxRadius, EventNeighbour* out) const override {
        if (k == 0 || !unlucky(p, k)) return m_inner->knn(p, k, maxRadius, out);
        thread_local std::vector<EventNeighbour> more;
        more.resize(k + 1);
        std::size_t n = m_inner->knn(p, k + 1, maxRadius, more.data());
        if (n == k + 1) more[k - 1] = more[k];  // the bug: the (k+1)-th instead of the k-th
        n = n == k + 1 ? k : (n > 0 ? n - 1 : 0);
        std::copy(more.begin(), more.begin() + std::ptrdiff_t(n), out);
        return n;
    }

    void radius(const Point3f& p, float r, std::vector<EventNeighbour>& out) const override {
        m_inner->radius(p, r, out);
        if (!out.empty() && unlucky(p, std::bit_cast<std::uint32_t>(r))) out.pop_back();
    }

private:
    /// One query in 10⁴, by a hash of its inputs (the same answer on every thread).
    static bool unlucky(const Point3f& p, std::uint64_t extra) {
        std::uint64_t h = 1469598103934665603ull;
        for (std::uint64_t v : {std::uint64_t(std::bit_cast<std::uint32_t>(p.x)), std::uint64_t(std::bit_cast<std::uint32_t>(p.y)),
                                std::uint64_t(std::bit_cast<std::uint32_t>(p.z)), extra}) {
            h = (h ^ v) * 1099511628211ull;
            h ^= h >> 29;
        }
        h ^= h >> 33;  // MurmurHash3's finaliser: every input bit reaches the low digits
        h *= 0xff51afd7ed558ccdull;
        h ^= h >> 33;
        return h % 10000 == 0;
    }

    Ref<IEventStore> m_inner;
};

} // namespace

EFFIGI_EXPORT_COMPONENT(BadNeighbourStore)
