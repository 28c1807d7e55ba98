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

/// Where a renderer's rays and time went (`effigi render --stats`), kept by renderers that
/// trace in stages (path's wavefront mode). Times are thread-seconds summed over threads.
struct WorkStats {
    enum Ray { Camera, Extension, Shadow, RayKinds };
    std::uint64_t rays[RayKinds] = {0, 0, 0};     ///< rays traced, by kind
    double traceSeconds[RayKinds] = {0, 0, 0};    ///< in the accelerator's batch calls, by kind
    double cameraSeconds = 0;  ///< generating camera samples (sampler, wavelengths, camera)
    double shadeSeconds = 0;   ///< surface interactions, emission, light and BSDF sampling
    double filmSeconds = 0;    ///< colour conversion and splatting into the film
    bool kept = false;         ///< false: the renderer keeps no such counts

    void merge(const WorkStats& o) {
        for (int k = 0; k < RayKinds; ++k) rays[k] += o.rays[k], traceSeconds[k] += o.traceSeconds[k];
        cameraSeconds += o.cameraSeconds, shadeSeconds += o.shadeSeconds, filmSeconds += o.filmSeconds;
        kept = kept || o.kept;
    }
};

struct RenderStats {
    std::uint64_t samples = 0;         ///< camera samples taken
    std::uint64_t rejectedSamples = 0; ///< NaN/Inf samples kept off the film
    double seconds = 0.0;
    bool interrupted = false;
    WorkStats work;
};

class IRenderer : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IRenderer");
    static constexpr const char* Tag = "renderer";

    virtual RenderStats render(const Scene& scene, const RenderControl& control) = 0;

    /// What the renderer does with a scene's participating media (Scene::hasMedia()):
    /// refuses the scene (the loader reports it), ignores the media as Mitsuba's surface
    /// integrators do (boundaries are crossed as their BSDFs say; the loader warns), or
    /// renders them.
    enum class MediaSupport { Refuses, Ignores, Renders };
    virtual MediaSupport mediaSupport() const { return MediaSupport::Refuses; }

    /// Whether the renderer renders motion blur (Scene::hasMotion()): every ray it traces
    /// carries the time of its path, from a camera ray timed within the shutter. The
    /// loader refuses a moving scene to the others in one line.
    virtual bool rendersMotion() const { return false; }

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
