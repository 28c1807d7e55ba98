#include "effigi/render/tile_renderer.hpp"

#include "effigi/core/input.hpp"
#include "effigi/core/progress.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/render/image_metrics.hpp"
#include "effigi/render/spectral_bins.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/colorspace.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cstdio>
#include <limits>
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
    const Point2f lens = sampler.get2D();
    const float time = camera.hasShutterInterval() ? sampler.get1D() : 0.f;  // a dimension only when it matters
    cs.ray = camera.generateRay({cs.pFilm + offset, lens, time}, cs.lambda, cs.weight);
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

AccumulatorSums PixelVariance::saveSums() const {
    AccumulatorSums s;
    if (m_pixels.empty()) return s;
    s.layout = fmt::format("pixel variance {}x{}", m_width, m_pixels.size() / std::size_t(m_width));
    s.doubles.resize(7 * m_pixels.size());
    for (std::size_t i = 0; i < m_pixels.size(); ++i) {
        const Pixel& p = m_pixels[i];
        double* d = s.doubles.data() + 7 * i;
        const double n = double(p.samples);
        d[0] = n;
        for (int c = 0; c < 3; ++c) {
            // As Estimate::merge: a pixel of one sample (infinite variance) has no spread yet.
            const double m2 = std::isfinite(p.variance[c]) ? double(p.variance[c]) * n * (n - 1.0) : 0.0;
            d[1 + c] = n * double(p.mean[c]);
            d[4 + c] = m2 + n * double(p.mean[c]) * double(p.mean[c]);
        }
    }
    return s;
}

void PixelVariance::loadSums(const AccumulatorSums& s) {
    int w = 0, h = 0;
    if (std::sscanf(s.layout.c_str(), "pixel variance %dx%d", &w, &h) != 2 || w <= 0 || h <= 0 ||
        s.layout != fmt::format("pixel variance {}x{}", w, h) || s.doubles.size() != 7 * std::size_t(w) * h ||
        !s.floats.empty())
        fail("renderer: saved error statistics of an unknown layout ('{}', {} values)", excerpt(s.layout),
             s.doubles.size());
    const std::size_t pixels = std::size_t(w) * std::size_t(h);
    m_pixels.assign(pixels, Pixel{});
    m_width = w;
    for (std::size_t i = 0; i < pixels; ++i) {
        const double* d = s.doubles.data() + 7 * i;
        Pixel& p = m_pixels[i];
        const double n = d[0];
        p.samples = std::uint32_t(std::clamp(n, 0.0, double(0xffffffffu)));
        for (int c = 0; c < 3 && n > 0.0; ++c) {
            const double mean = d[1 + c] / n, m2 = std::max(0.0, d[4 + c] - n * mean * mean);
            p.mean[c] = float(mean);
            p.variance[c] = n > 1.0 ? float(m2 / (n - 1.0) / n) : std::numeric_limits<float>::infinity();
        }
    }
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
