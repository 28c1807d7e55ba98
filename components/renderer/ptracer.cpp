// renderer "ptracer" — particle (light) tracing (Mitsuba 3's `ptracer`).
//
// Paths start at the lights (IEmitter::sampleEmission) and are continued by BSDF
// sampling in importance transport mode; every surface vertex is connected to the
// camera (ICameraImportance::sampleDirection) and its contribution splatted onto the
// film at the position it projects to (film_splat.hpp). Emitters seen directly are a separate estimate
// per path: a point chosen on a surface emitter (or a direction toward an infinite one)
// is connected to the camera; delta lights cannot be seen. As in Mitsuba, a pass traces
// spp · (full film pixels) light paths and each splat is scaled so the image matches
// the camera-side renderers (path) in expectation: the camera's importance integrates to
// 1 over the full film, so pixel j measures P · ∫ W_e L over j for P pixels, and with
// spp · P paths a splat weighs throughput · importance / spp. Splats spread over the
// film's reconstruction filter with weights normalised to sum to 1 (Mitsuba's normalised
// image block), so the filter only blurs and never changes the brightness.
// Shading normals get the adjoint correction |wo·ng · wi·ns| / |wo·ns · wi·ng| of Veach
// 1997 §5.3, and paths crossing the geometric and shading hemispheres inconsistently end.
//
// The walk from the lights is light_path.hpp, shared with photon tracing (photonmap).
// Parameters: max_depth (−1 unbounded; 0 nothing; 1 emitters seen directly; 2 direct
// lighting, as in Mitsuba), rr_depth (Russian roulette from that depth on),
// hide_emitters, samples_per_pass (spp is rendered in passes of this many samples; must
// divide the sampler's sample count, as Mitsuba requires).
// Needs a camera implementing ICameraImportance (perspective, thinlens, orthographic);
// others are an error.
// Reference: Veach 1997, PhD thesis, §4.A, §5.3, §8.1; Mitsuba 3 src/integrators/ptracer.cpp.
#include "film_splat.hpp"
#include "light_path.hpp"

#include "effigi/core/progress.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/icamera_importance.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/ifilter.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/render/scene.hpp"
#include "effigi/render/tile_renderer.hpp"
#include "effigi/spectral/cie.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <memory>

namespace effigi {
namespace {

/// One thread's share: its sampler, a block covering the whole film, counters.
struct ThreadState {
    Ref<ISampler> sampler;
    ImageBlock block;
    TileStats stats;
};

class LightTracer {
public:
    LightTracer(const Scene& scene, const ICameraImportance& camera, const FilterTable& filter, int maxDepth,
                int rrDepth, bool hideEmitters)
        : m_scene(scene), m_camera(camera), m_splatter(filter, scene.camera().film().cropOffset()),
          m_maxDepth(maxDepth), m_rrDepth(rrDepth), m_hideEmitters(hideEmitters) {
        Point3f cam = scene.camera().toWorld().point(Point3f(0.f));
        // Far enough for a direction toward an infinite light to leave the whole scene.
        m_farDistance = 2.f * (scene.bbox().boundingRadius() + length(cam - scene.bbox().center())) + 1.f;
    }

    /// One light path (Mitsuba's ParticleTracerIntegrator::sample).
    void sample(ISampler& sampler, ImageBlock& block, TileStats& ts) const {
        SampledWavelengths lambda = SampledWavelengths::sampleVisible(sampler.get1D());
        if (m_maxDepth != 0 && !m_hideEmitters) visibleEmitter(sampler, lambda, block, ts);
        traceLightPath(sampler, lambda, block, ts);
    }

private:
    /// Connect a point on a light (or a direction toward an infinite one) to the camera.
    void visibleEmitter(ISampler& sampler, const SampledWavelengths& lambda, ImageBlock& block, TileStats& ts) const {
        float selPdf;
        const IEmitter* emitter = m_scene.sampleEmitter(sampler.get1D(), selPdf);
        Point2f uPos = sampler.get2D(), uCam = sampler.get2D();
        if (!emitter || emitter->isDelta()) return;
        const Point3f cam = m_scene.camera().toWorld().point(Point3f(0.f));
        CameraImportanceSample cs;
        if (emitter->isInfinite()) {
            EmitterSample es = emitter->sampleDirect(cam, uPos, lambda);
            if (!(es.pdf > 0.f) || es.L.isBlack()) return;
            // The importance toward a point at distance R falls as 1/R²; R² restores the
            // importance per solid angle that arriving radiance needs.
            const float R = m_farDistance;
            // A camera with a delta direction (orthographic) sees no sampled direction.
            if (!m_camera.sampleDirection(cam + es.wi * R, uCam, cs) || cs.deltaDirection) return;
            // From the lens point the connection chose (a thin lens has more than one).
            if (m_scene.occluded(Ray{cs.pCamera, -cs.wi, Infinity})) return;
            splat(cs.pFilm, es.L * (cs.weight * R * R / (es.pdf * selPdf * cs.pdf)), lambda, block, ts);
            return;
        }
        // Surface emitters are Lambertian: the radiance of the sampled point holds in
        // every direction of its hemisphere, whichever direction sampleEmission drew.
        EmissionSample es = emitter->sampleEmission(uPos, Point2f(0.5f), lambda);
        if (!(es.pdfPosition > 0.f) || es.L.isBlack()) return;
        if (!m_camera.sampleDirection(es.ray.o, uCam, cs)) return;
        float cosTheta = dot(es.n, cs.wi);
        if (!(cosTheta > 0.f)) return;  // the camera is behind the light
        if (m_scene.occluded(Ray{es.ray.o, cs.pCamera - es.ray.o, 1.f - ShadowEpsilon})) return;
        splat(cs.pFilm, es.L * (cosTheta * cs.weight / (es.pdfPosition * selPdf * cs.pdf)), lambda, block, ts);
    }

