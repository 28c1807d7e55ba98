#pragma once
// The state of a Markov chain in primary sample space, as an ISampler (Kelemen et al.
// 2002): the renderer's path estimator runs unchanged on it, and every value it draws is
// one coordinate of the chain's current point in [0,1)^∞. Coordinates are created and
// mutated lazily, as in pbrt-v3's MLTSampler (§16.4.4): each remembers the iteration it
// was last brought up to date at, and when the estimator first asks for it in an
// iteration it catches up on the mutations it missed: a large step since then draws it
// afresh (uniform), and n small steps add one normal offset of standard deviation
// sigma·√n (the sum of n independent N(0, sigma²) steps), wrapped to [0,1). Both kernels
// are symmetric, so the acceptance probability is min(1, f(y)/f(x)).
// reject() restores exactly the values (and time stamps) the iteration changed; one read
// for the first time in it keeps the value it had before the step (drawn when first read).
//
// Streams: an estimator that builds several subpaths (bidirectional: camera, light,
// connection) keeps each on its own stream, so a mutation of one subpath's prefix does
// not shift which coordinates the other reads: coordinate k of stream s is dimension
// s + k · streamCount (pbrt-v3's StartStream). mltStartStream(sampler, s) selects a
// stream on any ISampler (a no-op for the others, whose values are all independent).
//
// Internal to renderer `pssmlt`; not a registered component.
// Reference: Kelemen, Szirmay-Kalos, Antal, Csonka 2002, "A Simple and Robust Mutation
// Strategy for the Metropolis Light Transport Algorithm"; Pharr, Jakob, Humphreys,
// Physically Based Rendering, 3rd ed., §16.4.
#include "effigi/interfaces/isampler.hpp"
#include "effigi/math/rng.hpp"

#include <cmath>
#include <memory>
#include <vector>

namespace effigi {

class PrimarySampleSpaceSampler final : public Implements<ISampler> {
public:
    /// `sigma`: standard deviation of a small step; `largeStepProb`: probability that an
    /// iteration is a large step; `streamCount`: how many streams dimensions interleave.
    PrimarySampleSpaceSampler(float sigma, float largeStepProb, int streamCount = 1)
        : m_sigma(sigma), m_largeStepProb(largeStepProb), m_streamCount(streamCount < 1 ? 1 : streamCount) {}

    /// Forget the state and seed the generator: the next iteration defines every
    /// coordinate afresh (a large step) from `seed` alone.
    void reset(std::uint64_t seed) {
        m_x.clear();
        m_iteration = 0;
        m_lastLargeStep = 0;
        m_largeStep = true;
        m_stream = m_index = 0;
        reseed(seed);
    }
    /// A new generator stream, the state kept: the chain's own mutations after its start
    /// state was regenerated from a bootstrap sample's seed.
    void reseed(std::uint64_t seed) { m_rng.seed(mixBits(seed), mixBits(seed ^ 0x5851f42d4c957f2dull)); }

    /// Begin the next iteration: a large step with probability largeStepProb (or when
    /// `forceLarge`), else a small one; the coordinates change when next read.
    void startIteration(bool forceLarge = false) {
        ++m_iteration;
        m_largeStep = forceLarge || m_rng.nextFloat() < m_largeStepProb;
        m_stream = m_index = 0;
    }
    bool largeStep() const { return m_largeStep; }
    /// Keep the iteration's values.
    void accept() {
        if (m_largeStep) m_lastLargeStep = m_iteration;
    }
    /// Give back the values and time stamps from before the iteration.
    void reject() {
        for (Coordinate& c : m_x)
            if (c.modified == m_iteration) c.value = c.backup, c.modified = c.modifiedBackup;
        --m_iteration;
    }

    /// Select stream `s` (0 .. streamCount − 1) from its first coordinate.
    void startStream(int s) {
        m_stream = s;
        m_index = 0;
    }
    int streamCount() const { return m_streamCount; }
    /// Coordinates created so far (all streams).
    std::size_t dimensions() const { return m_x.size(); }
    std::uint64_t iteration() const { return m_iteration; }
    /// The current state's value of dimension `i` as last read (tests); 0 if never read.
    float coordinate(std::size_t i) const { return i < m_x.size() ? m_x[i].value : 0.f; }

    // ISampler: the current state's coordinates, in order.
    float get1D() override { return value(std::size_t(m_stream) + std::size_t(m_index++) * m_streamCount); }
    Point2f get2D() override {
        float x = get1D();
        return {x, get1D()};
    }
    int samplesPerPixel() const override { return 1; }
    void startPixel(const Point2i&) override {}
    void startSample(std::uint64_t) override { m_stream = m_index = 0; }
    Ref<ISampler> clone(std::uint64_t streamOffset) const override {
        auto copy = std::make_shared<PrimarySampleSpaceSampler>(*this);
        copy->reseed(streamOffset);
        return copy;
    }

private:
    static constexpr std::uint64_t Undefined = ~std::uint64_t(0);
    static constexpr float OneMinusEpsilon = 0x1.fffffep-1f;
    static constexpr double TwoPi = 6.283185307179586;

    struct Coordinate {
        float value = 0.f, backup = 0.f;
        std::uint64_t modified = Undefined, modifiedBackup = Undefined;  ///< iteration it is up to date with
    };

    /// Coordinate `i` brought up to date with the current iteration.
    float value(std::size_t i) {
        if (i >= m_x.size()) m_x.resize(i + 1);
        Coordinate& c = m_x[i];
        if (c.modified == m_iteration) return c.value;
        // Never read, or not since before the last accepted large step: that step drew it
        // afresh, and nothing accepted or rejected since depended on it, so it is drawn
        // now (pbrt-v3 perturbs one first read before any large step was accepted from 0).
        if (c.modified == Undefined || c.modified < m_lastLargeStep) {
            c.value = m_rng.nextFloat();
            c.modified = m_lastLargeStep;
        }
        c.backup = c.value;
        c.modifiedBackup = c.modified;
        if (m_largeStep) {
            c.value = m_rng.nextFloat();
        } else {
            // The n small steps it missed at once: one normal draw (Box–Muller) of
            // variance n·sigma², wrapped to [0,1).
            const double n = double(m_iteration - c.modified);
            const double u1 = 1.0 - m_rng.nextDouble(), u2 = m_rng.nextDouble();
            double v = double(c.value) + m_sigma * std::sqrt(n * -2.0 * std::log(u1)) * std::cos(TwoPi * u2);
            v -= std::floor(v);
            c.value = std::min(float(v), OneMinusEpsilon);
        }
        c.modified = m_iteration;
        return c.value;
    }

    float m_sigma, m_largeStepProb;
    int m_streamCount;
    std::vector<Coordinate> m_x;
    std::uint64_t m_iteration = 0, m_lastLargeStep = 0;
    bool m_largeStep = true;
    int m_stream = 0, m_index = 0;
    PCG32 m_rng;
};

/// Select stream `s` of `sampler` if it is a PrimarySampleSpaceSampler (else nothing: an
/// ordinary sampler's values are independent whichever subpath reads them).
inline void mltStartStream(ISampler& sampler, int s) {
    if (auto* pss = dynamic_cast<PrimarySampleSpaceSampler*>(&sampler)) pss->startStream(s);
}

} // namespace effigi
