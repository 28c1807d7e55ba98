#pragma once
// IRenderer — the rendering method (Mitsuba's top-level "integrator"): path, aov, ...
// It fills the camera's film; render() returns counts for the final report.
#include "effigi/core/component.hpp"

#include <atomic>
#include <cstdint>
#include <vector>

namespace effigi {

class Scene;

struct RenderControl {
    const std::atomic<bool>* stop = nullptr;  ///< set asynchronously (SIGINT) to end early
    bool progress = true;                      ///< draw a progress bar on stderr
    int threads = 0;                           ///< 0 = all cores
    std::uint64_t seed = 0;                    ///< added to the sampler's seed
    /// Progressive rendering: this pass takes sample indices [sampleOffset, sampleOffset +
    /// sampleCount) of every pixel (sampleCount 0 = the sampler's sample_count) and, with
    /// accumulate, adds them to the film instead of starting a new image.
    std::uint64_t sampleOffset = 0;
    std::uint64_t sampleCount = 0;
    bool accumulate = false;

    bool stopRequested() const { return stop && stop->load(std::memory_order_relaxed); }
};

struct RenderStats {
    std::uint64_t samples = 0;         ///< camera samples taken
    std::uint64_t rejectedSamples = 0; ///< NaN/Inf samples kept off the film
    double seconds = 0.0;
    bool interrupted = false;
};

class IRenderer : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IRenderer");
    static constexpr const char* Tag = "renderer";

    virtual RenderStats render(const Scene& scene, const RenderControl& control) = 0;

    /// The renderer's own estimate of its error so far: for every pixel of the film
    /// (crop, row-major) and each of R, G, B (linear, the film's colour space before
    /// output), the variance of the pixel's value — 3 floats per pixel. False when the
    /// renderer keeps none (then only a reference image can tell its error).
    virtual bool varianceEstimate(std::vector<float>& variance) const {
        (void)variance;
        return false;
    }
};

} // namespace effigi