    /// The shared light-path walk (light_path.hpp), every vertex connected to the camera.
    void traceLightPath(ISampler& sampler, SampledWavelengths& lambda, ImageBlock& block, TileStats& ts) const {
        effigi::traceLightPath(m_scene, sampler, lambda, LightPathLimits{m_maxDepth, m_rrDepth},
                               [&](const LightVertex& v) {
                                   connectCamera(v.si, v.bsdf, v.wo, v.woGeo, v.beta, sampler.get2D(), v.lambda,
                                                 block, ts);
                                   return true;
                               });
    }

    /// Splat the contribution of vertex si seen by the camera (Mitsuba's connect_sensor).
    void connectCamera(const SurfaceInteraction& si, const IBSDF& bsdf, const Vector3f& wo, float woGeo,
                       const SampledSpectrum& beta, const Point2f& u, const SampledWavelengths& lambda,
                       ImageBlock& block, TileStats& ts) const {
        CameraImportanceSample cs;
        if (!m_camera.sampleDirection(si.p, u, cs)) return;
        Vector3f wi = si.toLocal(cs.wi);
        float wiGeo = dot(si.n, cs.wi);
        if (!(woGeo * wo.z > 0.f) || !(wiGeo * wi.z > 0.f)) return;
        SampledSpectrum f = bsdf.f(si, wo, wi, lambda, TransportMode::Importance);
        if (f.isBlack()) return;
        if (m_scene.occluded(si.spawnRayTo(cs.pCamera))) return;
        float correction = std::abs(wo.z * wiGeo / (wi.z * woGeo));
        splat(cs.pFilm, beta * f * (std::abs(wi.z) * correction * cs.weight / cs.pdf), lambda, block, ts);
    }

    void splat(const Point2f& pFilm, const SampledSpectrum& L, const SampledWavelengths& lambda, ImageBlock& block,
               TileStats& ts) const {
        m_splatter.splat(pFilm, L, lambda, block, ts);
    }

    const Scene& m_scene;
    const ICameraImportance& m_camera;
    FilmSplatter m_splatter;
    int m_maxDepth, m_rrDepth;
    bool m_hideEmitters;
    float m_farDistance = 1.f;
};

class ParticleTracerRenderer final : public Implements<IRenderer> {
public:
    static Schema schema() {
        Schema s("renderer", "ptracer", "Particle tracer: light paths connected to the camera (Mitsuba's `ptracer`).");
        s.cite("Veach 1997, Robust Monte Carlo Methods for Light Transport Simulation, §4.A, §8.1");
        s.integer("max_depth", -1, "Longest path in segments (-1: unbounded; 0: black; 1: emitters only)").atLeast(-1);
        s.integer("rr_depth", 5, "Depth from which Russian roulette may end paths").atLeast(1);
        s.boolean("hide_emitters", false, "Do not show emitters seen directly by the camera");
        s.optional("samples_per_pass", ParamType::Int,
                   "Samples per pixel per pass (divides the sample count; default: all in one pass)")
            .atLeast(1);
        s.ignored("timeout", "use effigi render --time for a time budget");
        s.addConformance({"default", {}});
        for (std::int64_t d : {0, 1, 3})
            s.addConformance({fmt::format("max_depth {}", d), {{"max_depth", d}}});
        s.addConformance({"rr_depth 1", {{"rr_depth", std::int64_t(1)}}});
        s.addConformance({"hide_emitters", {{"hide_emitters", true}}});
        s.addConformance({"one sample per pass", {{"samples_per_pass", std::int64_t(1)}}});
        return s;
    }

