// sampler "stratified" — jittered (stratified) sampling, one point per stratum.
//
// A pixel's sample_count samples are spread over sample_count strata in every
// dimension: a 1D draw (get1D) splits [0,1) into sample_count intervals, a 2D draw
// (get2D, getPixel2D) splits [0,1)² into a √n × √n grid, and each sample gets one
// stratum, jittered uniformly inside it. Which sample gets which stratum is a
// pseudo-random permutation keyed by (pixel, dimension, seed), different for every
// dimension so that dimensions do not correlate (Cook, Porter & Carpenter 1984 padded
// with random permutations; pbrt-v4 §8.5). The permutation is evaluated directly for a
// sample index — nothing is carried from sample to sample — so any order of indices and
// any split into progressive passes yields identical values.
//
// For smooth 2D integrands jittered sampling converges as N^-1 in RMS error
// (N^(-1/2-1/d), d = 2), for integrands with discontinuities along curves as N^-3/4
// (Mitchell 1996, "Consequences of Stratified Sampling in Graphics").
//
// Parameters:
//   sample_count  int  (default 4, >= 1)  samples per pixel; rounded UP to the next
//                                         square (as Mitsuba 3 does, with a warning)
//   seed          int  (default 0)        changes every sequence
//   jitter        bool (default true)     jitter inside the stratum; false puts every
//                                         point at its stratum's centre (not uniform)
//
// Sample indices ≥ sample_count start another round of the same strata with fresh
// permutations and jitter.
//
// Reference: R. L. Cook, T. Porter, L. Carpenter, "Distributed Ray Tracing", SIGGRAPH 1984;
// D. P. Mitchell, "Consequences of Stratified Sampling in Graphics", SIGGRAPH 1996.
#include "effigi/core/log.hpp"
#include "hashed_sampler.hpp"

#include <algorithm>
#include <cmath>

namespace effigi {
namespace {

class StratifiedSampler final : public HashedSampler<StratifiedSampler> {
public:
    static Schema schema() {
        Schema s("sampler", "stratified",
                 "Jittered stratified samples, strata permuted per pixel and dimension.");
        s.cite("R. L. Cook, T. Porter, L. Carpenter, Distributed Ray Tracing, SIGGRAPH 1984; D. P. Mitchell, "
               "Consequences of Stratified Sampling in Graphics, SIGGRAPH 1996");
        s.integer("sample_count", 4, "Samples per pixel, rounded up to a square (warning)").atLeast(1);
        s.integer("seed", 0, "Seed of every permutation and jitter: equal seeds give identical images");
        s.boolean("jitter", true, "Jitter inside each stratum (false: stratum centres)");
        s.addConformance({"default", {}});
        s.addConformance({"non-square count, other seed", {{"sample_count", std::int64_t(10)}, {"seed", std::int64_t(7)}}});
        s.addConformance({"one sample", {{"sample_count", std::int64_t(1)}, {"seed", std::int64_t(-1)}}});
        return s;
    }

    explicit StratifiedSampler(const Properties& p)
        : HashedSampler(std::uint64_t(p.getInt("seed"))), m_jitter(p.getBool("jitter")) {
        const std::int64_t requested = std::min<std::int64_t>(p.getInt("sample_count"), std::int64_t(1) << 30);
        m_resolution = std::max<std::uint32_t>(1, std::uint32_t(std::sqrt(double(requested))));
        while (std::int64_t(m_resolution) * m_resolution < requested) ++m_resolution;
        m_count = m_resolution * m_resolution;
        if (std::int64_t(m_count) != requested)
            log::warn("sampler \"stratified\": sample_count {} is not a square, using {}", requested, m_count);
        startPixel(Point2i(0));
    }

    StratifiedSampler(const StratifiedSampler&) = default;

    /// Every 1D draw is a Latin hypercube, every 2D draw one point per grid cell; jittered
    /// sampling's smooth rate is N^-1 in 2D (Mitchell 1996, above).
    SamplerClaims claims() const override { return stratumClaims(m_jitter, -1.0); }

    float get1D() override { return permutedStratum1D(m_jitter); }

    Point2f get2D() override {
        std::uint64_t key;
        const std::uint32_t stratum = permutedStratum(key);
        const double res = double(m_resolution);
        return {toUnit((double(stratum % m_resolution) + jitterOffset(m_jitter, key, 1)) / res),
                toUnit((double(stratum / m_resolution) + jitterOffset(m_jitter, key, 2)) / res)};
    }

private:
    bool m_jitter;
    std::uint32_t m_resolution = 1;  // √n (m_count = √n²)
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::StratifiedSampler)
