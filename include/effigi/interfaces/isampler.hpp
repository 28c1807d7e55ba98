#pragma once
// ISampler — points in [0,1)^n, one sequence per pixel and sample index, consumed a
// dimension at a time. Each rendering thread works on its own clone().
#include "effigi/core/component.hpp"
#include "effigi/math/vector.hpp"

#include <cstdint>

namespace effigi {

/// Stratification a sampler promises for the samplesPerPixel() samples of one pixel
/// (bit flags; effigi-conform checks each claimed one on the first four dimensions).
enum SamplerStratification : std::uint32_t {
    StratifyNone = 0,
    /// Drawn with get1D(): each dimension has one value in each of the spp equal
    /// intervals of [0,1) (a Latin hypercube).
    StratifyLatinHypercube = 1u << 0,
    /// Drawn with get2D() (spp a square): each 2D dimension has one point in each cell of
    /// the √spp × √spp grid (jittered sampling).
    StratifyJittered2D = 1u << 1,
    /// The first get2D() of spp = 2^m samples is a (0, m, 2)-net in base 2: every
    /// elementary interval of area 2^-m holds exactly one point.
    StratifyElementary2D = 1u << 2,
};

/// What a sampler claims about its points; the conformance runner holds it to them.
struct SamplerClaims {
    std::uint32_t stratification = StratifyNone;  ///< SamplerStratification flags
    /// Exponent r of the RMS error of an N-sample mean, ∝ N^r, for a smooth 2D integrand
    /// and for a discontinuous one (plain Monte Carlo: −0.5 for both), over N = 4..4096.
    double smoothRate = -0.5, discontinuousRate = -0.5;
};

class ISampler : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("ISampler");
    static constexpr const char* Tag = "sampler";

    /// The sampler's promises (default: none beyond uniform, independent values).
    virtual SamplerClaims claims() const { return {}; }

    virtual int samplesPerPixel() const = 0;
    /// Select the sequence of a pixel (or any integration domain keyed by two ints).
    virtual void startPixel(const Point2i& pixel) = 0;
    /// Start sample `index` of the current pixel at dimension 0.
    virtual void startSample(std::uint64_t index) = 0;

    virtual float get1D() = 0;
    virtual Point2f get2D() = 0;
    /// The film-position sample (some samplers stratify it specially).
    virtual Point2f getPixel2D() { return get2D(); }

    /// An independent copy for another thread, reseeded by `streamOffset`.
    virtual Ref<ISampler> clone(std::uint64_t streamOffset) const = 0;
};

} // namespace effigi
