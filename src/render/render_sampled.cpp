// renderSampled: every pixel of a sampled renderer (path, direct, aov, moment) estimated
// by the nested numerical integrator, in one pass over the tiles or, for an integrator that
// spreads samples over the pixels (IPixelAllocator), in two: a pilot of the same count in
// every pixel, then the counts the integrator gives each pixel from all the pilots.
#include "effigi/render/tile_renderer.hpp"

#include "effigi/interfaces/ifilter.hpp"
#include "effigi/interfaces/ifunction.hpp"
#include "effigi/interfaces/iintegrator_hooks.hpp"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <cmath>

namespace effigi {

namespace {

/// The samples of one pixel whose integrator weighs them (IWeightedSampler: VEGAS,
/// adaptive stratification, early stopping). They are splatted into a side block with
/// one more channel, the weight q (values · q and q), which is added to the tile's block
/// when the pixel is done, scaled by budget / Σ q and with the q channel as the filter
/// weight: each film pixel is then Σ q w f / Σ q w over the samples reaching it, and every
/// pixel weighs into its neighbours as if it had drawn `budget` uniform samples however
/// many it drew. (Unweighted samples go straight into the tile's block, as before.)
class WeightedPixel {
public:
    explicit WeightedPixel(const FilterTable& table) : m_table(table) {}

    /// The side block for the tile `tile` (film channels + 1), made when first needed.
    ImageBlock& block(const ImageBlock& tile) {
        if (m_block.offset() != tile.offset() || m_block.size() != tile.size() ||
            m_block.channels() != tile.channels() + 1 || m_block.data().empty())
            m_block = ImageBlock(tile.offset(), tile.size(), tile.channels() + 1, &m_table);
        if (m_block.border() != tile.border()) fail("renderSampled: side block and tile disagree on the filter radius");
        return m_block;
    }
    void add(double q) { m_weight += q, m_used = true; }

    /// Add the pixel's splats (pixels px ± border) to `tile` scaled by budget / Σ q; clear.
    void finish(const Point2i& px, ImageBlock& tile, double budget) {
        if (!m_used) return;
        const double scale = m_weight > 0.0 && std::isfinite(m_weight) ? budget / m_weight : 0.0;
        const int b = m_block.border(), n = tile.channels();
        const Vector2i s = m_block.storageSize();
        const Point2i lo = px - Vector2i(b), hi = px + Vector2i(b);  // block frame: offset − b at storage 0
        const Point2i o = m_block.offset() - Vector2i(b);
        for (int y = std::max(lo.y, o.y); y <= std::min(hi.y, o.y + s.y - 1); ++y)
            for (int x = std::max(lo.x, o.x); x <= std::min(hi.x, o.x + s.x - 1); ++x) {
                const std::size_t cell = std::size_t(y - o.y) * std::size_t(s.x) + std::size_t(x - o.x);
                float* src = m_block.data().data() + cell * std::size_t(n + 2);
                float* dst = tile.data().data() + cell * std::size_t(n + 1);
                for (int c = 0; c <= n; ++c) dst[c] += float(scale * src[c]);  // src[n], q, is dst's weight
                std::fill(src, src + n + 2, 0.f);
            }
        m_weight = 0.0, m_used = false;
    }

private:
    const FilterTable& m_table;
    ImageBlock m_block;
    double m_weight = 0.0;
    bool m_used = false;
};

/// One pixel's integrand in primary sample space (see renderSampled). The splatter
/// belongs to the calling thread and is reused from pixel to pixel: nothing is allocated
/// per sample or per pixel.
class SampledIntegrand final : public Implements<IFunction> {
public:
    SampledIntegrand(const Scene& scene, const ISampleRenderer& renderer, SampleSplatter& splatter, Point2i pixel,
                     ImageBlock& block, WeightedPixel& weighted, TileStats& stats, bool weighAll = false)
        : m_scene(scene), m_renderer(renderer), m_splatter(splatter), m_pixel(pixel), m_block(block),
          m_weighted(weighted), m_stats(stats), m_weighAll(weighAll) {}