    explicit ParticleTracerRenderer(const Properties& p)
        : m_maxDepth(int(p.getInt("max_depth"))), m_rrDepth(int(p.getInt("rr_depth"))),
          m_hideEmitters(p.getBool("hide_emitters")) {
        if (p.has("samples_per_pass")) {
            m_samplesPerPass = p.getInt("samples_per_pass");
            m_passWhere = p.whereOf("samples_per_pass");
            if (m_samplesPerPass < 1) failAt(m_passWhere, "{}: 'samples_per_pass' must be >= 1", p.describe());
        }
    }

    RenderStats render(const Scene& scene, const RenderControl& control) override;

private:
    int m_maxDepth, m_rrDepth;
    bool m_hideEmitters;
    std::int64_t m_samplesPerPass = std::numeric_limits<std::int64_t>::max();
    SourceLocation m_passWhere;
};

RenderStats ParticleTracerRenderer::render(const Scene& scene, const RenderControl& control) {
    ICamera& camera = scene.camera();
    IFilm& film = camera.film();
    const auto* importance = query<ICameraImportance>(&camera);
    if (!importance)
        fail("{}: renderer 'ptracer': the camera cannot be connected to from the scene (no ICameraImportance; "
             "use a perspective, thinlens or orthographic camera)",
             scene.sourceFile);
    if (!control.accumulate) film.prepare({"X", "Y", "Z"});
    RenderStats stats;
    if (scene.emitters().empty() || m_maxDepth == 0) return stats;  // black, as in Mitsuba

    SampleRange range{control.sampleOffset,
                      control.sampleCount ? control.sampleCount : std::uint64_t(camera.sampler().samplesPerPixel())};
    std::uint64_t perPass = std::min<std::uint64_t>(range.count, std::uint64_t(m_samplesPerPass));
    if (range.count % perPass != 0)
        failAt(m_passWhere, "renderer 'ptracer': the sample count {} is not a multiple of samples_per_pass = {}",
               range.count, perPass);

    std::unique_ptr<tbb::global_control> limit;
    if (control.threads > 0)
        limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      std::size_t(control.threads));
    FilterTable filter(film.filter());
    LightTracer tracer(scene, *importance, filter, m_maxDepth, m_rrDepth, m_hideEmitters);
    const Vector2i full = film.fullSize();
    tbb::enumerable_thread_specific<ThreadState> threads([&] {
        return ThreadState{camera.sampler().clone(control.seed), film.createBlock(Point2i(0), film.size()), {}};
    });
    // As many light paths as camera samples over the full film (Mitsuba's count), each
    // keyed by a film "pixel" and sample index so the result does not depend on threads.
    ProgressBar progress("Light tracing", std::uint64_t(full.x) * full.y * range.count, control.progress);
    auto start = std::chrono::steady_clock::now();
    for (std::uint64_t first = range.first; first < range.first + range.count && !control.stopRequested();
         first += perPass) {
        tbb::parallel_for(0, full.y, [&](int y) {
            if (control.stopRequested()) return;
            ThreadState& ts = threads.local();
            for (int x = 0; x < full.x; ++x) {
                ts.sampler->startPixel({x, y});
                for (std::uint64_t k = first; k < first + perPass; ++k) {
                    ts.sampler->startSample(k);
                    tracer.sample(*ts.sampler, ts.block, ts.stats);
                    ++ts.stats.samples;
                }
            }
            progress.update(std::uint64_t(full.x) * perPass);
        });
    }
    progress.finish();

    // Sum the threads' blocks. Each pixel's weight is the pass's spp (light paths per
    // full-film pixel), so the film's weighted average divides the splats by the total
    // spp over accumulated passes: Mitsuba's 1 / spp scale.
    ImageBlock total = film.createBlock(Point2i(0), film.size());
    std::vector<float>& data = total.data();
    for (const ThreadState& ts : threads) {
        const std::vector<float>& d = ts.block.data();
        for (std::size_t i = 0; i < data.size(); ++i) data[i] += d[i];
        stats.samples += ts.stats.samples;
        stats.rejectedSamples += ts.stats.rejected;
    }
    // A pass cut short (SIGINT) weighs by the light paths it did trace: any subset of
    // them is an unbiased set, so the image stays as bright, only noisier.
    const float spp = float(double(stats.samples) / (double(full.x) * double(full.y)));
    for (std::size_t i = std::size_t(total.channels()); i < data.size(); i += std::size_t(total.stride()))
        data[i] = spp;
    film.put(total);
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats.interrupted = control.stopRequested();
    return stats;
}

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::ParticleTracerRenderer)
