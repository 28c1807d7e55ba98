// renderer "path" — unidirectional spectral path tracing with next-event estimation.
//
// Each pixel is an integral over primary sample space, estimated by the numerical
// IIntegrator nested in the renderer (default `mean`) from the camera's sampler: EFFIGI's
// "pick and mix". A path samples four hero wavelengths, adds emission found by BSDF
// sampling and by light sampling, weighted by multiple importance sampling with the power
// heuristic (Veach & Guibas 1995), and is ended by Russian roulette after rr_depth.
// Parameters: max_depth (longest path in segments, −1 = unbounded; 1 = emitters seen
// directly, 2 = direct lighting — Mitsuba's convention), rr_depth, hide_emitters.
// Pass-through surfaces (BSDFNull lobes: null, the transparent part of mask) are not
// scattering events, as in Mitsuba 3's volpath: a null sample continues the ray straight
// on without counting a segment or playing Russian roulette, and the emission found
// beyond it is MIS-weighted with the density of the last real bounce (a null crossing
// does not change the direction, so that density and its point stay valid); shadow rays
// cross such surfaces weighted by evalNullTransmission (Scene::transmittance). Scenes
// without them take the plain occlusion test.
// Reference: Kajiya 1986, "The Rendering Equation"; Veach 1997, PhD thesis, ch. 9.
#include "mis.hpp"
#include "sampled_renderer.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/iintegrator.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/render/image_metrics.hpp"
#include "effigi/render/spectral_bins.hpp"
#include "effigi/render/tile_renderer.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/colorspace.hpp"

namespace effigi {
namespace {

using mis::powerHeuristic;

class PathTracer {
public:
    PathTracer(const Scene& scene, int maxDepth, int rrDepth, bool hideEmitters)
        : m_scene(scene), m_maxDepth(maxDepth < 0 ? std::numeric_limits<int>::max() : maxDepth),
          m_rrDepth(rrDepth), m_hideEmitters(hideEmitters) {}

