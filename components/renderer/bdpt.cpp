// renderer "bdpt" — bidirectional path tracing (Veach 1997; Lafortune & Willems 1993).
//
// Every camera sample traces a camera subpath and a light subpath and joins them in all
// ways (s, t) that give a path of at most max_depth segments (bdpt_connect.hpp): the
// camera path hitting a light (s = 0), light sampling (s = 1), light tracing to the
// camera (t = 1, splatted anywhere on the film) and connections of inner vertices. The
// strategies are combined with the power heuristic, which makes light arriving through
// small openings, caustics seen in mirrors and other paths that are hard from one side
// cheap from the other. Infinite emitters (envmap, constant, directional) cannot start
// light subpaths here; they are reached by the camera subpath and by light sampling,
// combined as in `path`. Pass-through (null) surfaces count as delta vertices, and so as
// segments for max_depth (path does not count them).
//
// The image is the camera-side estimate plus the light-tracing splats, scaled like
// ptracer's: light subpaths are as many as camera samples, so with the camera's
// importance normalised over the full film a splat weighs (full-film pixels) /
// (rendered pixels · spp).
//
// Parameters (Mitsuba 0.6 `bdpt` semantics): max_depth (−1 unbounded; 0 black; 1 lights
// seen directly), rr_depth (Russian roulette from that many segments on), hide_emitters,
// strategies (pbrt's visualize_strategies): also write each strategy's MIS-weighted
// contribution, for paths of up to 5 segments, as linear sRGB film channels "s<s>t<t>.R/G/B"
// (environment light counts as s = 0 when found, s = 1 when sampled); they sum to the image;
// pathgenerator (nested IPathGenerator: how the subpaths walk, default `bsdf`).
// Needs a camera with a density of directions: perspective or thinlens.
// Reference: E. Veach, PhD thesis, 1997, ch. 10; E. Veach, L. Guibas, "Bidirectional
// Estimators for Light Transport", 1994; pbrt 3rd ed., §16.3.
#include "bdpt_sample.hpp"
#include "film_splat.hpp"

#include "effigi/core/progress.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/ifilter.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/render/tile_renderer.hpp"
#include "effigi/spectral/colorspace.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <memory>

namespace effigi {
namespace {

using namespace bdpt;

/// One thread's sampler, blocks (camera-side estimate, light-tracing splats), paths and
/// the film values of one sample (X, Y, Z, then the strategy channels).
struct ThreadState {
    Ref<ISampler> sampler;
    ImageBlock camera, splats;
    TileStats stats;
    bdpt::Subpaths paths;
    std::vector<float> values, splatValues;
};

/// The film channels of the strategies (s, t) of paths up to MaxSegments segments.
class StrategyChannels {
public:
    static constexpr int MaxSegments = 5;
    explicit StrategyChannels(bool on) {
        for (int k = 1; on && k <= MaxSegments; ++k)
            for (int s = 0; s <= k; ++s) {
                int t = k + 1 - s;
                if (s == 1 && t == 1) continue;  // not a strategy (light point joined to the lens)
                m_slot[s][t] = 3 + int(m_names.size());
                for (const char* c : {"R", "G", "B"}) m_names.push_back(fmt::format("s{}t{}.{}", s, t, c));
            }
    }
    const std::vector<std::string>& names() const { return m_names; }
    /// First channel of strategy (s, t), or −1 if it has none.
    int slot(int s, int t) const { return s <= MaxSegments + 1 && t <= MaxSegments + 1 ? m_slot[s][t] : -1; }
    /// Add the contribution L (at the final wavelengths) of (s, t) to values, as linear sRGB.
    void add(float* values, int s, int t, const SampledSpectrum& L, const SampledWavelengths& lambda) const {
        int c = values ? slot(s, t) : -1;
        if (c < 0 || L.isBlack()) return;
        Vector3f rgb = xyzToLinearSRGB(cie::toXYZ(L, lambda));
        for (int i = 0; i < 3; ++i) values[c + i] += rgb[i];
    }

private:
    std::vector<std::string> m_names;
    int m_slot[MaxSegments + 2][MaxSegments + 2] = {};
};

class Bidirectional {
public:
    Bidirectional(Context ctx, const FilterTable& filter, Point2i cropOffset, bool hideEmitters,
                  const StrategyChannels& strategies)
        : m_ctx(std::move(ctx)), m_splatter(filter, cropOffset), m_hideEmitters(hideEmitters),
          m_strategies(strategies) {}

