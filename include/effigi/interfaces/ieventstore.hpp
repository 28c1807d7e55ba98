#pragma once
// IEventStore — EFFIGI's event store: points in space ("events": photons, irradiance
// records, SPPM visible points) kept in a spatial structure and found again by
// k-nearest-neighbour or radius queries. Components: kdtree (left-balanced, Jensen 2001),
// hashgrid (uniform hashed grid, for fixed-radius queries as SPPM makes them).
//
// The store holds positions only and answers with indices: event i is the i-th position
// inserted since the last clear(). The events themselves (Photon, IrradianceRecord in
// effigi/render/events.hpp) stay in the caller's array in insertion order, so one store
// serves every kind of event and a plugin store needs no knowledge of them.
//
// Determinism. Distances are compared as eventDistance2() computes them (float, one fixed
// order of operations) and ties are broken by index, so every correct store returns
// exactly the same neighbours, bit for bit, as the brute-force definition:
//   knn(p, k, r):  the k smallest (d², index) pairs with d² ≤ r², ascending by (d², index);
//   radius(p, r):  every event with d² ≤ r², ascending by (d², index).
// conformance/store_suite.cpp checks this against brute force.
//
// Concurrency and memory. insert() and build() are not thread-safe; queries are const,
// thread-safe after build(), and write only into caller-owned storage (no allocation per
// query once the caller's vector has grown). Inserting after build() invalidates the
// structure until the next build(), which covers every event inserted so far; a query in
// between is an effigi::Error (an empty store answers nothing).
#include "effigi/core/component.hpp"
#include "effigi/math/vector.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace effigi {

/// One answer of a query: which event, and its squared distance to the query point.
struct EventNeighbour {
    std::uint32_t index = 0;
    float dist2 = 0.f;

    friend bool operator<(const EventNeighbour& a, const EventNeighbour& b) {
        return a.dist2 < b.dist2 || (a.dist2 == b.dist2 && a.index < b.index);
    }
    friend bool operator==(const EventNeighbour& a, const EventNeighbour& b) {
        return a.index == b.index && a.dist2 == b.dist2;
    }
};

/// The squared distance every store compares (the same float operations everywhere, so
/// that stores and brute force agree exactly at ties and at the radius).
inline float eventDistance2(const Point3f& a, const Point3f& b) {
    float dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
    return (dx * dx + dy * dy) + dz * dz;
}

class IEventStore : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IEventStore");
    static constexpr const char* Tag = "store";

    /// Forget every event (keeps capacity).
    virtual void clear() = 0;
    /// Append events at these positions; their indices continue from size().
    /// Non-finite positions are an error (effigi::Error).
    virtual void insert(std::span<const Point3f> positions) = 0;
    /// Events inserted since clear().
    virtual std::size_t size() const = 0;
    /// Position of event i (i < size()).
    virtual Point3f position(std::uint32_t i) const = 0;
    /// Build (or rebuild) the search structure over every event inserted so far.
    /// `radiusHint` is the radius most queries will use (hashgrid sizes its cells from
    /// it; 0 = choose from the data); a store must answer every radius correctly anyway.
    virtual void build(float radiusHint = 0.f) = 0;

    /// The k nearest events with d² ≤ maxRadius² (maxRadius may be +∞), written to
    /// out[0..n) ascending by (d², index); returns n ≤ k. `out` holds at least k entries.
    virtual std::size_t knn(const Point3f& p, std::size_t k, float maxRadius, EventNeighbour* out) const = 0;

    /// Every event with d² ≤ radius², replacing the contents of `out`, ascending by
    /// (d², index).
    virtual void radius(const Point3f& p, float radius, std::vector<EventNeighbour>& out) const = 0;

    /// Bytes held by the store (reported by renderers as their map's memory).
    virtual std::size_t memoryBytes() const = 0;
};

} // namespace effigi
