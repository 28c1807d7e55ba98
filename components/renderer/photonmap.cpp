// renderer "photonmap" — Jensen's two-pass photon mapping with final gathering.
//
// Pass 1 traces light paths (light_path.hpp, the walk ptracer uses) and leaves photons
// (photon_map.hpp): the global map holds a photon at every vertex with a non-delta lobe,
// the caustic map only those reached through one or more delta bounces, L S+ D; each is a
// std::vector<Photon> indexed by an IEventStore (`store`, default kdtree) built here.
// Pass 2 follows delta bounces from the camera (emission seen on the way is added) to
// the first vertex x with a non-delta lobe, where the radiance leaving toward the camera
// is split as Jensen 2001, §9.1 does:
//   direct    next-event estimation: direct_samples light samples and BSDF samples
//             combined by MIS with the power heuristic (mis.hpp, as path does);
//   caustics  density estimate from the caustic map;
//   indirect  final gather: gather_samples BSDF-sampled rays, each followed through
//             delta bounces to a surface y where the global map's estimate is read
//             (emission at y is not: direct light is already counted at x); with
//             final_gather=false the global map is read at x itself, less its direct
//             (depth 1) and caustic photons.
// Delta lobes of a mixed BSDF (plastic's coat) are estimated by one BSDF sample that
// continues the path when it picks a delta lobe; chains of delta bounces end after 64.
// max_depth holds exactly: a photon of depth d is used at a camera depth c only when
// c + d ≤ max_depth.
//
// Spectral: photons keep their paths' four wavelengths; a camera path reads them through
// a box of spectral_bandwidth nm around each of its wavelengths (photon_map.hpp), and a
// dispersive interface on either side keeps the hero wavelength only (weight 4).
// Measured on scenes/cornell-box (128², 16 spp, two seeds; bench/RESULTS.md): the width
// shows no bias there (smooth spectra: wall means within noise for 5, 20 and 80 nm) and
// little noise, as the final gather averages many lookups: per-pixel noise on the walls
// 8.5 / 7.6 / 7.3 % for 5 / 20 / 80 nm (7.0 / 6.3 / 6.0 % with final_gather=false). The
// default 20 nm keeps spectral detail of that scale (line spectra, dispersion) at < 5 %
// extra noise over a box 4× as wide.
// Bias: density estimation blurs over the lookup radius and loses light at the edges of
// surfaces; at the defaults the Cornell box's image mean is 0.8 % low and the ceiling,
// the worst wall, 3.3 % (1.5 % with 1M global photons); bench/photonmap_vs_path.py.
//
// Parameters (Mitsuba 0.6's photonmapper, snake_case): global_photons, caustic_photons
// (photons to store; power is divided by the paths emitted), global_lookup_radius and
// caustic_lookup_radius (largest lookup radius, relative to the scene's bounding
// radius), lookup_size (k nearest photons), max_depth, rr_depth, direct_samples,
// gather_samples, hide_emitters; effigi's final_gather, kernel (cone | epanechnikov),
// spectral_bandwidth (nm), store (IEventStore type). The maps are rebuilt for every
// render() call (every progressive pass, with its own seed), so passes average
// independent maps.
// Reference: H. W. Jensen, "Global Illumination using Photon Maps", EGWR 1996;
// H. W. Jensen, "Realistic Image Synthesis Using Photon Mapping", 2001, ch. 7–9.
#include "mis.hpp"
#include "photon_map.hpp"
#include "sampled_renderer.hpp"

#include "effigi/core/log.hpp"
#include "effigi/core/registry.hpp"

#include <tbb/global_control.h>

#include <atomic>
#include <chrono>
#include <mutex>

namespace effigi {
namespace {

class PhotonMapRenderer final : public SampledRenderer {
public:
    static Schema schema();
    explicit PhotonMapRenderer(const Properties& p);

    RenderStats render(const Scene& scene, const RenderControl& control) override {
        auto start = std::chrono::steady_clock::now();
        buildMaps(scene, control);
        RenderStats stats = SampledRenderer::render(scene, control);
        stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return stats;
    }