    /// All strategies of one camera sample (bdpt_sample.hpp): the camera-side radiance is
    /// returned (and each strategy's share added to ts.values when strategy channels are
    /// on), the light-tracing strategies are splatted into ts's splat block.
    SampledSpectrum sample(FilmSample& fs, ThreadState& ts) const {
        float* values = m_strategies.names().empty() ? nullptr : ts.values.data();
        if (values) std::fill(ts.values.begin(), ts.values.end(), 0.f);
        SampledSpectrum L(0.f);
        bdpt::sample(
            m_ctx, m_hideEmitters, fs.ray, fs.weight, *ts.sampler, fs.lambda, ts.paths, [](int) {},
            [&](int s, int t, const SampledSpectrum& c) {
                L += c;
                m_strategies.add(values, s, t, c, fs.lambda);
            },
            [&](int s, const SampledSpectrum& c, const Point2f& pFilm) { splat(pFilm, c, s, fs.lambda, ts); });
        return L;
    }

private:
    /// A light-tracing contribution (t = 1), with its strategy channel when they are on.
    void splat(const Point2f& pFilm, const SampledSpectrum& L, int s, const SampledWavelengths& lambda,
               ThreadState& ts) const {
        if (m_strategies.names().empty()) return m_splatter.splat(pFilm, L, lambda, ts.splats, ts.stats);
        std::fill(ts.splatValues.begin(), ts.splatValues.end(), 0.f);
        Vector3f xyz = cie::toXYZ(L, lambda);
        std::copy(&xyz.x, &xyz.x + 3, ts.splatValues.begin());
        m_strategies.add(ts.splatValues.data(), s, 1, L, lambda);
        m_splatter.splat(pFilm, ts.splatValues.data(), ts.splats, ts.stats);
    }

    Context m_ctx;
    FilmSplatter m_splatter;
    bool m_hideEmitters;
    const StrategyChannels& m_strategies;
};

class BdptRenderer final : public Implements<IRenderer> {
public:
    static Schema schema() {
        Schema s("renderer", "bdpt", "Bidirectional path tracing: every join of a camera and a light subpath, "
                                     "weighted by the power heuristic.");
        s.cite("E. Veach, Robust Monte Carlo Methods for Light Transport Simulation, PhD thesis, 1997, ch. 10");
        s.integer("max_depth", -1, "Longest path in segments (-1: unbounded; 0: black; 1: emitters only)").atLeast(-1);
        s.integer("rr_depth", 5, "Segments after which Russian roulette may end subpaths").atLeast(1);
        s.boolean("hide_emitters", false, "Do not show emitters seen directly by the camera");
        s.boolean("strategies", false,
                  "Also write each strategy's weighted contribution (paths up to 5 segments) as channels s<s>t<t>.R/G/B");
        s.child("pathgenerator", "pathgenerator", "Walks of the camera and light subpaths (default: bsdf)");
        s.ignored("samples_per_pass", "effigi renders in passes of its own (see effigi render --spp)");
        s.ignored("timeout", "use effigi render --time for a time budget");
        s.ignored("lightImage", "the light-tracing strategies are always on");
        s.ignored("sampleDirect", "the direct-sampling strategies are always on");
        s.addConformance({"default", {}});
        for (std::int64_t d : {0, 1, 2, 3})
            s.addConformance({fmt::format("max_depth {}", d), {{"max_depth", d}}});
        s.addConformance({"rr_depth 1", {{"rr_depth", std::int64_t(1)}}});
        s.addConformance({"hide_emitters", {{"hide_emitters", true}}});
        s.addConformance({"strategy channels", {{"strategies", true}}});
        return s;
    }

    explicit BdptRenderer(const Properties& p)
        : m_maxDepth(int(p.getInt("max_depth"))), m_rrDepth(int(p.getInt("rr_depth"))),
          m_hideEmitters(p.getBool("hide_emitters")), m_strategies(p.getBool("strategies")),
          m_generator(pathGenerator(p)) {}

