// renderer "irradiancecache" — irradiance caching: indirect diffuse light interpolated
// from sparse records with gradients, direct and specular light by path tracing.
//
// Records (irradiance_gather.hpp; lookup: irradiance_cache.hpp): at a purely diffuse point,
// M × 3M stratified cosine-weighted gather rays (M = resolution, as Mitsuba 0.6's overture);
// each ray's radiance is path_core's estimator continued from its hit without the hit's own
// emission (direct light, which the render pass samples): the full indirect irradiance to
// max_depth (one bounce + NEE would drop the later bounces). E, Ward & Heckbert's gradients
// and the harmonic mean distance R come from the same samples; R is limited by
// E/|∇_t E| and neighbour clamping (Křivánek et al. 2006) and clamped to 1.5–10 pixel
// footprints at the overture's error a (clamp_screen; Tabellion & Lamorlette 2004), else to
// [1e-4, 1] × the scene's diagonal.
// Overture (deterministic): pixel centres on grids of stride 16, 8, 4, 2, 1, coarse to fine,
// each in four interleaved steps; a step looks up every new centre's first diffuse point
// (after delta bounces when max_depth is unbounded) in the cache as it stands, gathers
// records for the misses in parallel and adds them in pixel order. Error a = 0.2/quality (quality in Mitsuba's sense:
// higher, more records); the render pass reads with a / quality_adjustment (smoother). With
// overture = false only the stride-1 round runs, at the render's a.
// Render pass: camera paths as `path`; at the first diffuse point (after delta bounces only
// where max_depth is unbounded: records assume depth 1), L = emission + NEE and a BSDF sample (MIS) +
// f(wo, n) · E_cache. Where no record qualifies (points the overture did not see) the path
// simply goes on: path tracing, unbiased there. The render pass never writes the cache, so
// the image is a deterministic function of the seed.
// Spectral: records hold E at 16 nodes (360–830 nm, 31.3 nm apart); each gather ray is
// traced four times at four nodes each with the same random numbers (same directions);
// camera wavelengths interpolate between nodes (Catmull-Rom, clamped at 0). Bias: O(h⁴ E⁗),
// h = 31.3 nm; in a closed enclosure (exact in space) against `path`: flat-spectrum grey
// walls 0.1 %, D65 (its lines) R +0.5 %, red walls (0.7, 0.2, 0.1), whose indirect spectrum
// ρ/(1 − ρ) is sharp, R +0.6 % (linear: +3.8 %); narrow lines (F11) smear over ±31 nm.
// Biases in space: Ward's error a (worst across corners and contact shadows, where radii
// are clamped to a minimum footprint), traded against record count by the gradients and
// clamps. A non-Lambertian diffuse BSDF (orennayar) uses f(wo, n) for the whole hemisphere.
// Parameters (Mitsuba 0.6 irrcache's): resolution, quality, gradients, clamp_neighbor,
// clamp_screen, overture, quality_adjustment; max_depth, rr_depth (as `path`; Mitsuba
// takes them from the nested integrator); store (IEventStore, default kdtree).
// References: G. Ward, F. Rubinstein, R. Clear, "A Ray Tracing Solution for Diffuse
// Interreflection", SIGGRAPH 1988; G. Ward, P. Heckbert, "Irradiance Gradients", EGWR 1992;
// J. Křivánek et al., "Making Radiance and Irradiance Caching Practical", EGSR 2006.
#include "irradiance_gather.hpp"

#include "effigi/core/log.hpp"
#include "effigi/core/progress.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/render/tile_renderer.hpp"
#include "effigi/spectral/cie.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <chrono>

namespace effigi {
namespace {

using namespace irrcache;

bool diffuseOnly(const IBSDF& bsdf) {
    const std::uint32_t f = bsdf.flags();
    return (f & BSDFDiffuse) && !(f & (BSDFGlossy | BSDFSpecular | BSDFTransmission | BSDFNull));
}

/// The shading normal turned toward the viewer: the side whose irradiance is wanted.
Vector3f shadingSide(const SurfaceInteraction& si) { return faceForward(si.shading.n, si.wo); }

class IrradianceCacheRenderer final : public Implements<IRenderer> {
public:
    static constexpr float ErrorAtQuality1 = 0.2f;  ///< Ward's a at quality 1