    SampledSpectrum sampleRadiance(const Scene& scene, const Ray& ray, SampledWavelengths& lambda, ISampler& sampler,
                                   float*) const override {
        if (!m_built) {  // nested (aov, moment): nobody called render()
            std::lock_guard<std::mutex> lock(m_buildMutex);
            if (!m_built) const_cast<PhotonMapRenderer*>(this)->buildMaps(scene, RenderControl{nullptr, false});
        }
        SampledSpectrum L(0.f);
        auto emitted = [&](const SampledSpectrum& beta, const SampledSpectrum& Le, int depth) {
            if (depth <= m_maxDepth && !(depth == 1 && m_hideEmitters)) L += beta * Le;
        };
        followDeltaBounces(
            scene, ray, SampledSpectrum(1.f), lambda, sampler, 1, m_maxDepth,
            [&](const Vector3f& d, const SampledSpectrum& beta, int depth) {
                for (const IEmitter* env : scene.environments()) emitted(beta, env->evalEnvironment(d, lambda), depth);
            },
            [&](const SurfaceInteraction& si, const SampledSpectrum& beta, int depth) {
                if (si.emitter) emitted(beta, si.emitter->eval(si, lambda), depth);
            },
            [&](const SurfaceInteraction& si, const IBSDF& bsdf, const Vector3f& wo, const SampledSpectrum& beta,
                int depth) { L += beta * shade(scene, si, bsdf, wo, lambda, sampler, depth); });
        return L;
    }

private:
    /// Radiance leaving x = si toward wo through its non-delta lobes.
    SampledSpectrum shade(const Scene& scene, const SurfaceInteraction& si, const IBSDF& bsdf, const Vector3f& wo,
                          SampledWavelengths& lambda, ISampler& sampler, int depth) const {
        thread_local std::vector<EventNeighbour> scratch;
        SampledSpectrum L = direct(scene, si, bsdf, wo, lambda, sampler);
        L += m_caustic->radiance(si, bsdf, wo, lambda, m_causticLookup, PhotonFilter{1, m_maxDepth - depth}, scratch);
        if (!m_finalGather)
            return L + m_global->radiance(si, bsdf, wo, lambda, m_globalLookup,
                                          PhotonFilter{2, m_maxDepth - depth, true}, scratch);
        SampledSpectrum gathered(0.f);
        for (int k = 0; k < m_gatherSamples; ++k) {
            float uc = sampler.get1D();
            Point2f u = sampler.get2D();
            std::optional<BSDFSample> bs = bsdf.sample(si, wo, uc, u, lambda, TransportMode::Radiance);
            // Delta lobes are not gathered: the continuation in followDeltaBounces takes them.
            if (!bs || !(bs->pdf > 0.f) || bs->isSpecular() || (bs->flags & BSDFNull) || bs->f.isBlack()) continue;
            followDeltaBounces(
                scene, si.spawnRay(si.toWorld(bs->wi)), bs->f * (std::abs(bs->wi.z) / bs->pdf), lambda, sampler,
                depth + 1, m_maxDepth, [](const Vector3f&, const SampledSpectrum&, int) {},
                [](const SurfaceInteraction&, const SampledSpectrum&, int) {},
                [&](const SurfaceInteraction& y, const IBSDF& by, const Vector3f& woY, const SampledSpectrum& beta,
                    int depthY) {
                    gathered += beta * m_global->radiance(y, by, woY, lambda, m_globalLookup,
                                                          PhotonFilter{1, m_maxDepth - depthY}, scratch);
                });
        }
        return L + gathered / float(m_gatherSamples);
    }

    /// Next-event estimation with MIS (power heuristic), as path and direct do: light
    /// samples, and BSDF samples of the non-delta lobes that find an emitter.
    SampledSpectrum direct(const Scene& scene, const SurfaceInteraction& si, const IBSDF& bsdf, const Vector3f& wo,
                           SampledWavelengths& lambda, ISampler& sampler) const {
        SampledSpectrum L(0.f);
        for (int k = 0; k < m_directSamples; ++k) {
            float uSel = sampler.get1D();
            Point2f uL = sampler.get2D();
            std::optional<mis::LightSample> ls = mis::sampleLight(scene, si, bsdf, wo, uSel, uL, lambda);
            if (ls && !scene.occluded(ls->shadow)) {
                float w = ls->es.delta ? 1.f
                                       : mis::powerHeuristic(ls->pdf,
                                                             bsdf.pdf(si, wo, ls->wi, lambda, TransportMode::Radiance));
                L += ls->f * ls->es.L * (w / ls->pdf);
            }
            float uc = sampler.get1D();
            Point2f u = sampler.get2D();
            std::optional<BSDFSample> bs = bsdf.sample(si, wo, uc, u, lambda, TransportMode::Radiance);
            if (!bs || !(bs->pdf > 0.f) || bs->isSpecular() || (bs->flags & BSDFNull) || bs->f.isBlack()) continue;
            const SampledSpectrum beta = bs->f * (std::abs(bs->wi.z) / bs->pdf);
            const Vector3f d = si.toWorld(bs->wi);
            SurfaceInteraction hit;
            if (scene.intersect(si.spawnRay(d), hit)) {
                if (hit.emitter)
                    L += beta * hit.emitter->eval(hit, lambda) *
                         mis::powerHeuristic(bs->pdf, mis::emitterHitPdf(scene, si.p, hit));
            } else {
                for (const IEmitter* env : scene.environments())
                    L += beta * env->evalEnvironment(d, lambda) *
                         mis::powerHeuristic(bs->pdf, mis::environmentHitPdf(scene, *env, si.p, d));
            }
        }
        return L / float(m_directSamples);
    }

