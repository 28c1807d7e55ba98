#pragma once
// Progressive rendering: a scene's renderer run in passes whose sample counts double
// (1, 1, 2, 4, ... samples per pixel, so the totals are 1, 2, 4, 8, ...) until a sample
// count, a time budget or a noise target is reached. Each pass continues the same
// per-pixel sample sequences and adds to the film, so stopping after any pass leaves
// a complete image. `effigi render --time/--spp/--target-relmse` and `effigi converge`
// run on this.
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/render/scene.hpp"

#include <functional>

namespace effigi {

struct ProgressiveOptions {
    double timeBudget = 0.0;    ///< seconds of rendering; 0 = none
    std::uint64_t spp = 0;      ///< total samples per pixel; 0 = unlimited if a budget or target is set
    double targetRelMSE = 0.0;  ///< stop once the renderer's own relMSE estimate is below; 0 = off
    bool progress = true;       ///< progress bar on stderr
};

struct PassReport {
    std::uint64_t spp = 0;    ///< samples per pixel so far
    double seconds = 0.0;     ///< rendering time so far (passes only, not the callback)
    RenderStats stats;        ///< totals so far
    double estimatedRelMSE = -1.0;  ///< the renderer's own estimate, < 0 if it has none
};

/// Called after each pass (the film holds the image so far); return false to stop.
using PassCallback = std::function<bool(const PassReport&)>;

/// Render progressively; `base` supplies threads, seed and the stop flag.
RenderStats renderProgressive(const Scene& scene, const RenderControl& base, const ProgressiveOptions& options,
                              const PassCallback& afterPass = {});

} // namespace effigi
