#include "effigi/render/progressive.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/progress.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/render/image_metrics.hpp"

#include <chrono>
#include <cmath>

namespace effigi {

RenderStats renderProgressive(const Scene& scene, const RenderControl& base, const ProgressiveOptions& opt,
                              const PassCallback& afterPass) {
    if (opt.timeBudget <= 0.0 && opt.spp == 0 && opt.targetRelMSE <= 0.0)
        fail("progressive rendering needs a sample count, a time budget or a noise target");
    IRenderer& renderer = scene.renderer();
    IFilm& film = scene.camera().film();

    // The bar counts seconds against a budget, else samples per pixel.
    bool byTime = opt.timeBudget > 0.0;
    std::uint64_t total = byTime ? std::uint64_t(opt.timeBudget * 1000.0) : std::max<std::uint64_t>(opt.spp, 1);
    ProgressBar bar(byTime ? "Rendering (time)" : "Rendering", total, opt.progress && (byTime || opt.spp > 0));

    RenderStats totals;
    PassReport report;
    std::uint64_t next = 1;  // samples per pixel of the next pass
    double renderSeconds = 0.0;
    std::uint64_t shown = 0;  // progress reported to the bar
    for (;;) {
        if (opt.spp) next = std::min(next, opt.spp - report.spp);
        if (byTime && report.spp > 0) {
            // Shrink the pass to what the remaining time allows at the rate seen so far.
            double perSpp = renderSeconds / double(report.spp);
            double left = opt.timeBudget - renderSeconds;
            if (left < 0.5 * perSpp) break;
            next = std::max<std::uint64_t>(1, std::min(next, std::uint64_t(left / perSpp)));
        }
        RenderControl pass = base;
        pass.progress = false;
        pass.sampleOffset = report.spp;
        pass.sampleCount = next;
        pass.accumulate = report.spp > 0;
        auto start = std::chrono::steady_clock::now();
        RenderStats s = renderer.render(scene, pass);
        renderSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

        totals.samples += s.samples;
        totals.rejectedSamples += s.rejectedSamples;
        totals.work.merge(s.work);
        totals.seconds = renderSeconds;
        totals.interrupted = s.interrupted;
        report.spp += next;
        report.seconds = renderSeconds;
        report.stats = totals;
        report.estimatedRelMSE = -1.0;
        std::vector<float> variance;
        if ((opt.targetRelMSE > 0.0 || afterPass) && renderer.varianceEstimate(variance))
            report.estimatedRelMSE = estimatedRelMSE(film.develop(), variance);
        else if (opt.targetRelMSE > 0.0)
            fail("renderer {} keeps no estimate of its error, which a noise target needs", renderer.typeName());

        std::uint64_t done = std::min(total, byTime ? std::uint64_t(renderSeconds * 1000.0) : report.spp);
        bar.update(done - shown);
        shown = done;
        if (totals.interrupted) break;
        if (afterPass && !afterPass(report)) break;
        if (opt.spp && report.spp >= opt.spp) break;
        if (byTime && renderSeconds >= opt.timeBudget) break;
        if (opt.targetRelMSE > 0.0 && report.estimatedRelMSE >= 0.0 && report.estimatedRelMSE <= opt.targetRelMSE)
            break;
        next = report.spp;  // double the total
    }
    bar.finish();
    return totals;
}

} // namespace effigi
