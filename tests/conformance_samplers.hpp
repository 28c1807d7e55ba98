#pragma once
// Samplers for tests/test_conformance.cpp: a correct jittered / Latin-hypercube sampler
// (the sampler suite's stratification and convergence checks must pass it) and random
// samplers that break one promise each.
#include "effigi/interfaces/isampler.hpp"
#include "effigi/math/rng.hpp"

#include <numeric>
#include <vector>

namespace effigi::conformtest {

/// Per pixel, every one of the first Dims get2D() dimensions places its spp samples one
/// per cell of an nx × ny grid (nx ny = spp, nx = ny when spp is a square) with a random
/// permutation of the cells, jittered inside them; every get1D() dimension is a Latin
/// hypercube the same way. Claims: Latin hypercube, jittered 2D, RMS error ∝ N^-1 for
/// smooth and N^-3/4 for discontinuous 2D integrands (the jittered-sampling rates:
/// variance Σ over strata, O(N · N^-2 / N) resp. O(√N / N²)).
class TestJittered final : public Implements<ISampler> {
public:
    static constexpr int Dims = 8;
    TestJittered(int spp, std::uint64_t seed) : m_spp(spp), m_seed(seed) {
        m_nx = 1;
        while (m_nx * m_nx < spp) m_nx *= 2;
        m_ny = (spp + m_nx - 1) / m_nx;
        if (m_nx * m_ny != spp) m_nx = spp, m_ny = 1;  // not a power of two: 1D strata
        startPixel(Point2i(0));
    }
    SamplerClaims claims() const override {
        return {StratifyLatinHypercube | StratifyJittered2D, -1.0, -0.75};
    }
    int samplesPerPixel() const override { return m_spp; }
    void startPixel(const Point2i& p) override {
        m_key = mixBits(m_seed ^ mixBits((std::uint64_t(std::uint32_t(p.x)) << 32) | std::uint32_t(p.y)));
        PCG32 rng(m_key, 77);
        m_perm.assign(2 * Dims, std::vector<int>(std::size_t(m_spp)));
        for (auto& perm : m_perm) {
            std::iota(perm.begin(), perm.end(), 0);
            for (int i = m_spp - 1; i > 0; --i) std::swap(perm[std::size_t(i)], perm[rng.nextUInt() % std::uint32_t(i + 1)]);
        }
        startSample(0);
    }
    void startSample(std::uint64_t index) override {
        m_index = index;
        m_d1 = m_d2 = 0;
        m_rng.seed(mixBits(m_key ^ mixBits(index + 1)), m_key);
    }
    float get1D() override {
        int d = m_d1++;
        if (d >= Dims || m_index >= std::uint64_t(m_spp)) return m_rng.nextFloat();
        int s = m_perm[std::size_t(d)][m_index];
        return std::min((float(s) + m_rng.nextFloat()) / float(m_spp), OneMinusEpsilon);
    }
    Point2f get2D() override {
        int d = m_d2++;
        if (d >= Dims || m_index >= std::uint64_t(m_spp)) return {m_rng.nextFloat(), m_rng.nextFloat()};
        int s = m_perm[std::size_t(Dims + d)][m_index];
        float x = (float(s % m_nx) + m_rng.nextFloat()) / float(m_nx);
        float y = (float(s / m_nx) + m_rng.nextFloat()) / float(m_ny);
        return {std::min(x, OneMinusEpsilon), std::min(y, OneMinusEpsilon)};
    }
    Ref<ISampler> clone(std::uint64_t offset) const override { return std::make_shared<TestJittered>(m_spp, m_seed + offset); }

private:
    int m_spp, m_nx = 1, m_ny = 1;
    std::uint64_t m_seed, m_key = 0, m_index = 0;
    int m_d1 = 0, m_d2 = 0;
    std::vector<std::vector<int>> m_perm;
    PCG32 m_rng;
};

/// Independent random values with one fault.
class TestRandom final : public Implements<ISampler> {
public:
    enum Fault { ClaimsTooMuch, Correlated, ReturnsOne };
    TestRandom(int spp, Fault f) : m_spp(spp), m_fault(f) { startPixel(Point2i(0)); }
    SamplerClaims claims() const override {
        // Claims jittered sampling and its smooth rate, delivers plain Monte Carlo.
        if (m_fault == ClaimsTooMuch) return {StratifyJittered2D, -1.0, -0.5};
        return {};
    }
    int samplesPerPixel() const override { return m_spp; }
    void startPixel(const Point2i& p) override {
        m_key = mixBits((std::uint64_t(std::uint32_t(p.x)) << 32) | std::uint32_t(p.y));
        startSample(0);
    }
    void startSample(std::uint64_t index) override {
        m_rng.seed(mixBits(m_key ^ mixBits(index + 1)), m_key);
        m_count = 0;
    }
    float get1D() override {
        float v = m_rng.nextFloat();
        ++m_count;
        if (m_fault == Correlated && m_count % 2 == 0) {
            // Uniform on its own (a uniform shifted mod 1), but tied to the previous value.
            v = m_last + 0.1f * v;
            if (v >= 1.f) v -= 1.f;
        }
        if (m_fault == ReturnsOne && m_rng.nextUInt() % 1000 == 0) v = 1.f;
        m_last = v;
        return v;
    }
    Point2f get2D() override {
        float x = get1D();
        return {x, get1D()};
    }
    Ref<ISampler> clone(std::uint64_t) const override { return std::make_shared<TestRandom>(m_spp, m_fault); }

private:
    int m_spp;
    Fault m_fault;
    std::uint64_t m_key = 0;
    int m_count = 0;
    float m_last = 0.f;
    PCG32 m_rng;
};

} // namespace effigi::conformtest
