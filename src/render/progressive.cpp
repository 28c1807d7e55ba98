#include "effigi/render/progressive.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/progress.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/render/image_metrics.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace effigi {

namespace {

void add(RenderStats& to, const RenderStats& s) {
    to.samples += s.samples;
    to.rejectedSamples += s.rejectedSamples;
    to.work.merge(s.work);
    to.interrupted = to.interrupted || s.interrupted;
}

/// The renderer's relMSE estimate of the job's image (-1: none; -2: the renderer keeps
/// no estimate), the same in every process of a shared render.
double jobEstimate(const Scene& scene, PassSharing* sharing) {
    double e = -1.0;
    if (!sharing || sharing->gather(true)) {
        std::vector<float> variance;
        e = scene.renderer().varianceEstimate(variance) ? estimatedRelMSE(scene.camera().film().develop(), variance)
                                                        : -2.0;
    }
    return sharing ? sharing->fromRoot(e) : e;
}

} // namespace

RenderStats renderProgressive(const Scene& scene, const RenderControl& base, const ProgressiveOptions& opt,
                              const PassCallback& afterPass, PassReport* last) {
    if (opt.timeBudget <= 0.0 && opt.spp == 0 && opt.targetRelMSE <= 0.0)
        fail("progressive rendering needs a sample count, a time budget or a noise target");
    IRenderer& renderer = scene.renderer();
    PassSharing* sharing = opt.sharing;
    const std::uint64_t processes = sharing ? std::max<std::uint64_t>(1, sharing->processes()) : 1;

    // The bar counts seconds against a budget, else samples per pixel, of this run.
    const PassReport& resumed = opt.resumed;
    bool byTime = opt.timeBudget > 0.0;
    std::uint64_t total = byTime ? std::uint64_t(std::max(0.0, opt.timeBudget - resumed.seconds) * 1000.0)
                                 : std::max<std::uint64_t>(opt.spp - std::min(opt.spp, resumed.spp), 1);
    ProgressBar bar(byTime ? "Rendering (time)" : "Rendering", total, opt.progress && (byTime || opt.spp > 0));

    RenderStats local;  // this process's, this run
    PassReport report = resumed;
    report.estimatedRelMSE = -1.0;
    std::uint64_t next = report.spp > 0 ? report.spp : processes;  // samples per pixel of the next pass (job)
    std::uint64_t runSpp = 0;                                     // of the job, this run
    double localSeconds = 0.0, runSeconds = 0.0;
    bool filmHasSums = opt.filmResumed;
    std::uint64_t shown = 0;  // progress reported to the bar
    for (;;) {
        if (opt.spp) {
            if (report.spp >= opt.spp) break;
            next = std::min(next, opt.spp - report.spp);
        }
        if (report.spp > 0) {
            // The rate seen so far (this run's once it has one): shrink the pass to what the
            // remaining time allows, and to the longest pass wanted.
            double perSpp = runSpp > 0 ? runSeconds / double(runSpp) : report.seconds / double(report.spp);
            if (byTime) {
                double left = opt.timeBudget - report.seconds;
                if (left < 0.5 * perSpp) break;
                next = std::max<std::uint64_t>(1, std::min(next, std::uint64_t(left / perSpp)));
            }
            if (opt.maxPassSeconds > 0.0 && perSpp > 0.0)
                next = std::max<std::uint64_t>(1, std::min(next, std::uint64_t(opt.maxPassSeconds / perSpp)));
        }
        const std::uint64_t mine = sharing ? sharing->share(next) : next;
        auto start = std::chrono::steady_clock::now();
        if (mine > 0) {
            RenderControl pass = base;
            pass.progress = false;
            pass.sampleOffset = report.processSpp;
            pass.sampleCount = mine;
            pass.accumulate = filmHasSums;
            add(local, renderer.render(scene, pass));
            filmHasSums = true;
            report.processSpp += mine;
        } else {
            local.interrupted = local.interrupted || base.stopRequested();
        }
        localSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

        RenderStats job = local;
        runSeconds = localSeconds;
        if (sharing) sharing->combine(job, runSeconds);
        report.spp += next;
        runSpp += next;
        report.seconds = resumed.seconds + runSeconds;
        report.stats = resumed.stats;
        add(report.stats, job);
        report.stats.interrupted = job.interrupted;
        report.stats.seconds = report.seconds;
        report.estimatedRelMSE = -1.0;
        if (opt.targetRelMSE > 0.0 || (afterPass && !sharing)) {
            report.estimatedRelMSE = jobEstimate(scene, sharing);
            if (report.estimatedRelMSE == -2.0 && opt.targetRelMSE > 0.0)
                fail("renderer {} keeps no estimate of its error, which a noise target needs", renderer.typeName());
            report.estimatedRelMSE = std::max(report.estimatedRelMSE, -1.0);
        }

        std::uint64_t done = std::min(total, byTime ? std::uint64_t(runSeconds * 1000.0) : runSpp);
        bar.update(done - std::min(done, shown));
        shown = std::max(shown, done);
        if (job.interrupted) break;
        if (afterPass && !afterPass(report)) break;
        if (opt.spp && report.spp >= opt.spp) break;
        if (byTime && report.seconds >= opt.timeBudget) break;
        if (opt.targetRelMSE > 0.0 && report.estimatedRelMSE >= 0.0 && report.estimatedRelMSE <= opt.targetRelMSE)
            break;
        next = report.spp;  // double the total
    }
    bar.finish();
    if (last) *last = report;
    RenderStats totals = report.stats;
    totals.seconds = report.seconds;
    return totals;
}

} // namespace effigi
