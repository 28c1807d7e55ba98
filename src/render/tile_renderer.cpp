#include "effigi/render/tile_renderer.hpp"

#include "effigi/core/progress.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifunction.hpp"
#include "effigi/interfaces/iintegrator_hooks.hpp"
#include "effigi/interfaces/ifilter.hpp"
#include "effigi/render/image_metrics.hpp"
#include "effigi/render/spectral_bins.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/colorspace.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <memory>

namespace effigi {

namespace {
constexpr int TileSize = 32;
}

RenderStats renderTileBlocks(const Scene& scene, const RenderControl& control, const std::vector<std::string>& channels,
                             const std::string& label, const TileFunction& tileFn) {
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
        tileFn(offset, extent, range, *ts.sampler, block, ts.stats);
        film.put(block);  // a tile cut short by a stop request is still merged
        progress.update(std::uint64_t(extent.x) * extent.y * spp);
    });
    progress.finish();

    RenderStats stats;
    for (const auto& ts : threads) {
        stats.samples += ts.stats.samples;
        stats.rejectedSamples += ts.stats.rejected;
        stats.work.merge(ts.stats.work);
    }
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats.interrupted = interrupted || control.stopRequested();
    return stats;
}

RenderStats renderTiles(const Scene& scene, const RenderControl& control, const std::vector<std::string>& channels,
                        const std::string& label, const PixelFunction& pixel) {
    return renderTileBlocks(scene, control, channels, label,
                            [&](const Point2i& offset, const Vector2i& extent, SampleRange range, ISampler& sampler,
                                ImageBlock& block, TileStats& stats) {
                                // Checked per pixel so that SIGINT answers within one pixel's samples.
                                for (int y = offset.y; y < offset.y + extent.y && !control.stopRequested(); ++y)
                                    for (int x = offset.x; x < offset.x + extent.x && !control.stopRequested(); ++x)
                                        pixel({x, y}, range, sampler, block, stats);
                            });
}

FilmSample sampleCamera(const ICamera& camera, ISampler& sampler, const Point2i& pixel) {
    FilmSample cs;
    cs.lambda = SampledWavelengths::sampleVisible(sampler.get1D());
    cs.pFilm = Point2f(pixel) + sampler.getPixel2D();
    const Point2f offset(camera.film().cropOffset());
    cs.ray = camera.generateRay({cs.pFilm + offset, sampler.get2D(), 0.f}, cs.lambda, cs.weight);
    return cs;
}

SampledChannels sampledChannels(const IFilm& film, const std::vector<std::string>& extra) {
    const auto [lambdaMin, lambdaMax] = film.spectralRange();
    SampledChannels c{SpectralBinning(film.spectralBins(), lambdaMin, lambdaMax), {"X", "Y", "Z"}};
    for (std::string& name : c.bins.channelNames()) c.names.push_back(std::move(name));
    c.names.insert(c.names.end(), extra.begin(), extra.end());
    return c;
}

SampleSplatter::SampleSplatter(const SpectralBinning& bins, std::size_t extraChannels)
    : m_bins(bins), m_binCount(std::size_t(bins.count())), m_values(3 + m_binCount + extraChannels + 1, 0.f) {}

Vector3f SampleSplatter::put(ImageBlock& block, const Point2f& pFilm, const SampledSpectrum& L,
                             const SampledWavelengths& lambda, TileStats& stats) {
    return splat(block, pFilm, L, lambda, stats, nullptr);
}

Vector3f SampleSplatter::put(ImageBlock& block, const Point2f& pFilm, const SampledSpectrum& L,
                             const SampledWavelengths& lambda, TileStats& stats, float q) {
    return splat(block, pFilm, L, lambda, stats, &q);
}

Vector3f SampleSplatter::splat(ImageBlock& block, const Point2f& pFilm, const SampledSpectrum& L,
                               const SampledWavelengths& lambda, TileStats& stats, const float* q) {
    float* v = m_values.data();
    const std::size_t n = m_values.size() - 1;  // the film's channels
    Vector3f xyz = cie::toXYZ(L, lambda);
    bool finite = isFinite(xyz) && m_bins.estimate(L, lambda, v + 3);
    for (float* c = extra(); finite && c != v + n; ++c) finite = std::isfinite(*c);
    if (!finite) {  // keep NaN/Inf off the film, every channel of the sample; counted
        ++stats.rejected;
        xyz = Vector3f(0.f);
        std::fill(m_values.begin(), m_values.end(), 0.f);
    }
    v[0] = xyz.x, v[1] = xyz.y, v[2] = xyz.z;
    ++stats.samples;
    if (q) {
        for (std::size_t c = 0; c < n; ++c) v[c] *= *q;
        v[n] = *q;
    }
    block.put(pFilm, v);
    std::fill(m_values.begin() + 3 + std::ptrdiff_t(m_binCount), m_values.end(), 0.f);
    return xyzToLinearSRGB(xyz);
}

