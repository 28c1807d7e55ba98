#pragma once
// The irradiance cache of renderer `irradiancecache`: records of indirect irradiance with
// their gradients (made by irradiance_gather.hpp) and the weighted interpolation that
// reads them back.
//
// Lookup (Ward 1988): record i (of the 32 nearest) serves (p, n) when
// ε_i = ‖p − p_i‖/R_i + √(1 − n·n_i) < a and p_i is not in front of p; the estimate is the
// average of E_i + (n_i × n)·∇_r + (p − p_i)·∇_t with weights 1/ε_i − 1/a (Ward's 1/ε
// shifted to vanish at the edge of the validity region, so that the interpolant is
// continuous; Křivánek & Gautron 2009, §2.3).
// Records are inserted in batches in a fixed order with neighbour clamping (Křivánek et al.
// 2006: R_i ≤ R_j + ‖p_i − p_j‖ both ways), so the cache is deterministic.
//
// Spectral: a record holds E and its gradients at Nodes = 16 wavelengths evenly spaced over
// 360–830 nm (31.3 nm apart) and is read at any camera wavelength by interpolation.
#include "effigi/interfaces/ieventstore.hpp"
#include "effigi/spectral/wavelengths.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <vector>

namespace effigi::irrcache {

inline constexpr int Nodes = 16;
inline constexpr float NodeSpacing = (LambdaMax - LambdaMin) / float(Nodes - 1);
inline float nodeLambda(int i) { return LambdaMin + NodeSpacing * float(i); }
using NodeValues = std::array<float, Nodes>;
using NodeVectors = std::array<Vector3f, Nodes>;

/// One cached irradiance value (events.hpp's pattern: the cache keeps these in insertion
/// order, its IEventStore indexes their positions).
struct IrradianceRecord {
    Point3f p{0.f};
    Normal3f n{0.f, 0.f, 1.f};  ///< shading normal, on the side the light was gathered from
    NodeValues E{};              ///< indirect irradiance, W m⁻² nm⁻¹ at each node
    NodeVectors rotGrad{}, transGrad{};
    float R = 0.f;               ///< validity radius: rawR clamped to [minR, maxR]
    float rawR = 0.f;            ///< harmonic mean distance after gradient and neighbour limits
    float minR = 0.f, maxR = Infinity;
};

/// Node values at the four camera wavelengths: Catmull-Rom cubic interpolation (error
/// O(h⁴ E⁗) against linear's O(h² E''), which in a red-walled enclosure, where the indirect
/// spectrum ∝ ρ(λ)/(1 − ρ(λ)) is sharpened by the bounces, put +3.4 % into R), clamped at 0
/// where the cubic undershoots.
inline SampledSpectrum atWavelengths(const NodeValues& v, const SampledWavelengths& lambda) {
    SampledSpectrum out;
    for (int s = 0; s < NSpectrumSamples; ++s) {
        float x = std::clamp((lambda[s] - LambdaMin) / NodeSpacing, 0.f, float(Nodes - 1));
        int i = std::min(int(x), Nodes - 2);
        float t = x - float(i);
        const float p0 = v[std::max(i - 1, 0)], p1 = v[i], p2 = v[i + 1], p3 = v[std::min(i + 2, Nodes - 1)];
        const float c = 0.5f * (2.f * p1 + t * ((p2 - p0) + t * ((2.f * p0 - 5.f * p1 + 4.f * p2 - p3) +
                                                                t * (3.f * (p1 - p2) + p3 - p0))));
        out[s] = std::max(c, 0.f);
    }
    return out;
}

/// The records, an IEventStore over their positions, Ward's interpolation.
class IrradianceCache {
public:
    /// Records a lookup considers: the nearest this many (in coarse-to-fine caches a point
    /// lies in a handful of validity regions; farther records would weigh next to nothing).
    static constexpr std::size_t MaxNeighbours = 32;

