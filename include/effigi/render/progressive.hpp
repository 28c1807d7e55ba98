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

struct PassReport {
    std::uint64_t spp = 0;    ///< samples per pixel so far (of the whole job)
    double seconds = 0.0;     ///< rendering time so far (passes only, not the callback)
    RenderStats stats;        ///< totals so far
    double estimatedRelMSE = -1.0;  ///< the renderer's own estimate, < 0 if it has none
    /// Sample indices this process has used in every pixel (with its seed): its next pass
    /// starts there. Equal to spp in a render of one process.
    std::uint64_t processSpp = 0;
};

class PassSharing;

struct ProgressiveOptions {
    double timeBudget = 0.0;    ///< seconds of rendering; 0 = none
    std::uint64_t spp = 0;      ///< total samples per pixel; 0 = unlimited if a budget or target is set
    double targetRelMSE = 0.0;  ///< stop once the renderer's own relMSE estimate is below; 0 = off
    bool progress = true;       ///< progress bar on stderr
    /// Cut passes so that none should take longer (checkpoints are written between
    /// passes; the doubling would otherwise space them ever further apart); 0 = no limit.
    /// Read before every pass: the pass callback may change it (effigi render --preview
    /// shortens passes while a page watches).
    double maxPassSeconds = 0.0;
    /// A resumed render (effigi render --resume): the job's report when it was saved; its
    /// processSpp is this process's first sample index. The budget counts from it.
    PassReport resumed;
    /// Whether this process's film (and the renderer's sums) already hold resumed sums:
    /// its first pass adds to them instead of preparing the film.
    bool filmResumed = false;
    /// Null: one process renders the whole job. Else its share of every pass (MPI ranks).
    PassSharing* sharing = nullptr;
};

/// A progressive render spread over several processes that each render a share of every
/// pass with a seed of their own (apps/effigi/render_mpi.cpp). All of them run the same
/// sequence of passes and make the same decisions, from the job's numbers; the methods
/// marked collective must be called by every process at the same point.
class PassSharing {
public:
    virtual ~PassSharing() = default;
    /// Number of processes; the first pass gives each one sample per pixel.
    virtual std::uint64_t processes() const = 0;
    /// This process's share of a pass of `spp` samples per pixel of the whole job.
    virtual std::uint64_t share(std::uint64_t spp) const = 0;
    /// Collective: this process's totals and time so far become the whole job's (samples
    /// summed, interrupted by any, the longest time), the same in every process.
    virtual void combine(RenderStats& totals, double& seconds) = 0;
    /// Collective: the whole job's film and renderer sums (with the renderer's error
    /// statistics if `errorStatistics`) pooled into the root's, the others' cleared.
    /// True in the root, whose film then holds the job's image.
    virtual bool gather(bool errorStatistics) = 0;
    /// Collective: the root's value, everywhere.
    virtual double fromRoot(double value) = 0;
};

/// Called after each pass (the film holds the image so far); return false to stop.
using PassCallback = std::function<bool(const PassReport&)>;

/// Render progressively; `base` supplies threads, seed and the stop flag. `last`, if
/// given, receives the report after the last pass (also one cut short by a stop request).
RenderStats renderProgressive(const Scene& scene, const RenderControl& base, const ProgressiveOptions& options,
                              const PassCallback& afterPass = {}, PassReport* last = nullptr);

} // namespace effigi
