// renderer "whitted" — classic recursive ray tracing (Whitted 1980), spectral: light
// arriving along chains of perfectly specular bounces that end on a surface lit directly
// by the emitters (paths E S* D L in Heckbert's notation), plus emitters and the
// environment seen along such chains.
//
// At each surface the camera ray (or a specular chain from it) reaches:
//  - the surface's emission, if it is an area light;
//  - direct light from every emitter through the BSDF's non-delta part (f·|cos θ|):
//    delta lights (point, spot, projector, directional) exactly, one shadow ray each;
//    area and environment lights by `emitter_samples` light samples each, averaged
//    (Whitted's point samples of a light, made unbiased for lights of finite size);
//  - then, if the BSDF has delta lobes (mirror, glass, the coating of plastic), the ray
//    goes on along one of them. Which one is left to the BSDF's own sampling: the BSDF is
//    sampled once; a delta sample continues the chain with weight f·|cos θ|/pdf, a sample
//    of a non-delta lobe ends it (that light is what direct lighting took). In expectation
//    this is the sum over the delta lobes of each lobe's weight times what it sees: the
//    branches of Whitted's ray tree, one chosen per camera sample with the BSDF's lobe
//    probabilities (glass: the Fresnel reflectance) instead of all traced. It works for every
//    BSDF, whatever lobe its `uc` selects, keeps the cost linear in the depth, and is
//    deterministic for single-lobe mirrors (conductor); glass needs a few samples per pixel.
// Nothing else: non-delta lobes are never followed (no indirect diffuse or glossy light,
// no ambient term), and shadow rays are not bent by mirrors or glass (glass casts a full
// shadow; caustics, paths L S+ D …, are absent). Pass-through surfaces (null, the
// transparent part of mask) are crossed straight on without counting a segment, and
// shadow rays cross them weighted by their transmission (Scene::transmittance), as in
// `path`.
// Depth (Mitsuba's convention for max_depth, in segments): emission counts on segments
// 1..max_depth, direct light needs one more segment (the shadow ray): max_depth 0 is
// black, 1 shows the emitters only, 2 is direct lighting of the first surface, each
// further segment one more specular bounce. −1 (default, like Mitsuba's path) is unbounded
// with a hard cap of 64 segments, which only mirror corridors and trapped light reach.
// Parameters: max_depth (int, −1), emitter_samples (int, 1: light samples per area or
// environment emitter at each shaded point), hide_emitters (emitters seen directly by the
// camera add no emission; their surface still reflects light, as in `path`), and the
// scheduling parameters of the sampled renderers (`integrator` child, default mean).
// References: T. Whitted, "An Improved Illumination Model for Shaded Display", CACM 23(6),
// 1980; A. S. Glassner (ed.), "An Introduction to Ray Tracing", Academic Press, 1989;
// pbrt-v3's WhittedIntegrator (depth in bounces; it traces both branches of glass).
#include "sampled_renderer.hpp"

#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/iemitter.hpp"

#include <cmath>

namespace effigi {
namespace {

class WhittedRenderer final : public SampledRenderer {
public:
    /// Segments of an unbounded (max_depth −1) chain.
    static constexpr int HardCap = 64;

    static Schema schema() {
        Schema s("renderer", "whitted",
                 "Whitted ray tracing: direct light at the end of specular (mirror, glass) chains.");
        s.cite("T. Whitted 1980, An Improved Illumination Model for Shaded Display, CACM 23(6); "
               "A. S. Glassner (ed.) 1989, An Introduction to Ray Tracing");
        s.integer("max_depth", -1,
                  "Longest path in segments (Mitsuba's convention: 1 = emitters only, 2 = direct light); -1: "
                  "unbounded (capped at 64)")
            .range(-1, 1 << 20);
        s.integer("emitter_samples", 1, "Light samples per area or environment emitter at each shaded point")
            .range(1, 1024);
        s.boolean("hide_emitters", false, "Do not show emitters seen directly by the camera");
        addSchedulingParams(s);
        using Params = std::vector<std::pair<std::string, PropertyValue>>;
        auto depth = [](std::int64_t d) { return Params{{"max_depth", d}}; };
        s.addConformance({"default", {}});
        s.addConformance({"max_depth 0", depth(0)});
        s.addConformance({"max_depth 1", depth(1)});
        s.addConformance({"max_depth 2", depth(2)});
        s.addConformance({"max_depth 100", depth(100)});
        s.addConformance({"hide_emitters", {{"hide_emitters", true}}});
        s.addConformance({"emitter_samples 4", {{"emitter_samples", std::int64_t(4)}}});
        return s;
    }

