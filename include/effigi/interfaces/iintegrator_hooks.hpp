#pragma once
// Optional interfaces between an IIntegrator and the IFunction it integrates; neither
// side needs them, and an integrator or integrand without them behaves as before.
//
// IWeightedSampler — implemented by the sampler an integrator hands to the integrand when
// its points are not uniform on [0,1)^d or do not count equally (VEGAS's grid, adaptive
// stratification) or when it may stop before its budget. An integrand that records its
// samples itself (a pixel's integrand splats each sample into the film) asks for the
// weight q of the current sample once it has drawn its dimensions and records
// Σ q f / Σ q: the integrator's own estimate (or an equally consistent one). q = 1 for
// a uniform sample; q = 0 for a sample that only explores and is not in the estimate.
//
// IIntegrationObserver — implemented by an integrand that wants to know what an adaptive
// integrator did (tests, effigi-conform, diagnostics): its stages (iterations, rounds),
// their consistency (χ²/dof, Lepage 1978), the VEGAS grid, the strata.
//
// IPixelAllocator — implemented by an integrator that spreads a render pass's samples
// unevenly over the image (per-pixel adaptive sampling), which one pixel's integral cannot
// do alone. A renderer that knows it (renderSampled) draws a pass in two parts: a pilot of
// the same count in every pixel, then the counts allocate() gives each pixel from all the
// pilots. The two parts of a pixel weigh into it by shares fixed before either is drawn,
// so the pixel stays unbiased however the counts depend on the pilot (Kirk & Arvo 1991);
// and every pixel weighs into its neighbours as if it had drawn the whole budget.
#include "effigi/interfaces/iintegrator.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace effigi {

class IWeightedSampler : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IWeightedSampler");
    static constexpr const char* Tag = "sampler";

    /// Weight of the current sample (the one begun by the last startSample) in the
    /// integrator's estimate; valid once the integrand has drawn its dimensions.
    virtual double sampleWeight() const = 0;
};

/// What an adaptive integrator reports at the end of one integrate() call.
struct IntegrationReport {
    /// Estimate of each stage, in order (VEGAS iterations, adaptive rounds).
    std::vector<Estimate> stages;
    /// The leading stages that only trained the integrator and are not in its estimate.
    int trainingStages = 0;
    /// χ²/dof of the estimating stages about their combined value (Lepage 1978); NaN
    /// when there are fewer than two or a stage has no finite, positive variance.
    double chi2PerDof = std::numeric_limits<double>::quiet_NaN();
    /// VEGAS: the bin edges of each adapted dimension, 0 = x₀ < x₁ < … < x_K = 1.
    std::vector<std::vector<double>> grid;
    /// Adaptive stratification: the final strata, boxes over the stratified dimensions.
    struct Stratum {
        std::vector<double> lower, upper;
        std::uint64_t samples = 0;  ///< evaluations drawn in it (its own, not its parent's)
        double sigma = 0.0;         ///< estimated standard deviation of f in it
    };
    std::vector<Stratum> strata;
};

/// χ²/dof of stages[first..] about their inverse-variance weighted mean, over every
/// channel (Lepage 1978): ≈ 1 when the stages agree within their error bars; NaN when
/// fewer than two stages or a variance that is not finite and positive.
inline double stageChi2PerDof(const std::vector<Estimate>& stages, std::size_t first, int channels) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    if (stages.size() < first + 2 || channels < 1) return nan;
    double chi2 = 0.0;
    for (int c = 0; c < channels; ++c) {
        double wsum = 0.0, mean = 0.0;
        for (std::size_t k = first; k < stages.size(); ++k) {
            const double v = stages[k].variance[c];
            if (!(v > 0.0) || !std::isfinite(v)) return nan;
            wsum += 1.0 / v, mean += stages[k].mean[c] / v;
        }
        mean /= wsum;
        for (std::size_t k = first; k < stages.size(); ++k) {
            const double d = stages[k].mean[c] - mean;
            chi2 += d * d / stages[k].variance[c];
        }
    }
    return chi2 / double(channels) / double(stages.size() - first - 1);
}

class IIntegrationObserver : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IIntegrationObserver");
    static constexpr const char* Tag = "function";

    /// Called once at the end of each integrate() call by integrators that report.
    virtual void integrated(const IntegrationReport& report) = 0;
};

/// What a pixel's pilot found: the mean of its linear sRGB and the variance of that mean.
struct PixelPilot {
    float mean[3] = {0.f, 0.f, 0.f}, variance[3] = {0.f, 0.f, 0.f};
    std::uint32_t samples = 0;
};

class IPixelAllocator : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IPixelAllocator");
    static constexpr const char* Tag = "integrator";

    struct Plan {
        std::uint64_t pilot = 0;  ///< samples every pixel draws first; 0: one uniform part
        double pilotShare = 0.0;  ///< the pilot's weight in each pixel, the rest 1 − it
    };
    /// How a pass of `budget` samples a pixel (indices [first, first + budget)) is split.
    virtual Plan plan(std::uint64_t budget) const = 0;
    /// For each pixel of the width × height pilots (row-major), how many samples it draws
    /// after its pilot: 1 to budget − pilot, so that its indices stay within the pass's.
    virtual void allocate(std::span<const PixelPilot> pilots, int width, int height, std::uint64_t budget,
                          std::vector<std::uint64_t>& counts) const = 0;
};

} // namespace effigi
