// renderer "direct" — direct illumination: light arriving at the first surface the camera
// sees straight from an emitter, and emitters seen directly.
//
// At the first hit, `emitter_samples` light samples and `bsdf_samples` BSDF samples are
// taken and combined by multiple importance sampling with the power heuristic, each
// technique's density scaled by its share of the samples (Veach & Guibas 1995, the
// "multi-sample model"; Veach 1997, sec. 9.2.4). Emitter sampling is skipped on purely
// specular surfaces (it cannot hit a delta lobe); BSDF samples that hit an emitter or
// leave the scene into an environment add its radiance. Like Mitsuba 3's `direct`, it
// draws the camera ray, wavelengths and film position from the pixel's integral, which
// the nested IIntegrator (default `mean`) estimates.
// Parameters (Mitsuba 3's): shading_samples (sets both counts), emitter_samples,
// bsdf_samples, hide_emitters (emitters seen by the camera are passed through, so what is
// behind them shows).
// Reference: E. Veach, L. Guibas, "Optimally Combining Sampling Techniques for Monte Carlo
// Rendering", SIGGRAPH 1995; Mitsuba 3, src/integrators/direct.cpp (semantics).
#include "mis.hpp"
#include "sampled_renderer.hpp"

namespace effigi {
namespace {

using mis::powerHeuristic;

class DirectRenderer final : public SampledRenderer {
public:
    static Schema schema() {
        Schema s("renderer", "direct", "Direct illumination: emitter and BSDF samples combined by MIS.");
        s.cite("Veach & Guibas 1995, Optimally Combining Sampling Techniques for Monte Carlo Rendering");
        s.integer("shading_samples", 1, "Sets both emitter_samples and bsdf_samples").range(0, 1024);
        s.integer("emitter_samples", 1, "Emitter samples per camera sample (default: shading_samples)")
            .range(0, 1024);
        s.integer("bsdf_samples", 1, "BSDF samples per camera sample (default: shading_samples)").range(0, 1024);
        s.boolean("hide_emitters", false, "Do not show emitters seen directly by the camera");
        addSchedulingParams(s);
        s.addConformance({"default", {}});
        auto counts = [](std::int64_t emitter, std::int64_t bsdf) {
            using Params = std::vector<std::pair<std::string, PropertyValue>>;
            return Params{{"emitter_samples", emitter}, {"bsdf_samples", bsdf}};
        };
        s.addConformance({"emitter samples only", counts(1, 0)});
        s.addConformance({"bsdf samples only", counts(0, 1)});
        s.addConformance({"shading_samples 4", {{"shading_samples", std::int64_t(4)}}});
        return s;
    }

    explicit DirectRenderer(const Properties& p)
        : SampledRenderer(p), m_hideEmitters(p.getBool("hide_emitters")) {
        auto given = [&](const char* name) { return !p.find(name)->fromDefault; };
        if (given("shading_samples") && (given("emitter_samples") || given("bsdf_samples")))
            failAt(p.whereOf("shading_samples"),
                   "renderer 'direct': give either 'shading_samples' or 'emitter_samples'/'bsdf_samples', not both");
        const int shading = int(p.getInt("shading_samples"));
        m_emitterSamples = given("emitter_samples") ? int(p.getInt("emitter_samples")) : shading;
        m_bsdfSamples = given("bsdf_samples") ? int(p.getInt("bsdf_samples")) : shading;
        if (m_emitterSamples + m_bsdfSamples == 0)
            failAt(p.where(), "renderer 'direct': needs at least one emitter or BSDF sample");
        const float sum = float(m_emitterSamples + m_bsdfSamples);
        m_fracEmitter = float(m_emitterSamples) / sum;
        m_fracBsdf = float(m_bsdfSamples) / sum;
    }

    MediaSupport mediaSupport() const override { return MediaSupport::Ignores; }  // as Mitsuba's direct
    bool rendersMotion() const override { return true; }