void PixelVariance::prepare(const IFilm& film, bool accumulate) {
    Vector2i size = film.size();
    if (!accumulate || m_pixels.size() != std::size_t(size.x) * size.y)
        m_pixels.assign(std::size_t(size.x) * size.y, Pixel{});
    m_width = size.x;
    m_filterFactor = filterVarianceFactor(film.filter());
}

void PixelVariance::merge(const Point2i& px, const Estimate& e) {
    Pixel& p = m_pixels[std::size_t(px.y) * m_width + px.x];
    Estimate pooled;
    pooled.channels = 3;
    pooled.samples = p.samples;
    for (int c = 0; c < 3; ++c) pooled.mean[c] = p.mean[c], pooled.variance[c] = p.variance[c];
    pooled.merge(e);
    for (int c = 0; c < 3; ++c) p.mean[c] = float(pooled.mean[c]), p.variance[c] = float(pooled.variance[c]);
    p.samples = std::uint32_t(std::min<std::uint64_t>(pooled.samples, 0xffffffffu));
}

bool PixelVariance::get(std::vector<float>& variance) const {
    // The integrator's variance is that of the samples drawn for the pixel; the film
    // pixel is a filtered average over neighbouring pixels' samples too.
    variance.resize(3 * m_pixels.size());
    for (std::size_t i = 0; i < m_pixels.size(); ++i)
        for (int c = 0; c < 3; ++c) variance[3 * i + c] = float(m_pixels[i].variance[c] * m_filterFactor);
    return !m_pixels.empty();
}

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
    void finish(const Point2i& px, ImageBlock& tile, std::uint64_t budget) {
        if (!m_used) return;
        const double scale = m_weight > 0.0 && std::isfinite(m_weight) ? double(budget) / m_weight : 0.0;
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
                     ImageBlock& block, WeightedPixel& weighted, TileStats& stats)
        : m_scene(scene), m_renderer(renderer), m_splatter(splatter), m_pixel(pixel), m_block(block),
          m_weighted(weighted), m_stats(stats) {}

    int dimension() const override { return 0; }
    int channels() const override { return 3; }
    void eval(ISampler& sampler, std::span<double> out) override {
        FilmSample cs = sampleCamera(m_scene.camera(), sampler, m_pixel);
        SampledSpectrum L = cs.weight * m_renderer.sampleRadiance(m_scene, cs.ray, cs.lambda, sampler, m_splatter.extra());
        Vector3f rgb;
        if (const IWeightedSampler* w = query<IWeightedSampler>(&sampler)) {
            double q = w->sampleWeight();
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
    return renderTiles(scene, control, channels.names, "Rendering",
                       [&](const Point2i& px, SampleRange range, ISampler& sampler, ImageBlock& block,
                           TileStats& stats) {
                           WeightedPixel& w = weighted.local();
                           SampledIntegrand f(scene, renderer, splatters.local(), px, block, w, stats);
                           sampler.startPixel(px);
                           variance.merge(px, integrator.integrate(f, sampler, range.first, range.count));
                           w.finish(px, block, range.count);
                       });
}

std::vector<NestedRenderer> nestedRenderers(const Properties& p) {
    std::vector<NestedRenderer> out;
    int unnamed = 0;
    for (const Properties::Entry& e : p.entries()) {
        const auto* c = std::get_if<ComponentValue>(&e.value);
        if (!c || c->tag != "renderer") continue;
        std::string name = e.name.empty() ? fmt::format("_arg_{}", unnamed++) : e.name;
        Ref<ISampleRenderer> r = query<ISampleRenderer>(c->object);
        if (!r)
            failAt(e.where,
                   "{}: nested {} ('{}') cannot be nested: it renders whole images, not single samples "
                   "(nestable renderers: path, direct, aov, moment)",
                   p.describe(), c->object->typeName(), name);
        out.push_back({std::move(name), std::move(r)});
    }
    return out;
}

Ref<IIntegrator> defaultIntegrator() {
    Properties p("integrator", "mean");
    Ref<IIntegrator> r = query<IIntegrator>(Registry::instance().create("integrator", "mean", p));
    if (!r) fail("the default integrator 'mean' is not an integrator");
    return r;
}

} // namespace effigi
