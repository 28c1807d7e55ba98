// renderer "sppm" — stochastic progressive photon mapping (Mitsuba 0.6's `sppm`).
//
// Each iteration (Hachisuka & Jensen 2009; pbrt-v3 §16.2, pbrt-v4's SPPMIntegrator):
//  1. camera pass (sppm_core.hpp): one path per pixel through delta bounces to a visible
//     point; emission on the way and direct light there (NEE + MIS, as path) go to Ld;
//  2. photon pass: photon_count light paths (light_path.hpp); every vertex with a
//     non-delta BSDF after the first segment leaves a photon (depth-1 photons would count
//     direct light twice), indexed by the `store` child (IEventStore, default hashgrid);
//  3. per pixel: the photons within the pixel's radius R give Φ = Σ β f(wo, ωp) Φp, M
//     of them, and the progressive update (α = alpha)
//         N' = N + αM,   R' = R √(N' / (N + M)),   τ' = (τ + Φ) R'² / R².
// After n iterations the pixel is L = Ld / n + τ / (n · photon_count · π R²).
// Photons whose normal turns away from the visible point's (n · np < 0.5) are skipped,
// as in photon_map.hpp (Jensen 2001, §7.2); a photon path longer than max_depth once
// joined to the camera path is skipped too, so max_depth means what it means for path.
//
// Spectral, without a spectral kernel: each iteration draws ONE set of four wavelengths
// (van der Corput in the iteration index, shifted by the seed), shared by every camera
// path and photon of that iteration, so photon power and camera throughput multiply slot
// by slot. Photons hold power / pdf(λ) (events.hpp), camera values are not divided: the
// pdf is divided once. A path that met a dispersive interface keeps only its hero slot
// (pdf/4): a product is then hero-only, with the factor 4 once (the photon's, else
// applied here). Values are converted to XYZ per iteration.
//
// Progressive: the per-pixel state (R, N, τ, Ld) persists across render() calls with
// RenderControl::accumulate; a call runs the sample indices [sampleOffset, +sampleCount)
// as iterations (default: max_passes, else the sampler's sample count), so
// `effigi render --spp N` runs N iterations and two calls of n equal one of 2n exactly.
// The film gets each pixel's estimate with weight 1 (a box over the pixel, as Mitsuba's
// and pbrt's SPPM: the film's filter is not applied). varianceEstimate() is false: the
// iterations share each pixel's shrinking radius, so they are not independent samples,
// and the estimator's error is mostly bias, which no sample variance shows.
// Parameters: max_depth, rr_depth, hide_emitters, photon_count (light paths per
// iteration; Mitsuba 0.6 counts stored photons), initial_radius (0: Mitsuba's
// 5 · scene radius / film width in pixels), alpha, max_passes; child `store`.
// Reference: T. Hachisuka, H. W. Jensen, "Stochastic Progressive Photon Mapping",
// SIGGRAPH Asia 2009; Knaus & Zwicker 2011 (the radius update as a sequence of kernels).
#include "photon_map.hpp"
#include "sppm_core.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/math/sample_sequences.hpp"
#include "effigi/spectral/cie.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>

#include <chrono>