    void buildMaps(const Scene& scene, const RenderControl& control);

    int m_maxDepth, m_rrDepth, m_directSamples, m_gatherSamples;
    bool m_hideEmitters, m_finalGather;
    std::uint64_t m_globalPhotons, m_causticPhotons;
    float m_globalRadius, m_causticRadius;
    PhotonLookup m_globalLookup, m_causticLookup;
    std::string m_store;
    std::unique_ptr<PhotonMap> m_global, m_caustic;
    std::atomic<bool> m_built{false};
    mutable std::mutex m_buildMutex;
};

Schema PhotonMapRenderer::schema() {
    Schema s("renderer", "photonmap",
             "Photon mapping (Jensen): global and caustic photon maps, next-event estimation, final gathering.");
    s.cite("H. W. Jensen, Realistic Image Synthesis Using Photon Mapping, 2001; Global Illumination using Photon "
           "Maps, EGWR 1996");
    s.integer("global_photons", 250000, "Photons to store in the global map").range(0, 1e9);
    s.integer("caustic_photons", 250000, "Photons to store in the caustic map").range(0, 1e9);
    s.real("global_lookup_radius", 0.05, "Largest global-map lookup radius, relative to the scene's bounding radius")
        .range(0.0, 1e3);
    s.real("caustic_lookup_radius", 0.0125, "Largest caustic-map lookup radius, relative to the scene's bounding radius")
        .range(0.0, 1e3);
    s.integer("lookup_size", 120, "Nearest photons in a radiance estimate (k)").range(1, 100000);
    s.integer("max_depth", -1, "Longest path in segments (-1: unbounded; 0: black; 1: emitters only)").atLeast(-1);
    s.integer("rr_depth", 5, "Depth from which Russian roulette may end light paths").atLeast(1);
    s.integer("direct_samples", 1, "Light and BSDF samples of direct light per camera sample").range(1, 1024);
    s.integer("gather_samples", 1, "Final-gather rays per camera sample (Mitsuba 0.6: glossy_samples)").range(1, 1024);
    s.boolean("final_gather", true, "Estimate indirect light by final gathering (false: read the global map at x)");
    s.string("kernel", "epanechnikov", "Density-estimation kernel: cone (Jensen) or epanechnikov")
        .oneOf({"cone", "epanechnikov"});
    s.real("spectral_bandwidth", 20.0, "Width of the wavelength box through which photons are seen").range(0.0, 470.0)
        .withUnit("nm");
    s.string("store", "kdtree", "Event store (IEventStore component) indexing the photons");
    s.boolean("hide_emitters", false, "Do not show emitters seen directly by the camera");
    s.optional("glossy_samples", ParamType::Int, "Mitsuba 0.6's name, read as gather_samples").range(1, 1024);
    s.ignored("granularity", "effigi chooses its own photon chunks");
    s.ignored("volume_photons", "effigi has no participating media");
    addSchedulingParams(s);
    // The configurations store 50000 global and 5000 caustic photons (the defaults
    // otherwise) or 25000 / 2500, which keeps the suite's hundreds of map builds quick;
    // extremes: k = 1, a box as wide as the spectrum, radii 1/10 of the default (a lookup
    // then finds ~3 photons).
    using Params = std::vector<std::pair<std::string, PropertyValue>>;
    s.addConformance({"default, 50000 photons",
                      {{"global_photons", std::int64_t(50000)}, {"caustic_photons", std::int64_t(5000)}}});
    auto config = [&](std::string name, Params extra) {
        extra.emplace_back("global_photons", std::int64_t(25000));
        extra.emplace_back("caustic_photons", std::int64_t(2500));
        s.addConformance({std::move(name), std::move(extra)});
    };
    config("no final gather", {{"final_gather", false}});
    config("cone kernel", {{"kernel", std::string("cone")}});
    for (std::int64_t d : {0, 1, 2, 3})
        config(fmt::format("max_depth {}", d), {{"max_depth", d}});
    config("rr_depth 1", {{"rr_depth", std::int64_t(1)}});
    config("hide_emitters", {{"hide_emitters", true}});
    config("k 1", {{"lookup_size", std::int64_t(1)}});
    config("wide spectral box", {{"spectral_bandwidth", 470.0}});
    config("small radii", {{"global_lookup_radius", 0.005}, {"caustic_lookup_radius", 0.00125}});
    config("hashgrid store", {{"store", std::string("hashgrid")}});
    return s;
}

PhotonMapRenderer::PhotonMapRenderer(const Properties& p)
    : SampledRenderer(p), m_maxDepth(int(p.getInt("max_depth"))), m_rrDepth(int(p.getInt("rr_depth"))),
      m_directSamples(int(p.getInt("direct_samples"))),
      m_gatherSamples(int(p.has("glossy_samples") ? p.getInt("glossy_samples") : p.getInt("gather_samples"))),
      m_hideEmitters(p.getBool("hide_emitters")), m_finalGather(p.getBool("final_gather")),
      m_globalPhotons(std::uint64_t(p.getInt("global_photons"))),
      m_causticPhotons(std::uint64_t(p.getInt("caustic_photons"))),
      m_globalRadius(p.getFloat("global_lookup_radius")), m_causticRadius(p.getFloat("caustic_lookup_radius")),
      m_store(p.getString("store")) {
    for (const char* name : {"global_lookup_radius", "caustic_lookup_radius", "spectral_bandwidth"})
        if (!(p.getFloat(name) > 0.f) || !std::isfinite(p.getFloat(name)))
            failAt(p.whereOf(name), "{}: '{}' must be a positive number", p.describe(), name);
    if (!Registry::instance().knows("store", m_store))
        failAt(p.whereOf("store"), "{}: 'store': no event store named '{}' (try kdtree or hashgrid)", p.describe(),
               m_store);
    if (m_maxDepth < 0) m_maxDepth = 1 << 30;
    const PhotonKernel kernel = p.getString("kernel") == "cone" ? PhotonKernel::Cone : PhotonKernel::Epanechnikov;
    const float bandwidth = p.getFloat("spectral_bandwidth");
    const std::size_t k = std::size_t(p.getInt("lookup_size"));
    m_globalLookup = PhotonLookup{k, 0.f, bandwidth, kernel};
    m_causticLookup = PhotonLookup{k, 0.f, bandwidth, kernel};
}

void PhotonMapRenderer::buildMaps(const Scene& scene, const RenderControl& control) {
    auto start = std::chrono::steady_clock::now();
    std::unique_ptr<tbb::global_control> limit;  // -t applies to photon tracing too
    if (control.threads > 0)
        limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      std::size_t(control.threads));
    const float sceneRadius = std::max(scene.bbox().boundingRadius(), 1e-6f);
    m_globalLookup.maxRadius = m_globalRadius * sceneRadius;
    m_causticLookup.maxRadius = m_causticRadius * sceneRadius;
    auto makeMap = [&] {
        Properties props("store", m_store);
        Ref<IEventStore> store = query<IEventStore>(Registry::instance().create("store", m_store, props));
        if (!store) fail("renderer 'photonmap': '{}' is not an event store", m_store);
        return std::make_unique<PhotonMap>(store);
    };
    m_global = makeMap();
    m_caustic = makeMap();
    // A photon at depth d lights a camera vertex one segment away at least.
    const LightPathLimits limits{m_maxDepth >= (1 << 30) ? -1 : m_maxDepth, m_rrDepth};
    // Each pass (sample offset) gets its own maps; same seed and pass, same maps.
    const std::uint64_t seed = mixBits(control.seed * 0x9e3779b97f4a7c15ull + control.sampleOffset);
    // Photons light paths of 3 segments or more (camera, gather or photon, ≥ 1 more):
    // below that, emission and next-event estimation see everything.
    const bool needMaps = m_maxDepth >= 3;
    PhotonTraceResult g = tracePhotons(scene, PhotonPass::Global, needMaps ? m_globalPhotons : 0, limits, seed, control);
    PhotonTraceResult c = tracePhotons(scene, PhotonPass::Caustic, needMaps ? m_causticPhotons : 0, limits,
                                       seed + 1, control);
    const std::uint64_t gPaths = g.emittedPaths, cPaths = c.emittedPaths;
    m_global->build(std::move(g.photons), gPaths ? 1.f / float(gPaths) : 0.f, m_globalLookup.maxRadius, gPaths);
    m_caustic->build(std::move(c.photons), cPaths ? 1.f / float(cPaths) : 0.f, m_causticLookup.maxRadius, cPaths);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    log::info("photonmap: global map {} photons ({} light paths), caustic map {} photons ({} light paths); "
              "traced and built in {:.2f} s, {:.1f} MiB",
              m_global->size(), gPaths, m_caustic->size(), cPaths, seconds,
              double(m_global->memoryBytes() + m_caustic->memoryBytes()) / (1024.0 * 1024.0));
    if (m_causticPhotons > 0 && cPaths > 0 && m_caustic->size() == 0)
        log::debug("photonmap: no caustic photons (no delta surfaces lit from the emitters)");
    m_built = true;
}

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::PhotonMapRenderer)
