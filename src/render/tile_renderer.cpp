#include "effigi/render/tile_renderer.hpp"

#include "effigi/core/progress.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <memory>

namespace effigi {

namespace {
constexpr int TileSize = 32;
}

RenderStats renderTiles(const Scene& scene, const RenderControl& control, const std::vector<std::string>& channels,
                        const std::string& label, const PixelFunction& pixel) {
    ICamera& camera = scene.camera();
    IFilm& film = camera.film();
    ISampler& sampler = camera.sampler();
    if (!control.accumulate) film.prepare(channels);

    Vector2i size = film.size();
    int tilesX = (size.x + TileSize - 1) / TileSize, tilesY = (size.y + TileSize - 1) / TileSize;
    SampleRange range{control.sampleOffset,
                      control.sampleCount ? control.sampleCount : std::uint64_t(sampler.samplesPerPixel())};
    std::uint64_t spp = range.count;

    std::unique_ptr<tbb::global_control> limit;
    if (control.threads > 0)
        limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      std::size_t(control.threads));

    struct ThreadState {
        Ref<ISampler> sampler;
        TileStats stats;
    };
    tbb::enumerable_thread_specific<ThreadState> threads(
        [&] { return ThreadState{sampler.clone(control.seed), {}}; });

    ProgressBar progress(label, std::uint64_t(size.x) * size.y * spp, control.progress);
    auto start = std::chrono::steady_clock::now();
    std::atomic<bool> interrupted{false};

    tbb::parallel_for(0, tilesX * tilesY, [&](int tile) {
        if (control.stopRequested()) {
            interrupted = true;
            return;
        }
        ThreadState& ts = threads.local();
        Point2i offset((tile % tilesX) * TileSize, (tile / tilesX) * TileSize);
        Vector2i extent(std::min(TileSize, size.x - offset.x), std::min(TileSize, size.y - offset.y));
        ImageBlock block = film.createBlock(offset, extent);
        // The stop request is checked per pixel so that SIGINT answers within one
        // pixel's samples; a tile cut short is still merged.
        std::uint64_t done = 0;
        for (int y = offset.y; y < offset.y + extent.y && !control.stopRequested(); ++y)
            for (int x = offset.x; x < offset.x + extent.x && !control.stopRequested(); ++x, ++done)
                pixel({x, y}, range, *ts.sampler, block, ts.stats);
        film.put(block);
        progress.update(done * spp);
    });
    progress.finish();

    RenderStats stats;
    for (const auto& ts : threads) {
        stats.samples += ts.stats.samples;
        stats.rejectedSamples += ts.stats.rejected;
    }
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats.interrupted = interrupted || control.stopRequested();
    return stats;
}

} // namespace effigi