    RenderStats render(const Scene& scene, const RenderControl& control) override;
    /// Moving shapes: both subpaths of a sample share the camera ray's time.
    bool rendersMotion() const override { return true; }

private:
    int m_maxDepth, m_rrDepth;
    bool m_hideEmitters;
    StrategyChannels m_strategies;
    Ref<IPathGenerator> m_generator;
};

RenderStats BdptRenderer::render(const Scene& scene, const RenderControl& control) {
    ICamera& camera = scene.camera();
    IFilm& film = camera.film();
    Context ctx = makePathContext(scene, m_maxDepth, m_rrDepth, *m_generator, "renderer 'bdpt'");
    std::vector<std::string> channels = {"X", "Y", "Z"};
    channels.insert(channels.end(), m_strategies.names().begin(), m_strategies.names().end());
    if (!control.accumulate) film.prepare(channels);
    RenderStats stats;
    if (m_maxDepth == 0) return stats;

    std::unique_ptr<tbb::global_control> limit;
    if (control.threads > 0)
        limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      std::size_t(control.threads));
    FilterTable filter(film.filter());
    const Bidirectional tracer(std::move(ctx), filter, film.cropOffset(), m_hideEmitters, m_strategies);
    const SampleRange range{control.sampleOffset, control.sampleCount ? control.sampleCount
                                                                      : std::uint64_t(camera.sampler().samplesPerPixel())};
    const Vector2i size = film.size();
    tbb::enumerable_thread_specific<ThreadState> threads([&] {
        return ThreadState{camera.sampler().clone(control.seed), film.createBlock(Point2i(0), size),
                           film.createBlock(Point2i(0), size), {}, {},
                           std::vector<float>(channels.size()), std::vector<float>(channels.size())};
    });
    ProgressBar progress("Rendering (bdpt)", std::uint64_t(size.x) * size.y * range.count, control.progress);
    auto start = std::chrono::steady_clock::now();
    tbb::parallel_for(0, size.y, [&](int y) {
        if (control.stopRequested()) return;
        ThreadState& ts = threads.local();
        for (int x = 0; x < size.x; ++x) {
            ts.sampler->startPixel({x, y});
            for (std::uint64_t k = range.first; k < range.first + range.count; ++k) {
                ts.sampler->startSample(k);
                FilmSample fs = sampleCamera(camera, *ts.sampler, {x, y});
                Vector3f xyz = cie::toXYZ(tracer.sample(fs, ts), fs.lambda);
                std::copy(&xyz.x, &xyz.x + 3, ts.values.begin());
                if (!std::all_of(ts.values.begin(), ts.values.end(), [](float v) { return std::isfinite(v); })) {
                    ++ts.stats.rejected;
                    std::fill(ts.values.begin(), ts.values.end(), 0.f);
                }
                ts.camera.put(fs.pFilm, ts.values.data());
                ++ts.stats.samples;
            }
        }
        progress.update(std::uint64_t(size.x) * range.count);
    });
    progress.finish();

    // Camera-side sums and weights, plus the splats scaled so that the developed pixel is
    // (camera sum / weight) + splats · full-film pixels / (light paths).
    ImageBlock total = film.createBlock(Point2i(0), size);
    std::vector<float> splats(total.data().size(), 0.f);
    for (const ThreadState& ts : threads) {
        for (std::size_t i = 0; i < splats.size(); ++i) {
            total.data()[i] += ts.camera.data()[i];
            splats[i] += ts.splats.data()[i];
        }
        stats.samples += ts.stats.samples;
        stats.rejectedSamples += ts.stats.rejected;
    }
    const Vector2i full = film.fullSize();
    const double lightPaths = double(std::max<std::uint64_t>(stats.samples, 1));
    const float scale = float(double(full.x) * double(full.y) / lightPaths);
    std::vector<float>& data = total.data();
    const std::size_t stride = std::size_t(total.stride()), n = std::size_t(total.channels());
    for (std::size_t i = 0; i < data.size(); i += stride)
        for (std::size_t c = 0; c < n; ++c) data[i + c] += splats[i + c] * data[i + n] * scale;
    film.put(total);
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats.interrupted = control.stopRequested();
    return stats;
}

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::BdptRenderer)
