#pragma once
// IRenderer — the rendering method (Mitsuba's top-level "integrator"): path, aov, ...
// It fills the camera's film; render() returns counts for the final report.
#include "effigi/core/component.hpp"

#include <atomic>
#include <cstdint>

namespace effigi {

class Scene;

struct RenderControl {
    const std::atomic<bool>* stop = nullptr;  ///< set asynchronously (SIGINT) to end early
    bool progress = true;                      ///< draw a progress bar on stderr
    int threads = 0;                           ///< 0 = all cores
    std::uint64_t seed = 0;                    ///< added to the sampler's seed

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
};

} // namespace effigi