    static Schema schema() {
        Schema s("renderer", "irradiancecache",
                 "Irradiance caching with gradients: indirect diffuse light interpolated from records, the rest "
                 "by path tracing.");
        s.cite("Ward, Rubinstein & Clear, SIGGRAPH 1988; Ward & Heckbert, Irradiance Gradients, EGWR 1992");
        s.integer("resolution", 14, "θ strata of a record's gather (φ: 3×; 3·resolution² rays)").range(1, 256);
        s.real("quality", 1.0, "Higher places more records: Ward's error a = 0.2/quality").range(1e-4, 1e4);
        s.boolean("gradients", true, "Extrapolate with rotational and translational gradients (Ward & Heckbert)");
        s.boolean("clamp_neighbor", true, "Neighbour clamping of validity radii (Křivánek et al. 2006)");
        s.boolean("clamp_screen", true, "Clamp validity radii to 1.5–10 pixel footprints (Tabellion 2004)");
        s.boolean("overture", true, "Seed the cache coarse to fine over the image before rendering");
        s.real("quality_adjustment", 0.5, "Quality factor of the render pass after an overture (≤ 1: smoother)")
            .range(1e-3, 1.0);
        s.integer("max_depth", -1, "Longest path in segments (-1: unbounded), as renderer path").atLeast(-1);
        s.integer("rr_depth", 5, "Depth from which Russian roulette may end paths").atLeast(1);
        s.child("store", "store", "Event store over record positions (default: kdtree)");
        s.addConformance({"default", {}});
        s.addConformance({"resolution 1", {{"resolution", std::int64_t(1)}}});
        s.addConformance({"quality 1e-4", {{"quality", 1e-4}, {"resolution", std::int64_t(4)}}});
        s.addConformance({"quality 1e4", {{"quality", 1e4}, {"resolution", std::int64_t(2)}}});
        s.addConformance({"no gradients, no clamps",
                          {{"gradients", false}, {"clamp_neighbor", false}, {"clamp_screen", false}}});
        s.addConformance({"no overture", {{"overture", false}, {"resolution", std::int64_t(6)}}});
        for (std::int64_t d : {0, 1, 2, 3})
            s.addConformance({fmt::format("max_depth {}", d), {{"max_depth", d}}});
        s.addConformance({"rr_depth 1", {{"rr_depth", std::int64_t(1)}}});
        return s;
    }

    explicit IrradianceCacheRenderer(const Properties& p)
        : m_resolution(int(p.getInt("resolution"))), m_aOverture(ErrorAtQuality1 / float(p.getFloat("quality"))),
          m_gradients(p.getBool("gradients")),
          m_clampNeighbour(p.getBool("clamp_neighbor")), m_clampScreen(p.getBool("clamp_screen")),
          m_overture(p.getBool("overture")), m_maxDepth(int(p.getInt("max_depth"))),
          m_rrDepth(int(p.getInt("rr_depth"))), m_store(p.get<IEventStore>("store")) {
        m_aRender = m_overture ? m_aOverture / float(p.getFloat("quality_adjustment")) : m_aOverture;
    }

    RenderStats render(const Scene& scene, const RenderControl& control) override {
        std::unique_ptr<tbb::global_control> limit;
        if (control.threads > 0)
            limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                          std::size_t(control.threads));
        double cacheSeconds = 0.0;
        if (!control.accumulate || m_cachedScene != &scene) cacheSeconds = buildCache(scene, control);
        for (Scratch& t : m_scratch) t.lookups = 0, t.fallbacks = 0;
        RenderStats stats = renderCameraSamples(
            scene, control,
            [&](const Ray& ray, SampledWavelengths& lambda, const SampledSpectrum& weight, ISampler& sampler) {
                const SampledSpectrum L = weight * radiance(scene, ray, lambda, sampler);  // may end secondaries
                return cie::toXYZ(L, lambda);
            });
        std::uint64_t lookups = 0, fallbacks = 0;
        for (const Scratch& t : m_scratch) lookups += t.lookups, fallbacks += t.fallbacks;
        if (lookups > 0)
            log::info("irradiancecache: {:.2f} % of {} cache lookups found no record (path traced there)",
                      100.0 * double(fallbacks) / double(lookups), lookups);
        stats.seconds += cacheSeconds;
        return stats;
    }

private:
    /// Where the overture looks for a record: the first diffuse point of a pixel centre.
    struct Candidate {
        bool valid = false, miss = false;
        SurfaceInteraction si;
        Vector3f n{0.f};
        float footprint = Infinity;
    };
    struct Scratch {
        std::vector<EventNeighbour> near;
        GatherSampler sampler;
        std::unique_ptr<HemisphereGather> gather;
        std::uint64_t lookups = 0, fallbacks = 0;  // render pass
    };