    void reset(Ref<IEventStore> store, bool clampNeighbour) {
        m_store = std::move(store);
        m_store->clear();
        m_records.clear();
        m_maxR = 0.f;
        m_clampNeighbour = clampNeighbour;
    }
    bool empty() const { return m_records.empty(); }
    std::size_t size() const { return m_records.size(); }
    const std::vector<IrradianceRecord>& records() const { return m_records; }
    std::size_t memoryBytes() const {
        return m_records.capacity() * sizeof(IrradianceRecord) + (m_store ? m_store->memoryBytes() : 0);
    }

    /// Append a batch (in its order: deterministic), clamping radii against the records
    /// already there and each other, then rebuild the store.
    void add(std::vector<IrradianceRecord> batch) {
        const std::size_t first = m_records.size();
        std::vector<EventNeighbour> near;
        for (IrradianceRecord& r : batch) {
            if (m_clampNeighbour) {
                auto clampPair = [&](IrradianceRecord& q) {
                    const float d = std::sqrt(eventDistance2(r.p, q.p));
                    r.rawR = std::min(r.rawR, q.rawR + d);
                    if (q.rawR > r.rawR + d) {
                        q.rawR = r.rawR + d;
                        q.R = std::clamp(q.rawR, q.minR, q.maxR);
                    }
                };
                if (first > 0 && std::isfinite(r.rawR)) {
                    m_store->radius(r.p, r.rawR, near);
                    for (const EventNeighbour& e : near) clampPair(m_records[e.index]);
                }
                for (std::size_t i = first; i < m_records.size(); ++i)
                    if (eventDistance2(r.p, m_records[i].p) < r.rawR * r.rawR) clampPair(m_records[i]);
            }
            r.R = std::clamp(r.rawR, r.minR, r.maxR);
            m_records.push_back(r);
        }
        // Inserting invalidates the store's structure: only after the batch's queries.
        std::vector<Point3f> positions;
        for (std::size_t i = first; i < m_records.size(); ++i) positions.push_back(m_records[i].p);
        m_store->insert(positions);
        m_maxR = 0.f;
        for (const IrradianceRecord& r : m_records) m_maxR = std::max(m_maxR, r.R);
        m_store->build();
    }

    /// Interpolated irradiance at p with normal n (unit, on the side to shade) from the
    /// records within Ward's error a; false where none qualifies.
    bool lookup(const Point3f& p, const Vector3f& n, float a, bool gradients, NodeValues& E,
                std::vector<EventNeighbour>& near) const {
        if (m_records.empty()) return false;
        // The nearest MaxNeighbours within the largest validity radius: a radius query
        // alone returns most of the cache wherever one record's radius is large.
        near.resize(MaxNeighbours);
        const std::size_t found = m_store->knn(p, MaxNeighbours, a * m_maxR, near.data());
        double wSum = 0.0;
        std::array<double, Nodes> sum{};
        for (std::size_t k = 0; k < found; ++k) {
            const EventNeighbour& e = near[k];
            const IrradianceRecord& r = m_records[e.index];
            const float cosN = dot(n, r.n);
            if (cosN <= 0.f) continue;
            const Vector3f dp = p - r.p;
            // Ward's test: a record in front of p sees light p does not.
            // (Tolerance: 5 % of the validity radius, at most 5 % of R however large a is.)
            if (dot(dp, (n + r.n) * 0.5f) < -0.05f * std::min(a, 1.f) * r.R) continue;
            const float eps = std::sqrt(e.dist2) / r.R + std::sqrt(std::max(0.f, 1.f - cosN));
            if (!(eps < a)) continue;
            const double w = 1.0 / std::max(eps, 1e-6f) - 1.0 / a;
            const Vector3f nxn = cross(r.n, n);
            for (int i = 0; i < Nodes; ++i) {
                float v = r.E[i];
                if (gradients) v += dot(nxn, r.rotGrad[i]) + dot(dp, r.transGrad[i]);
                sum[i] += w * std::max(v, 0.f);
            }
            wSum += w;
        }
        if (!(wSum > 0.0)) return false;
        for (int i = 0; i < Nodes; ++i) E[i] = float(sum[i] / wSum);
        return true;
    }

private:
    Ref<IEventStore> m_store;
    std::vector<IrradianceRecord> m_records;
    float m_maxR = 0.f;
    bool m_clampNeighbour = true;
};

} // namespace effigi::irrcache