    int dimension() const override { return 0; }
    int channels() const override { return 3; }
    void eval(ISampler& sampler, std::span<double> out) override {
        FilmSample cs = sampleCamera(m_scene.camera(), sampler, m_pixel);
        SampledSpectrum L = cs.weight * m_renderer.sampleRadiance(m_scene, cs.ray, cs.lambda, sampler, m_splatter.extra());
        Vector3f rgb;
        const IWeightedSampler* w = query<IWeightedSampler>(&sampler);
        if (w || m_weighAll) {
            double q = w ? w->sampleWeight() : 1.0;
            if (!(q >= 0.0) || !std::isfinite(q)) q = 0.0;
            rgb = m_splatter.put(m_weighted.block(m_block), cs.pFilm, L, cs.lambda, m_stats, float(q));
            m_weighted.add(q);
        } else {
            rgb = m_splatter.put(m_block, cs.pFilm, L, cs.lambda, m_stats);
        }
        out[0] = rgb.x, out[1] = rgb.y, out[2] = rgb.z;
    }

private:
    const Scene& m_scene;
    const ISampleRenderer& m_renderer;
    SampleSplatter& m_splatter;
    Point2i m_pixel;
    ImageBlock& m_block;
    WeightedPixel& m_weighted;
    TileStats& m_stats;
    bool m_weighAll;  // a part of an allocated pass: its pixels are scaled to their shares
};

} // namespace

RenderStats renderSampled(const Scene& scene, const RenderControl& control, const IIntegrator& integrator,
                          const ISampleRenderer& renderer, PixelVariance& variance) {
    const IFilm& film = scene.camera().film();
    const std::vector<std::string> extra = renderer.sampleChannels();
    const SampledChannels channels = sampledChannels(film, extra);
    variance.prepare(film, control.accumulate);
    tbb::enumerable_thread_specific<SampleSplatter> splatters(
        [&] { return SampleSplatter(channels.bins, extra.size()); });
    const FilterTable table(film.filter());  // the film's, for the side blocks of weighted samples
    tbb::enumerable_thread_specific<WeightedPixel> weighted([&] { return WeightedPixel(table); });
    // `count` samples of pixel px from index `first`; weighed ones scaled to `weight` in all.
    auto pixel = [&](const Point2i& px, std::uint64_t first, std::uint64_t count, ISampler& sampler,
                     ImageBlock& block, TileStats& stats, bool weighAll, double weight) {
        WeightedPixel& w = weighted.local();
        SampledIntegrand f(scene, renderer, splatters.local(), px, block, w, stats, weighAll);
        sampler.startPixel(px);
        const Estimate e = integrator.integrate(f, sampler, first, count);
        w.finish(px, block, weight);
        return e;
    };

    const std::uint64_t budget =
        control.sampleCount ? control.sampleCount : std::uint64_t(scene.camera().sampler().samplesPerPixel());
    auto* allocator = query<IPixelAllocator>(const_cast<IIntegrator*>(&integrator));  // query() changes nothing
    const IPixelAllocator::Plan plan = allocator ? allocator->plan(budget) : IPixelAllocator::Plan{};
    if (plan.pilot == 0 || plan.pilot >= budget || !(plan.pilotShare > 0.0 && plan.pilotShare < 1.0))
        return renderTiles(scene, control, channels.names, "Rendering",
                           [&](const Point2i& px, SampleRange range, ISampler& sampler, ImageBlock& block,
                               TileStats& stats) {
                               variance.merge(px, pixel(px, range.first, range.count, sampler, block, stats, false,
                                                        double(range.count)));
                           });

    // The pilot: plan.pilot samples in every pixel, weighing pilotShare of the budget.
    const Vector2i size = film.size();
    std::vector<PixelPilot> pilots(std::size_t(size.x) * std::size_t(size.y));
    auto at = [&](const Point2i& px) { return std::size_t(px.y) * std::size_t(size.x) + std::size_t(px.x); };
    RenderControl part = control;
    part.sampleCount = plan.pilot;
    RenderStats stats = renderTiles(
        scene, part, channels.names, "Rendering (pilot)",
        [&](const Point2i& px, SampleRange range, ISampler& sampler, ImageBlock& block, TileStats& ts) {
            const Estimate e =
                pixel(px, range.first, range.count, sampler, block, ts, true, plan.pilotShare * double(budget));
            PixelPilot& p = pilots[at(px)];
            for (int c = 0; c < 3; ++c) p.mean[c] = float(e.mean[c]), p.variance[c] = float(e.variance[c]);
            p.samples = std::uint32_t(std::min<std::uint64_t>(e.samples, 0xffffffffu));
        });
    if (stats.interrupted) return stats;

    // The rest: each pixel's allocated count from the following indices, weighing the rest
    // of the budget; the variance store gets the pixel as the film has it, both parts at
    // their fixed shares.
    std::vector<std::uint64_t> counts;
    allocator->allocate(pilots, size.x, size.y, budget, counts);
    if (counts.size() != pilots.size())
        fail("integrator '{}': allocated {} pixels of {}", integrator.typeName(), counts.size(), pilots.size());
    part.accumulate = true;
    part.sampleOffset = control.sampleOffset + plan.pilot;
    part.sampleCount = budget - plan.pilot;
    const double a = plan.pilotShare, b = 1.0 - a;
    const RenderStats rest = renderTiles(
        scene, part, channels.names, "Rendering",
        [&](const Point2i& px, SampleRange range, ISampler& sampler, ImageBlock& block, TileStats& ts) {
            const PixelPilot& p = pilots[at(px)];
            const std::uint64_t n = std::clamp<std::uint64_t>(counts[at(px)], 1, range.count);
            Estimate e = pixel(px, range.first, n, sampler, block, ts, true, b * double(budget));
            for (int c = 0; c < 3; ++c) {
                e.mean[c] = a * p.mean[c] + b * e.mean[c];
                e.variance[c] = a * a * p.variance[c] + b * b * e.variance[c];
            }
            e.samples += p.samples;
            variance.merge(px, e);
        });
    stats.samples += rest.samples, stats.rejectedSamples += rest.rejectedSamples;
    stats.work.merge(rest.work);
    stats.seconds += rest.seconds;
    stats.interrupted = rest.interrupted;
    return stats;
}

} // namespace effigi