    bool cacheUsable(const PathState& s, const SurfaceInteraction& si) const {
        return !m_cache.empty() && si.bsdf && diffuseOnly(*si.bsdf) && (s.depth == 1 || (m_maxDepth < 0 && s.specular));
    }

    /// One camera sample: `path` with the indirect diffuse part of the first diffuse point
    /// taken from the cache where a record qualifies.
    SampledSpectrum radiance(const Scene& scene, const Ray& ray, SampledWavelengths& lambda, ISampler& sampler) const {
        const PathIntegrator full(scene, m_maxDepth, m_rrDepth, false);
        PathState s(ray);
        SurfaceInteraction si;
        std::optional<ShadowRay> shadow;
        for (;;) {
            if (!scene.intersect(s.ray, si)) {
                full.miss(s, lambda);
                break;
            }
            if (cacheUsable(s, si)) {
                Scratch& t = m_scratch.local();
                const Vector3f wo = si.toLocal(si.wo);
                const Vector3f wn(0.f, 0.f, wo.z < 0.f ? -1.f : 1.f);
                const SampledSpectrum f = si.bsdf->f(si, wo, wn, lambda, TransportMode::Radiance);
                NodeValues E;
                const bool black = f.isBlack();  // e.g. a one-sided wall from behind: no record needed
                if (!black) ++t.lookups;
                if (black || m_cache.lookup(si.p, shadingSide(si), m_aRender, m_gradients, E, t.near)) {
                    if (!black) s.L += s.beta * f * atWavelengths(E, lambda);
                    // Emission, NEE and one BSDF sample for the direct light (MIS): `path`
                    // one segment longer than here.
                    return PathIntegrator(scene, s.depth + 1, m_rrDepth, false).liFromHit(s, si, lambda, sampler);
                }
                ++t.fallbacks;
            }
            const bool more = full.scatter(s, si, lambda, sampler, shadow);
            if (shadow) s.L += shadow->contribution * full.shadowTransmittance(shadow->ray, lambda);
            if (!more) break;
        }
        return s.L;
    }

    /// The overture's point for pixel px (crop frame), following delta bounces when the
    /// render pass would (max_depth unbounded).
    bool candidate(const Scene& scene, const Point2i& px, GatherSampler& rng, Candidate& c) const {
        const ICamera& camera = scene.camera();
        const Point2f centre = Point2f(px) + Point2f(0.5f) + Point2f(camera.film().cropOffset());
        SampledWavelengths lambda = SampledWavelengths::fromNodes({400.f, 500.f, 600.f, 700.f}, {1.f, 1.f, 1.f, 1.f});
        SampledSpectrum w(1.f);
        Ray ray = camera.generateRay({centre, Point2f(0.5f), 0.f}, lambda, w);
        float travelled = 0.f;
        SurfaceInteraction& si = c.si;
        int depth = 1;
        for (;; ++depth) {
            if (!scene.intersect(ray, si) || !si.bsdf) return false;
            travelled += length(si.p - ray.o);
            if (diffuseOnly(*si.bsdf)) break;
            if (m_maxDepth >= 0 || depth >= 16 || !si.bsdf->isPureSpecular()) return false;
            std::optional<BSDFSample> bs =
                si.bsdf->sample(si, si.toLocal(si.wo), rng.get1D(), rng.get2D(), lambda, TransportMode::Radiance);
            if (!bs || !(bs->pdf > 0.f)) return false;
            ray = si.spawnRay(si.toWorld(bs->wi));
        }
        c.n = shadingSide(si);
        const Vector3f wo = si.toLocal(si.wo);
        if (si.bsdf->f(si, wo, {0.f, 0.f, wo.z < 0.f ? -1.f : 1.f}, lambda, TransportMode::Radiance).isBlack())
            return false;  // reflects nothing toward the camera: the render pass reads no record here
        // Footprint: the pixel's neighbours' rays met on the tangent plane (first hit), or
        // their spread angle times the distance travelled (after delta bounces).
        auto neighbour = [&](float dx, float dy) {
            return camera.generateRay({centre + Point2f(dx, dy), Point2f(0.5f), 0.f}, lambda, w);
        };
        const Ray rx = neighbour(1.f, 0.f), ry = neighbour(0.f, 1.f), r0 = neighbour(0.f, 0.f);
        if (depth == 1) {
            auto onPlane = [&](const Ray& r) { return r.o + r.d * (dot(si.p - r.o, si.n) / dot(r.d, si.n)); };
            c.footprint = std::sqrt(length(cross(onPlane(rx) - si.p, onPlane(ry) - si.p)));
        } else {
            c.footprint = travelled * length(normalize(rx.d) - normalize(r0.d));
        }
        return c.valid = true;
    }