namespace effigi {
namespace {

class SppmRenderer final : public Implements<IRenderer> {
public:
    static Schema schema() {
        Schema s("renderer", "sppm", "Stochastic progressive photon mapping (Mitsuba 0.6's `sppm`).");
        s.cite("Hachisuka & Jensen 2009, Stochastic Progressive Photon Mapping, SIGGRAPH Asia");
        s.integer("max_depth", -1, "Longest path in segments (-1: unbounded; 0: black; 1: emitters only)").atLeast(-1);
        s.integer("rr_depth", 5, "Depth from which Russian roulette may end paths").atLeast(1);
        s.boolean("hide_emitters", false, "Do not show emitters seen directly by the camera");
        s.integer("photon_count", 50000, "Light paths traced per iteration").range(1, 1 << 30);
        s.real("initial_radius", 0.0, "Initial gather radius (0: 5 pixels' worth of the scene's bounding radius)")
            .atLeast(0.0)
            .withUnit("scene units");
        s.real("alpha", 0.7, "Fraction of new photons kept per iteration (0 < alpha < 1; smaller shrinks faster)")
            .range(0.0, 1.0);
        s.integer("max_passes", -1, "Iterations of a render without --spp/--time (-1: the sampler's sample count)")
            .atLeast(-1);
        s.child("store", "store", "Event store indexing each iteration's photons (default: hashgrid)");
        s.ignored("granularity", "photons are traced in fixed chunks of effigi's own");
        s.ignored("timeout", "use effigi render --time for a time budget");
        // The suite renders hundreds of 8² to 12² images of unit-sized scenes: 5000 photon
        // paths an iteration, radius 0.1 (the automatic radius of so few pixels covers
        // most of a scene, and every query then sorts every photon).
        using Params = std::vector<std::pair<std::string, PropertyValue>>;
        auto cfg = [&](std::string name, Params extra) {
            auto has = [&](const char* k) {
                return std::any_of(extra.begin(), extra.end(), [&](const auto& e) { return e.first == k; });
            };
            if (!has("photon_count")) extra.push_back({"photon_count", std::int64_t(5000)});
            if (!has("initial_radius")) extra.push_back({"initial_radius", 0.1});
            s.addConformance({std::move(name), std::move(extra)});
        };
        cfg("default", {});
        for (std::int64_t d : {0, 1, 2, 3}) cfg(fmt::format("max_depth {}", d), {{"max_depth", d}});
        cfg("rr_depth 1", {{"rr_depth", std::int64_t(1)}});
        cfg("hide_emitters", {{"hide_emitters", true}});
        cfg("alpha 0.05", {{"alpha", 0.05}});
        cfg("alpha 0.99", {{"alpha", 0.99}});
        cfg("initial_radius 1e-3", {{"initial_radius", 1e-3}});
        cfg("automatic radius", {{"initial_radius", 0.0}, {"photon_count", std::int64_t(1000)}});
        cfg("one photon path", {{"photon_count", std::int64_t(1)}});
        return s;
    }

    explicit SppmRenderer(const Properties& p)
        : m_maxDepth(int(p.getInt("max_depth"))), m_rrDepth(int(p.getInt("rr_depth"))),
          m_hideEmitters(p.getBool("hide_emitters")), m_photonCount(std::uint64_t(p.getInt("photon_count"))),
          m_initialRadius(p.getFloat("initial_radius")), m_alpha(p.getFloat("alpha")),
          m_maxPasses(p.getInt("max_passes")), m_store(p.get<IEventStore>("store")) {
        if (!(m_alpha > 0.f && m_alpha < 1.f))
            failAt(p.whereOf("alpha"), "{}: 'alpha' must lie strictly between 0 and 1 (got {})", p.describe(), m_alpha);
        if (!(std::isfinite(m_initialRadius) && m_initialRadius < 1e9f))
            failAt(p.whereOf("initial_radius"), "{}: 'initial_radius' must be finite", p.describe());
        if (!m_store) {
            Properties sp("store", "hashgrid");
            m_store = query<IEventStore>(Registry::instance().create("store", "hashgrid", sp));
            if (!m_store) fail("{}: the default store 'hashgrid' is not an event store", p.describe());
        }
    }

    RenderStats render(const Scene& scene, const RenderControl& control) override;

private:
    /// The iteration's wavelength sample: radical inverse of k, shifted by the seed.
    static float wavelengthSample(std::uint64_t k, std::uint64_t seed) {
        float u = fixedToFloat(vanDerCorput(std::uint32_t(k))) + fixedToFloat(std::uint32_t(mixBits(seed + 0x3c6ef372u)));
        return u >= 1.f ? u - 1.f : u;
    }
    void tracePhotons(const Scene& scene, std::uint64_t k, const SampledWavelengths& lambda,
                      const RenderControl& control);
    void gather(const SampledWavelengths& lambda, RenderStats& stats);
    void writeFilm(IFilm& film) const;

    int m_maxDepth, m_rrDepth;
    bool m_hideEmitters;
    std::uint64_t m_photonCount;
    float m_initialRadius, m_alpha;
    std::int64_t m_maxPasses;
    Ref<IEventStore> m_store;

