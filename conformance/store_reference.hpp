#pragma once
// The brute-force definition of IEventStore's answers, and the point sets the store
// suite (conformance/store_suite.cpp), tests/test_store.cpp and bench/store_bench.cpp
// run stores on. Header-only: the tests and the bench include it without linking the
// conformance library.
#include "effigi/interfaces/ieventstore.hpp"
#include "effigi/math/rng.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

namespace effigi::conform {

/// IEventStore's answers by definition, from every event's (d², index) at one query
/// point. at(q, depth) sorts only the `depth` nearest (nth_element), which answers every
/// knn with k ≤ depth and every radius query whose answer is shorter than depth; the
/// others fall back to filtering and sorting all n.
class BruteForce {
public:
    explicit BruteForce(std::span<const Point3f> points) : m_points(points) {}

    void at(const Point3f& q, std::size_t depth = std::size_t(-1)) {
        m_all.clear();
        for (std::size_t i = 0; i < m_points.size(); ++i) {
            float d2 = eventDistance2(q, m_points[i]);
            if (!std::isnan(d2)) m_all.push_back({std::uint32_t(i), d2});  // NaN is within no radius
        }
        m_sorted = std::min(depth, m_all.size());
        std::nth_element(m_all.begin(), m_all.begin() + std::ptrdiff_t(m_sorted), m_all.end());
        std::sort(m_all.begin(), m_all.begin() + std::ptrdiff_t(m_sorted));
    }

    /// The k smallest (d², index) with d² ≤ maxRadius², ascending.
    std::vector<EventNeighbour> knn(std::size_t k, float maxRadius) const {
        const float r2 = maxRadius * maxRadius;
        if (k > m_sorted && m_sorted < m_all.size()) {
            std::vector<EventNeighbour> all = within(r2);
            if (all.size() > k) all.resize(k);
            return all;
        }
        std::vector<EventNeighbour> out;
        for (std::size_t i = 0; i < k && i < m_sorted && m_all[i].dist2 <= r2; ++i) out.push_back(m_all[i]);
        return out;
    }

    /// Every (d², index) with d² ≤ r², ascending.
    std::vector<EventNeighbour> radius(float r) const {
        const float r2 = r * r;
        if (m_sorted == m_all.size() || (m_sorted > 0 && m_all[m_sorted - 1].dist2 > r2))
            return knn(m_sorted, r);
        return within(r2);
    }

private:
    std::vector<EventNeighbour> within(float r2) const {
        std::vector<EventNeighbour> out;
        for (const EventNeighbour& e : m_all)
            if (e.dist2 <= r2) out.push_back(e);
        std::sort(out.begin(), out.end());
        return out;
    }

    std::span<const Point3f> m_points;
    std::vector<EventNeighbour> m_all;  ///< (index, d²) of every event; [0, m_sorted) sorted
    std::size_t m_sorted = 0;
};

/// The point sets a store is checked on. `scale` is the extent of the set (radii of
/// queries are chosen relative to it).
enum class PointSet { Uniform, Clustered, Coplanar, Collinear, Duplicates, AllEqual, Huge, Tiny };

inline const char* pointSetName(PointSet s) {
    switch (s) {
    case PointSet::Uniform: return "uniform";
    case PointSet::Clustered: return "clustered";
    case PointSet::Coplanar: return "coplanar";
    case PointSet::Collinear: return "collinear";
    case PointSet::Duplicates: return "duplicates";
    case PointSet::AllEqual: return "all equal";
    case PointSet::Huge: return "huge (1e6)";
    case PointSet::Tiny: return "tiny (1e-6)";
    }
    return "?";
}

inline float pointSetScale(PointSet s) { return s == PointSet::Huge ? 1e6f : s == PointSet::Tiny ? 1e-6f : 1.f; }

/// A standard normal deviate (Box–Muller).
inline float gaussian(PCG32& rng) {
    const double u = 1.0 - rng.nextDouble(), v = rng.nextDouble();
    return float(std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * 3.14159265358979323846 * v));
}

/// n points of a set:
///  uniform     [0, 1)³
///  clustered   16 Gaussian blobs, σ from 0.002 to 0.05, centres uniform in [0.1, 0.9)³
///  coplanar    z = 0.5, (x, y) uniform
///  collinear   on the diagonal (t, 2t, 3t)/√14 + (0.1, 0.2, 0.3)
///  duplicates  every point one of n/8 + 1 sites of the lattice (i/8, j/8, l/8), i, j, l < 9:
///              exact duplicates and many equal distances (ties decided by index)
///  all equal   (0.3, 0.3, 0.3), n times
///  huge        uniform in [−1e6, 1e6)³;  tiny  uniform in [0, 1e-6)³
inline std::vector<Point3f> makePoints(PointSet s, std::size_t n, PCG32& rng) {
    std::vector<Point3f> p(n);
    auto uniform = [&] { return Point3f(rng.nextFloat(), rng.nextFloat(), rng.nextFloat()); };
    switch (s) {
    case PointSet::Uniform:
        for (auto& x : p) x = uniform();
        break;
    case PointSet::Clustered: {
        Point3f centre[16];
        float sigma[16];
        for (int c = 0; c < 16; ++c) {
            centre[c] = 0.1f + 0.8f * uniform();
            sigma[c] = 0.002f * std::pow(25.f, float(c) / 15.f);
        }
        for (auto& x : p) {
            int c = int(rng.nextUInt() % 16);
            x = centre[c] + sigma[c] * Point3f(gaussian(rng), gaussian(rng), gaussian(rng));
        }
        break;
    }
    case PointSet::Coplanar:
        for (auto& x : p) x = Point3f(rng.nextFloat(), rng.nextFloat(), 0.5f);
        break;
    case PointSet::Collinear: {
        const Point3f d = Point3f(1.f, 2.f, 3.f) / std::sqrt(14.f);
        for (auto& x : p) x = Point3f(0.1f, 0.2f, 0.3f) + rng.nextFloat() * d;
        break;
    }
    case PointSet::Duplicates: {
        std::vector<Point3f> sites(n / 8 + 1);
        for (auto& x : sites)
            x = Point3f(float(rng.nextUInt() % 9), float(rng.nextUInt() % 9), float(rng.nextUInt() % 9)) * 0.125f;
        for (auto& x : p) x = sites[rng.nextUInt() % sites.size()];
        break;
    }
    case PointSet::AllEqual:
        for (auto& x : p) x = Point3f(0.3f);
        break;
    case PointSet::Huge:
        for (auto& x : p) x = (uniform() - 0.5f) * 2e6f;
        break;
    case PointSet::Tiny:
        for (auto& x : p) x = uniform() * 1e-6f;
        break;
    }
    return p;
}

} // namespace effigi::conform