    double buildCache(const Scene& scene, const RenderControl& control) {
        const auto start = std::chrono::steady_clock::now();
        if (!m_store) {
            Properties sp("store", "kdtree");
            m_store = query<IEventStore>(Registry::instance().create("store", "kdtree", sp));
        }
        m_cache.reset(m_store, m_clampNeighbour);
        m_cachedScene = &scene;
        m_diagonal = length(scene.bbox().max - scene.bbox().min);
        if (!(m_diagonal > 0.f) || !std::isfinite(m_diagonal)) m_diagonal = 1.f;
        if (m_maxDepth >= 0 && m_maxDepth < 3) return 0.0;  // no indirect light to cache
        const Vector2i size = scene.camera().film().size();
        const float aLookup = m_overture ? m_aOverture : m_aRender;
        const RecordSettings settings{m_maxDepth, m_rrDepth, m_gradients, m_clampScreen, m_aOverture, m_diagonal};
        ProgressBar bar("Irradiance cache", std::uint64_t(size.x) * size.y, control.progress);
        std::vector<int> strides = m_overture ? std::vector<int>{16, 8, 4, 2, 1} : std::vector<int>{1};
        // Each stride's new centres in up to four steps by parity of (x/st, y/st): centres
        // of one step are 2·st apart, so fewer of them miss for want of each other's records.
        for (int step = 0; step < 4 * int(strides.size()); ++step) {
            const int st = strides[step / 4], px = step % 2, py = step / 2 % 2;
            if (st != strides.front() && px == 0 && py == 0) continue;  // the previous stride's grid
            std::vector<Point2i> pixels;
            for (int y = py * st; y < size.y; y += 2 * st)
                for (int x = px * st; x < size.x; x += 2 * st) pixels.emplace_back(x, y);
            std::vector<Candidate> cands(pixels.size());
            tbb::parallel_for(std::size_t(0), pixels.size(), [&](std::size_t i) {
                Scratch& t = m_scratch.local();
                t.sampler.setKey(mixBits(control.seed ^ 0x5ca1ab1eull) ^
                                 mixBits((std::uint64_t(pixels[i].y) << 32) | std::uint32_t(pixels[i].x)));
                t.sampler.startSample(0);
                NodeValues E;
                if (candidate(scene, pixels[i], t.sampler, cands[i]))
                    cands[i].miss = !m_cache.lookup(cands[i].si.p, cands[i].n, aLookup, m_gradients, E, t.near);
                if (!cands[i].miss) bar.update(1);
            });
            std::vector<std::size_t> misses;
            for (std::size_t i = 0; i < cands.size(); ++i)
                if (cands[i].valid && cands[i].miss) misses.push_back(i);
            std::vector<IrradianceRecord> batch(misses.size());
            tbb::parallel_for(std::size_t(0), misses.size(), [&](std::size_t m) {
                if (control.stopRequested()) return;
                const Point2i px = pixels[misses[m]];
                const std::uint64_t pixelKey = (std::uint64_t(px.y) << 32) | std::uint32_t(px.x);
                const std::uint64_t key = mixBits(control.seed * 0x9e3779b97f4a7c15ull ^ mixBits(pixelKey));
                Scratch& t = m_scratch.local();
                if (!t.gather) t.gather = std::make_unique<HemisphereGather>(m_resolution, 3 * m_resolution);
                const Candidate& c = cands[misses[m]];
                batch[m] = makeRecord(scene, c.si, c.n, c.footprint, key, settings, *t.gather, t.sampler);
                bar.update(1);
            });
            if (control.stopRequested()) break;
            m_cache.add(std::move(batch));
        }
        bar.finish();
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        log::info("irradiancecache: {} records ({}×{} gather rays, 4 wavelength passes each), {:.2f} MiB, {:.2f} s",
                  m_cache.size(), m_resolution, 3 * m_resolution, double(m_cache.memoryBytes()) / (1 << 20), seconds);
        return seconds;
    }

    int m_resolution;
    float m_aOverture, m_aRender = 0.4f, m_diagonal = 1.f;
    bool m_gradients, m_clampNeighbour, m_clampScreen, m_overture;
    int m_maxDepth, m_rrDepth;
    Ref<IEventStore> m_store;
    IrradianceCache m_cache;
    const Scene* m_cachedScene = nullptr;
    mutable tbb::enumerable_thread_specific<Scratch> m_scratch;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::IrradianceCacheRenderer)