    SampledSpectrum sampleRadiance(const Scene& scene, const Ray& ray, SampledWavelengths& lambda,
                                   ISampler& sampler, float*) const override {
        SurfaceInteraction si;
        bool hit = scene.intersect(ray, si);
        // Hidden emitters are stepped through (Mitsuba skips area emitters on the camera
        // ray); the bound keeps stacked coplanar emitters from looping forever.
        for (int k = 0; m_hideEmitters && hit && si.emitter && k < 16; ++k)
            hit = scene.intersect(si.spawnRay(ray.d), si);
        SampledSpectrum L(0.f);
        if (!hit) {
            if (!m_hideEmitters)
                for (const IEmitter* env : scene.environments()) L += env->evalEnvironment(ray.d, lambda);
            return L;
        }
        if (!m_hideEmitters && si.emitter) L += si.emitter->eval(si, lambda);
        if (!si.bsdf) return L;
        const IBSDF& bsdf = *si.bsdf;
        const Vector3f wo = si.toLocal(si.wo);
        // Every sample draws the same dimensions whether or not it is used.
        for (int i = 0; i < m_emitterSamples; ++i) {
            float uSel = sampler.get1D();
            Point2f u = sampler.get2D();
            if (!bsdf.isPureSpecular()) L += emitterSample(scene, si, bsdf, wo, uSel, u, lambda);
        }
        for (int i = 0; i < m_bsdfSamples; ++i) {
            float uc = sampler.get1D();
            Point2f u = sampler.get2D();
            L += bsdfSample(scene, si, bsdf, wo, uc, u, lambda);
        }
        return L;
    }

private:
    SampledSpectrum emitterSample(const Scene& scene, const SurfaceInteraction& si, const IBSDF& bsdf,
                                  const Vector3f& wo, float uSel, const Point2f& u,
                                  const SampledWavelengths& lambda) const {
        std::optional<mis::LightSample> ls = mis::sampleLight(scene, si, bsdf, wo, uSel, u, lambda);
        if (!ls || scene.occluded(ls->shadow)) return SampledSpectrum(0.f);
        // A delta emitter cannot be found by BSDF sampling: the light sample takes it all.
        // (Mitsuba 3 omits the 1/emitter_samples here, multiplying point lights by the
        // sample count; effigi averages, which is what the estimator needs.)
        float w = 1.f;
        if (!ls->es.delta)
            w = powerHeuristic(ls->pdf * m_fracEmitter,
                               bsdf.pdf(si, wo, ls->wi, lambda, TransportMode::Radiance) * m_fracBsdf);
        return ls->f * ls->es.L * (w / (ls->pdf * float(m_emitterSamples)));
    }

    SampledSpectrum bsdfSample(const Scene& scene, const SurfaceInteraction& si, const IBSDF& bsdf,
                               const Vector3f& wo, float uc, const Point2f& u, SampledWavelengths& lambda) const {
        std::optional<BSDFSample> bs = bsdf.sample(si, wo, uc, u, lambda, TransportMode::Radiance);
        if (!bs || !(bs->pdf > 0.f) || bs->f.isBlack()) return SampledSpectrum(0.f);
        const SampledSpectrum beta = bs->f * (std::abs(bs->wi.z) / (bs->pdf * float(m_bsdfSamples)));
        const Vector3f d = si.toWorld(bs->wi);
        SurfaceInteraction hit;
        SampledSpectrum L(0.f);
        // A specular lobe cannot be found by emitter sampling: its density there is 0.
        if (scene.intersect(si.spawnRay(d), hit)) {
            if (!hit.emitter) return L;
            SampledSpectrum Le = hit.emitter->eval(hit, lambda);
            float pdfE = bs->isSpecular() ? 0.f : mis::emitterHitPdf(scene, si.p, hit);
            L += beta * Le * powerHeuristic(bs->pdf * m_fracBsdf, pdfE * m_fracEmitter);
        } else {
            for (const IEmitter* env : scene.environments()) {
                SampledSpectrum Le = env->evalEnvironment(d, lambda);
                float pdfE = bs->isSpecular() ? 0.f : mis::environmentHitPdf(scene, *env, si.p, d);
                L += beta * Le * powerHeuristic(bs->pdf * m_fracBsdf, pdfE * m_fracEmitter);
            }
        }
        return L;
    }

    int m_emitterSamples = 1, m_bsdfSamples = 1;
    float m_fracEmitter = 0.5f, m_fracBsdf = 0.5f;
    bool m_hideEmitters;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::DirectRenderer)