    SampledSpectrum li(Ray ray, SampledWavelengths& lambda, ISampler& sampler) const {
        SampledSpectrum L(0.f), beta(1.f);
        bool specular = false;
        float prevPdf = 1.f, etaScale = 1.f;
        Point3f prevP = ray.o;
        SurfaceInteraction si;
        int nullCrossings = 0;

        for (int depth = 1;; ++depth) {  // depth = segments traced so far
            if (!m_scene.intersect(ray, si)) {
                for (const IEmitter* env : m_scene.environments()) {
                    SampledSpectrum Le = env->evalEnvironment(ray.d, lambda);
                    if (depth == 1 && m_hideEmitters) continue;
                    float w = 1.f;
                    if (depth > 1 && !specular)
                        w = powerHeuristic(prevPdf, mis::environmentHitPdf(m_scene, *env, prevP, ray.d));
                    L += beta * Le * w;
                }
                break;
            }
            if (si.emitter && !(depth == 1 && m_hideEmitters)) {
                SampledSpectrum Le = si.emitter->eval(si, lambda);
                if (!Le.isBlack()) {
                    float w = 1.f;
                    if (depth > 1 && !specular)
                        w = powerHeuristic(prevPdf, mis::emitterHitPdf(m_scene, prevP, si));
                    L += beta * Le * w;
                }
            }
            if (!si.bsdf) break;
            const IBSDF& bsdf = *si.bsdf;
            // At the last segment only a pass-through may still go on.
            const bool scatters = depth < m_maxDepth;
            if (!scatters && !bsdf.hasNull()) break;
            Vector3f wo = si.toLocal(si.wo);
            // Always draw the light-sampling dimensions so every path uses the same layout.
            float uLight = sampler.get1D();
            Point2f uLight2 = sampler.get2D();
            if (scatters && !bsdf.isPureSpecular()) L += beta * directLight(si, bsdf, wo, uLight, uLight2, lambda);

            float uc = sampler.get1D();
            Point2f u = sampler.get2D();
            std::optional<BSDFSample> bs = bsdf.sample(si, wo, uc, u, lambda, TransportMode::Radiance);
            if (!bs || bs->pdf <= 0.f || bs->f.isBlack()) break;
            if (bs->flags & BSDFNull) {
                // Straight on along the same line: not a bounce, so depth, the MIS state
                // (prevPdf, prevP, specular) and Russian roulette are left as they were.
                if (++nullCrossings > Scene::MaxNullCrossings) break;
                beta *= bs->f * (std::abs(bs->wi.z) / bs->pdf);
                ray = si.spawnRay(ray.d);
                --depth;
                continue;
            }
            if (!scatters) break;
            beta *= bs->f * (std::abs(bs->wi.z) / bs->pdf);
            specular = bs->isSpecular();
            prevPdf = bs->pdf;
            prevP = si.p;
            if (bs->isTransmission()) etaScale *= sqr(bs->eta);
            ray = si.spawnRay(si.toWorld(bs->wi));

            // Russian roulette on the throughput with the radiance scale of refraction
            // removed, so paths inside glass are not killed for being "bright".
            if (depth >= m_rrDepth) {
                float q = std::min(beta.maxValue() * etaScale, 0.95f);
                if (sampler.get1D() >= q) break;
                beta *= 1.f / q;
            }
        }
        return L;
    }

private:
    SampledSpectrum directLight(const SurfaceInteraction& si, const IBSDF& bsdf, const Vector3f& wo, float uSel,
                                const Point2f& u, const SampledWavelengths& lambda) const {
        std::optional<mis::LightSample> ls = mis::sampleLight(m_scene, si, bsdf, wo, uSel, u, lambda);
        if (!ls) return SampledSpectrum(0.f);
        SampledSpectrum f = ls->f;
        if (m_scene.hasNullBSDFs()) {
            f *= m_scene.transmittance(ls->shadow, lambda);
            if (f.isBlack()) return SampledSpectrum(0.f);
        } else if (m_scene.occluded(ls->shadow)) {
            return SampledSpectrum(0.f);
        }
        float w = ls->es.delta ? 1.f : powerHeuristic(ls->pdf, bsdf.pdf(si, wo, ls->wi, lambda, TransportMode::Radiance));
        return f * ls->es.L * (w / ls->pdf);
    }

    const Scene& m_scene;
    int m_maxDepth, m_rrDepth;
    bool m_hideEmitters;
};

class PathRenderer final : public SampledRenderer {
public:
    static Schema schema() {
        Schema s("renderer", "path", "Unidirectional spectral path tracer with next-event estimation and MIS.");
        s.cite("Veach 1997, Robust Monte Carlo Methods for Light Transport Simulation, ch. 9");
        s.integer("max_depth", -1, "Longest path in segments (-1: unbounded; 1: emitters only)").atLeast(-1);
        s.integer("rr_depth", 5, "Depth from which Russian roulette may end paths").atLeast(1);
        s.boolean("hide_emitters", false, "Do not show emitters seen directly by the camera");
        addSchedulingParams(s);
        return s;
    }

    explicit PathRenderer(const Properties& p)
        : SampledRenderer(p), m_maxDepth(int(p.getInt("max_depth"))), m_rrDepth(int(p.getInt("rr_depth"))),
          m_hideEmitters(p.getBool("hide_emitters")) {}

    /// One camera sample (ISampleRenderer): what moment and aov nest.
    SampledSpectrum sampleRadiance(const Scene& scene, const Ray& ray, SampledWavelengths& lambda,
                                   ISampler& sampler, float*) const override {
        return PathTracer(scene, m_maxDepth, m_rrDepth, m_hideEmitters).li(ray, lambda, sampler);
    }

private:
    int m_maxDepth, m_rrDepth;
    bool m_hideEmitters;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::PathRenderer)