    explicit WhittedRenderer(const Properties& p)
        : SampledRenderer(p), m_emitterSamples(int(p.getInt("emitter_samples"))),
          m_hideEmitters(p.getBool("hide_emitters")) {
        const std::int64_t d = p.getInt("max_depth");
        m_maxDepth = d < 0 ? HardCap : int(d);
    }

    bool rendersMotion() const override { return true; }

    SampledSpectrum sampleRadiance(const Scene& scene, const Ray& cameraRay, SampledWavelengths& lambda,
                                   ISampler& sampler, float*) const override {
        SampledSpectrum L(0.f), beta(1.f);
        Ray ray = cameraRay;
        int depth = 1, nullCrossings = 0;  // segments traced, `ray` included
        SurfaceInteraction si;
        for (;;) {
            // Emission counts on segments 1..max_depth (hidden on the camera's own).
            const bool emits = depth <= m_maxDepth && !(depth == 1 && m_hideEmitters);
            if (!scene.intersect(ray, si)) {
                if (emits)
                    for (const IEmitter* env : scene.environments()) L += beta * env->evalEnvironment(ray.d, lambda);
                break;
            }
            if (emits && si.emitter) L += beta * si.emitter->eval(si, lambda);
            if (!si.bsdf) break;
            const IBSDF& bsdf = *si.bsdf;
            // At the last segment only a pass-through may still go on.
            const bool scatters = depth < m_maxDepth;
            if (!scatters && !bsdf.hasNull()) break;
            const Vector3f wo = si.toLocal(si.wo);
            if (scatters && !bsdf.isPureSpecular()) L += beta * directLight(scene, si, bsdf, wo, lambda, sampler);

            const float uc = sampler.get1D();
            const Point2f u = sampler.get2D();
            std::optional<BSDFSample> bs = bsdf.sample(si, wo, uc, u, lambda, TransportMode::Radiance);
            if (!bs || !(bs->pdf > 0.f) || bs->f.isBlack()) break;
            const bool pass = bs->flags & BSDFNull;
            // A non-delta lobe ends the chain: its light was gathered by directLight.
            if (pass ? ++nullCrossings > Scene::MaxNullCrossings : !(scatters && bs->isSpecular())) break;
            beta *= bs->f * (std::abs(bs->wi.z) / bs->pdf);
            if (beta.isBlack()) break;
            // A pass-through continues along the same line and is not a segment.
            ray = si.spawnRay(pass ? ray.d : si.toWorld(bs->wi));
            if (!pass) ++depth;
        }
        return L;
    }

private:
    /// Light from every emitter at si through the BSDF's non-delta part: delta emitters by
    /// their one sample, the others by m_emitterSamples samples, averaged. Every emitter
    /// draws m_emitterSamples 2D samples, used or not, so the sample layout is fixed.
    SampledSpectrum directLight(const Scene& scene, const SurfaceInteraction& si, const IBSDF& bsdf,
                                const Vector3f& wo, const SampledWavelengths& lambda, ISampler& sampler) const {
        SampledSpectrum Ld(0.f);
        for (const IEmitter* emitter : scene.emitters()) {
            const int n = emitter->isDelta() ? 1 : m_emitterSamples;
            for (int i = 0; i < m_emitterSamples; ++i) {
                const Point2f u = sampler.get2D();
                if (i >= n) continue;
                EmitterSample es = emitter->sampleDirect(si.p, u, lambda);
                if (!(es.pdf > 0.f) || es.L.isBlack()) continue;
                const Vector3f wi = si.toLocal(es.wi);
                SampledSpectrum f = bsdf.f(si, wo, wi, lambda, TransportMode::Radiance) * std::abs(wi.z);
                if (f.isBlack()) continue;
                const Ray shadow = std::isinf(es.dist) ? si.spawnRay(es.wi) : si.spawnRayTo(es.p);
                SampledSpectrum T = scene.hasNullBSDFs() ? scene.transmittance(shadow, lambda)
                                                         : SampledSpectrum(scene.occluded(shadow) ? 0.f : 1.f);
                Ld += f * es.L * T * (1.f / (es.pdf * float(n)));
            }
        }
        return Ld;
    }

    int m_maxDepth, m_emitterSamples;
    bool m_hideEmitters;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::WhittedRenderer)
