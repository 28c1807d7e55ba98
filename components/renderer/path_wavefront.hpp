#pragma once
// The wavefront mode of `path`: the paths of a whole tile advance together, segment by
// segment, and every kind of ray is traced in one batch through IIntersect's batch methods
// (Embree: 16-wide packets), instead of one ray at a time between shading steps.
//
// A tile of up to 32×32 pixels renders one sample index of every pixel per wave. A wave
// is: camera samples for all its paths; then, while any path is alive, the closest hits
// of all live paths' rays in one batch, the shading step of each path
// (PathIntegrator::scatter: emission, light sample, BSDF sample; hits grouped by shape),
// and all shadow rays of that step in one batch; finally every sample is splatted. Each path keeps its own
// sampler (one per pixel of the tile, started at that pixel) and draws the same dimensions
// in the same order as the one-path loop, so the estimator is the same: with the same
// seed both modes draw the same random numbers for each sample.
//
// Reference: Laine, Karras, Aila 2013, "Megakernels Considered Harmful: Wavefront Path
// Tracing on GPUs", HPG; Wald et al. 2014 (Embree packets).
#include "path_core.hpp"

#include "effigi/math/running_estimate.hpp"
#include "effigi/render/tile_renderer.hpp"

#include <tbb/enumerable_thread_specific.h>

#include <chrono>
#include <vector>

namespace effigi {

class PathWavefront {
public:
    PathWavefront(const Scene& scene, const PathIntegrator& integrator, const SpectralBinning& bins,
                  std::uint64_t seed)
        : m_scene(scene), m_integrator(integrator), m_splatter(bins, 0), m_seed(seed) {}

    /// All samples `range` of the tile's pixels; per-pixel mean and variance to `variance`.
    void renderTile(const Point2i& offset, const Vector2i& extent, SampleRange range, ImageBlock& block,
                    TileStats& stats, const RenderControl& control, PixelVariance& variance) {
        const std::size_t n = std::size_t(extent.x) * std::size_t(extent.y);
        prepare(n);
        // Paths in 4 x 4 pixel blocks, so that each packet of 16 camera rays is a compact
        // bundle (and so are, roughly, their first bounces).
        std::size_t i = 0;
        for (int by = 0; by < extent.y; by += 4)
            for (int bx = 0; bx < extent.x; bx += 4)
                for (int y = by; y < std::min(by + 4, extent.y); ++y)
                    for (int x = bx; x < std::min(bx + 4, extent.x); ++x, ++i) {
                        m_pixel[i] = Point2i(offset.x + x, offset.y + y);
                        m_samplers[i]->startPixel(m_pixel[i]);
                        m_pixelStats[i] = RunningEstimate(3);
                    }
        for (std::uint64_t k = range.first; k < range.first + range.count && !control.stopRequested(); ++k)
            wave(n, k, block, stats);
        for (std::size_t i = 0; i < n; ++i) variance.merge(m_pixel[i], m_pixelStats[i].estimate());
    }

private:
    using Clock = std::chrono::steady_clock;
    static double since(Clock::time_point& t) {
        Clock::time_point now = Clock::now();
        double s = std::chrono::duration<double>(now - t).count();
        t = now;
        return s;
    }

    void prepare(std::size_t n) {
        const ISampler& proto = m_scene.camera().sampler();
        while (m_samplers.size() < n) m_samplers.push_back(proto.clone(m_seed));
        m_pixel.resize(n), m_pixelStats.resize(n), m_paths.resize(n), m_lambda.resize(n);
        m_pFilm.resize(n), m_weight.resize(n);
        m_active.reserve(n), m_next.reserve(n), m_rays.reserve(n), m_hits.resize(n);
        m_shadowRays.reserve(n), m_shadowL.reserve(n), m_shadowOwner.reserve(n), m_blocked.resize(n);
    }

    /// Sample index k of the tile's n pixels, start to finish.
    void wave(std::size_t n, std::uint64_t k, ImageBlock& block, TileStats& stats) {
        WorkStats& w = stats.work;
        w.kept = true;
        Clock::time_point t = Clock::now();
        m_active.clear();
        for (std::size_t i = 0; i < n; ++i) {
            ISampler& sampler = *m_samplers[i];
            sampler.startSample(k);
            FilmSample cs = sampleCamera(m_scene.camera(), sampler, m_pixel[i]);
            m_paths[i] = PathState(cs.ray);
            m_lambda[i] = cs.lambda, m_pFilm[i] = cs.pFilm, m_weight[i] = cs.weight;
            m_active.push_back(std::uint32_t(i));
        }
        w.cameraSeconds += since(t);

        for (int kind = WorkStats::Camera; !m_active.empty(); kind = WorkStats::Extension) {
            m_rays.clear();
            for (std::uint32_t i : m_active) m_rays.push_back(m_paths[i].ray);
            m_scene.intersect(m_rays, std::span<Hit>(m_hits.data(), m_rays.size()));
            w.rays[kind] += m_rays.size();
            w.traceSeconds[kind] += since(t);

            shade(std::span<const std::uint32_t>(m_active));
            w.shadeSeconds += since(t);

            traceShadows(w);
            w.traceSeconds[WorkStats::Shadow] += since(t);
            std::swap(m_active, m_next);
        }

        for (std::size_t i = 0; i < n; ++i) {
            // The pixel's estimate, as the mean integrator keeps it: the samples' linear sRGB.
            const Vector3f rgb = m_splatter.put(block, m_pFilm[i], m_weight[i] * m_paths[i].L, m_lambda[i], stats);
            const double v[3] = {rgb.x, rgb.y, rgb.z};
            m_pixelStats[i].add(v);
        }
        w.filmSeconds += since(t);
    }