    // State across iterations (and accumulating render() calls).
    Vector2i m_size{0};
    std::vector<SppmPixel> m_pixels;
    std::vector<VisiblePoint> m_points;       // this iteration's, one per pixel
    std::vector<Photon> m_photons;            // this iteration's
    std::vector<std::uint8_t> m_heroOnly;     // per photon: its path kept only the hero slot
    std::vector<std::vector<Photon>> m_chunkPhotons;
    std::vector<std::vector<std::uint8_t>> m_chunkHero;
    std::uint64_t m_iterations = 0;
};

RenderStats SppmRenderer::render(const Scene& scene, const RenderControl& control) {
    IFilm& film = scene.camera().film();
    const Vector2i size = film.size();
    const std::size_t pixels = std::size_t(size.x) * std::size_t(size.y);
    if (!control.accumulate || size != m_size || m_pixels.size() != pixels) {
        const Vector2i full = film.fullSize();
        const float r0 = m_initialRadius > 0.f ? m_initialRadius
                                               : 5.f * scene.bbox().boundingRadius() / float(std::max(full.x, full.y));
        m_size = size;
        m_pixels.assign(pixels, SppmPixel{});
        for (SppmPixel& px : m_pixels) px.radius = r0;
        m_points.assign(pixels, VisiblePoint{});
        m_iterations = 0;
    }
    const std::uint64_t count = control.sampleCount ? control.sampleCount
                                : m_maxPasses > 0   ? std::uint64_t(m_maxPasses)
                                                    : std::uint64_t(scene.camera().sampler().samplesPerPixel());
    std::unique_ptr<tbb::global_control> limit;
    if (control.threads > 0)
        limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      std::size_t(control.threads));
    RenderStats stats;
    const auto start = std::chrono::steady_clock::now();
    SppmCameraPass cameraPass(scene, m_maxDepth, m_rrDepth, m_hideEmitters);
    tbb::enumerable_thread_specific<Ref<ISampler>> samplers([&] { return scene.camera().sampler().clone(control.seed); });
    ProgressBar progress("SPPM iterations", count, control.progress);
    for (std::uint64_t k = control.sampleOffset; k < control.sampleOffset + count; ++k) {
        if (control.stopRequested()) break;
        const SampledWavelengths lambda = SampledWavelengths::sampleVisible(wavelengthSample(k, control.seed));
        tbb::parallel_for(0, size.y, [&](int y) {
            if (control.stopRequested()) return;
            ISampler& sampler = *samplers.local();
            for (int x = 0; x < size.x; ++x) {
                VisiblePoint& vp = m_points[std::size_t(y) * size.x + x];
                sampler.startPixel({x, y});
                sampler.startSample(k);
                SampledSpectrum L = cameraPass.trace({x, y}, sampler, lambda, vp);
                vp.ld = cie::toXYZ(L, vp.lambda);
            }
        });
        // A photon (depth >= 2) joined to a camera path (>= 1 segment) needs max_depth >= 3.
        if (m_maxDepth < 0 || m_maxDepth >= 3) tracePhotons(scene, k, lambda, control);
        else m_photons.clear(), m_heroOnly.clear();
        if (control.stopRequested()) break;  // an unfinished iteration leaves no trace
        gather(lambda, stats);
        ++m_iterations;
        stats.samples += pixels;
        progress.update(1);
    }
    progress.finish();
    writeFilm(film);
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats.interrupted = control.stopRequested();
    return stats;
}

void SppmRenderer::tracePhotons(const Scene& scene, std::uint64_t k, const SampledWavelengths& lambda,
                                const RenderControl& control) {
    constexpr std::uint64_t Chunk = 4096;
    const std::uint64_t chunks = (m_photonCount + Chunk - 1) / Chunk;
    m_chunkPhotons.resize(chunks), m_chunkHero.resize(chunks);
    const LightPathLimits limits{m_maxDepth, m_rrDepth};
    tbb::parallel_for(std::uint64_t(0), chunks, [&](std::uint64_t c) {
        std::vector<Photon>& out = m_chunkPhotons[c];
        std::vector<std::uint8_t>& hero = m_chunkHero[c];
        out.clear(), hero.clear();
        if (control.stopRequested()) return;
        photon_detail::PathSampler sampler(control.seed);
        for (std::uint64_t i = c * Chunk; i < std::min(m_photonCount, (c + 1) * Chunk); ++i) {
            sampler.startSample(k * m_photonCount + i);  // path i of iteration k: its own stream
            SampledWavelengths pathLambda = lambda;
            traceLightPath(scene, sampler, pathLambda, limits, [&](const LightVertex& v) {
                if (v.depth < 2 || v.bsdf.isPureSpecular()) return true;
                Photon ph = photonAt(v);
                if (!ph.power.isFinite() || ph.power.isBlack()) return true;
                out.push_back(ph);
                hero.push_back(v.lambda.secondaryTerminated() ? 1 : 0);
                return true;
            });
        }
    });
    m_photons.clear(), m_heroOnly.clear();
    for (std::uint64_t c = 0; c < chunks; ++c) {
        m_photons.insert(m_photons.end(), m_chunkPhotons[c].begin(), m_chunkPhotons[c].end());
        m_heroOnly.insert(m_heroOnly.end(), m_chunkHero[c].begin(), m_chunkHero[c].end());
    }
}

void SppmRenderer::gather(const SampledWavelengths& lambda, RenderStats& stats) {
    std::vector<Point3f> positions(m_photons.size());
    std::transform(m_photons.begin(), m_photons.end(), positions.begin(), [](const Photon& p) { return p.p; });
    float maxRadius = 0.f;
    for (std::size_t i = 0; i < m_pixels.size(); ++i)
        if (m_points[i].depth > 0) maxRadius = std::max(maxRadius, m_pixels[i].radius);
    m_store->clear();
    m_store->insert(positions);
    m_store->build(maxRadius);
    const SampledSpectrum pdf = lambda.pdf();  // of the iteration's (untouched) wavelengths
    tbb::enumerable_thread_specific<std::vector<EventNeighbour>> scratch;
    std::atomic<std::uint64_t> rejected{0};
    tbb::parallel_for(std::size_t(0), m_pixels.size(), [&](std::size_t i) {
        const VisiblePoint& vp = m_points[i];
        SppmPixel& px = m_pixels[i];
        Vector3f phi(0.f);
        float M = 0.f;
        if (vp.depth > 0 && !m_photons.empty()) {
            std::vector<EventNeighbour>& found = scratch.local();
            m_store->radius(vp.si.p, px.radius, found);
            const bool cameraHero = vp.lambda.secondaryTerminated();
            SampledSpectrum sum(0.f);
            for (const EventNeighbour& e : found) {
                const Photon& ph = m_photons[e.index];
                if (m_maxDepth >= 0 && int(ph.depth) + vp.depth > m_maxDepth) continue;
                if (dot(ph.n, vp.si.n) < 0.5f) continue;
                M += 1.f;
                SampledSpectrum c = vp.beta * ph.power *
                                    vp.si.bsdf->f(vp.si, vp.wo, vp.si.toLocal(ph.wi), vp.lambda, TransportMode::Radiance);
                if (cameraHero) c = SampledSpectrum(c[0] * (m_heroOnly[e.index] ? 1.f : 4.f), 0.f, 0.f, 0.f);
                sum += c;
            }
            // sum is already divided by the pdf (photon side): toXYZ divides once more.
            phi = cie::toXYZ(sum * pdf, lambda);
        }
        if (!isFinite(phi) || !isFinite(vp.ld)) {
            rejected.fetch_add(1, std::memory_order_relaxed);
            return;
        }
        for (int c = 0; c < 3; ++c) px.ld[c] += vp.ld[c];
        px.update(M, phi, m_alpha);
    });
    stats.rejectedSamples += rejected.load();
}

void SppmRenderer::writeFilm(IFilm& film) const {
    film.prepare({"X", "Y", "Z"});
    ImageBlock block = film.createBlock(Point2i(0), m_size);
    std::vector<float>& data = block.data();
    const int border = block.border(), stride = block.stride(), width = block.storageSize().x;
    const double n = double(m_iterations), emitted = n * double(m_photonCount);
    for (int y = 0; y < m_size.y; ++y)
        for (int x = 0; x < m_size.x; ++x) {
            const SppmPixel& px = m_pixels[std::size_t(y) * m_size.x + x];
            float* v = data.data() + (std::size_t(y + border) * width + (x + border)) * stride;
            for (int c = 0; c < 3; ++c) v[c] = float(px.estimate(c, n, emitted));
            v[3] = 1.f;
        }
    film.put(block);
}

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::SppmRenderer)