    /// One shading step of every live path whose ray was just traced (m_hits).
    void shade(std::span<const std::uint32_t> active) {
        m_next.clear();
        m_shadowRays.clear(), m_shadowL.clear(), m_shadowOwner.clear();
        std::optional<ShadowRay> shadow;
        orderByShape(active.size());
        for (std::uint32_t j : m_order) {
            const std::uint32_t i = active[j];
            PathState& s = m_paths[i];
            if (!m_hits[j].valid()) {
                m_integrator.miss(s, m_lambda[i]);
                continue;
            }
            const SurfaceInteraction si = m_scene.interaction(s.ray, m_hits[j]);
            if (m_integrator.scatter(s, si, m_lambda[i], *m_samplers[i], shadow)) m_next.push_back(i);
            if (shadow) {
                m_shadowRays.push_back(shadow->ray);
                m_shadowL.push_back(shadow->contribution);
                m_shadowOwner.push_back(i);
            }
        }
    }

    /// The order in which the step's hits are shaded: grouped by shape (so by BSDF and
    /// emitter; misses last), a counting sort. Code and data of one material stay hot:
    /// measured +2 % samples/s on the Cornell box, +3 % on the glossy one (bench/RESULTS.md).
    void orderByShape(std::size_t n) {
        m_order.resize(n);
        const std::size_t shapes = m_scene.shapes().size();
        m_bucket.assign(shapes + 2, 0);
        auto key = [&](std::size_t j) { return m_hits[j].valid() ? std::size_t(m_hits[j].shape) : shapes; };
        for (std::size_t j = 0; j < n; ++j) ++m_bucket[key(j) + 1];
        for (std::size_t b = 1; b < m_bucket.size(); ++b) m_bucket[b] += m_bucket[b - 1];
        for (std::size_t j = 0; j < n; ++j) m_order[m_bucket[key(j)]++] = std::uint32_t(j);
    }

    /// The step's shadow rays in one batch; unblocked ones add their contribution.
    void traceShadows(WorkStats& w) {
        const std::size_t m = m_shadowRays.size();
        w.rays[WorkStats::Shadow] += m;
        if (m_integrator.shadowsNeedTransmittance()) {  // through null surfaces, one at a time
            for (std::size_t j = 0; j < m; ++j) {
                const std::uint32_t i = m_shadowOwner[j];
                m_paths[i].L += m_shadowL[j] * m_integrator.shadowTransmittance(m_shadowRays[j], m_lambda[i]);
            }
            return;
        }
        m_scene.occluded(m_shadowRays, std::span<std::uint8_t>(m_blocked.data(), m));
        for (std::size_t j = 0; j < m; ++j)
            if (!m_blocked[j]) m_paths[m_shadowOwner[j]].L += m_shadowL[j];
    }

    const Scene& m_scene;
    const PathIntegrator& m_integrator;
    SampleSplatter m_splatter;
    std::uint64_t m_seed;
    // Per path of the wave (= per pixel of the tile), structure of arrays.
    std::vector<Ref<ISampler>> m_samplers;
    std::vector<Point2i> m_pixel;
    std::vector<RunningEstimate> m_pixelStats;
    std::vector<PathState> m_paths;
    std::vector<SampledWavelengths> m_lambda;
    std::vector<Point2f> m_pFilm;
    std::vector<SampledSpectrum> m_weight;
    // Queues: live paths, their rays and hits; the step's shadow rays.
    std::vector<std::uint32_t> m_active, m_next;
    std::vector<Ray> m_rays;
    std::vector<Hit> m_hits;
    std::vector<Ray> m_shadowRays;
    std::vector<SampledSpectrum> m_shadowL;
    std::vector<std::uint32_t> m_shadowOwner;
    std::vector<std::uint8_t> m_blocked;
    std::vector<std::uint32_t> m_order, m_bucket;
};

/// Renders the scene's film with the wavefront mode (the `mean` integrator's estimate per
/// pixel, into `variance`).
inline RenderStats renderPathWavefront(const Scene& scene, const RenderControl& control,
                                       const PathIntegrator& integrator, PixelVariance& variance) {
    const SampledChannels channels = sampledChannels(scene.camera().film());
    variance.prepare(scene.camera().film(), control.accumulate);
    tbb::enumerable_thread_specific<PathWavefront> engines(
        [&] { return PathWavefront(scene, integrator, channels.bins, control.seed); });
    return renderTileBlocks(scene, control, channels.names, "Rendering",
                            [&](const Point2i& offset, const Vector2i& extent, SampleRange range, ISampler&,
                                ImageBlock& block, TileStats& stats) {
                                engines.local().renderTile(offset, extent, range, block, stats, control, variance);
                            });
}

} // namespace effigi
