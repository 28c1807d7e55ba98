// renderer "twopass" — radiosity for the diffuse light, ray tracing for the specular.
//
// First pass (view-independent, once per scene): the radiosity solution of the diffuse
// and emitting surfaces, exactly as renderer `radiosity` computes it (nested mesh,
// formfactor — default analytic — and solver; save_solution / load_solution), with the
// light that mirrors and glass carry between diffuse surfaces added as extended form
// factors (Sillion & Puech 1989; specular_rays per element, 0 = specular surfaces are
// black occluders in this pass).
// Second pass (per view): from the camera, rays follow specular reflection and
// refraction (delta BSDF lobes, sampled at the path's wavelengths so glass disperses)
// until they reach a surface the solution covers; there the solution — through its
// IIlluminationMap interface — gives the diffuse radiance, Gouraud-interpolated. So a
// mirror shows the radiosity-lit room and a glass sphere refracts it (Wallace, Cohen &
// Greenberg 1987: diffuse from the preprocess, specular from the view pass).
//
// Parameters:
//   max_depth      int (default 8, >= 1)    specular bounces followed, in both passes
//   specular_rays  int (default 64, >= 0)   rays per element for the extended form factors
//   mesh, formfactor, solver, save_solution, load_solution, history: see
//   effigi/render/radiosity_solution.hpp
//
// Limitations: glossy lobes are neither traced nor meshed exactly (a surface with a
// diffuse or glossy lobe is meshed with its albedo); light reaching the camera by
// diffuse → specular → diffuse paths is in the solution only when specular_rays > 0.
//
// References: J. R. Wallace, M. F. Cohen, D. P. Greenberg, "A Two-Pass Solution to the
// Rendering Equation: A Synthesis of Ray Tracing and Radiosity Methods", SIGGRAPH 1987;
// F. Sillion, C. Puech, "A General Two-Pass Method Integrating Specular and Diffuse
// Reflection", SIGGRAPH 1989.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/render/radiosity_solution.hpp"
#include "effigi/render/tile_renderer.hpp"
#include "effigi/spectral/cie.hpp"

namespace effigi {
namespace {

class TwoPassRenderer final : public Implements<IRenderer, IRadiosityReport> {
public:
    static Schema schema() {
        Schema s("renderer", "twopass",
                 "Two-pass: radiosity for diffuse light (with extended form factors through specular surfaces), "
                 "ray tracing for specular reflection and refraction.");
        s.cite("Wallace, Cohen & Greenberg, A Two-Pass Solution to the Rendering Equation, SIGGRAPH 1987; "
               "Sillion & Puech, SIGGRAPH 1989");
        s.integer("max_depth", 8, "Specular bounces followed per path (both passes)").range(1, 1000);
        s.integer("specular_rays", 64, "Rays per element for form factors through specular surfaces (0: none)")
            .range(0, 1e6);
        RadiositySolution::addParams(s);
        return s;
    }

    explicit TwoPassRenderer(const Properties& p) : m_maxDepth(int(p.getInt("max_depth"))), m_solution(p, "analytic") {
        m_solution.setSpecularTransfer(int(p.getInt("specular_rays")), m_maxDepth);
    }

    RenderStats render(const Scene& scene, const RenderControl& control) override {
        double solveSeconds = m_solution.prepare(scene, control);
        RenderStats stats = renderCameraSamples(
            scene, control,
            [&](const Ray& ray, SampledWavelengths& lambda, const SampledSpectrum& weight, ISampler& sampler) {
                // trace() may terminate secondary wavelengths: convert after it returns.
                const SampledSpectrum L = weight * trace(scene, ray, lambda, sampler);
                return cie::toXYZ(L, lambda);
            });
        stats.seconds += solveSeconds;
        stats.interrupted = stats.interrupted || m_solution.interrupted();
        return stats;
    }

    const SolverReport& solverReport() const override { return m_solution.report(); }

private:
    /// The second pass: follow delta lobes until the solution covers the surface.
    SampledSpectrum trace(const Scene& scene, Ray ray, SampledWavelengths& lambda, ISampler& sampler) const {
        const IIlluminationMap& map = m_solution.map();
        SampledSpectrum beta(1.f);
        SurfaceInteraction si;
        for (int depth = 0; depth <= m_maxDepth; ++depth) {
            if (!scene.intersect(ray, si)) {
                SampledSpectrum L(0.f);
                for (const IEmitter* env : scene.environments()) L += env->evalEnvironment(ray.d, lambda);
                return beta * L;
            }
            if (map.covers(si)) return beta * map.radiance(si, lambda);
            const IBSDF* bsdf = si.bsdf;
            // Not in the solution and not specular (a back face, an unmeshed shape): its
            // own emission if it has any, else black.
            if (!bsdf || !bsdf->hasSpecular() || depth == m_maxDepth)
                return si.emitter ? beta * si.emitter->eval(si, lambda) : SampledSpectrum(0.f);
            float uc = sampler.get1D();
            Point2f u = sampler.get2D();
            std::optional<BSDFSample> bs = bsdf->sample(si, si.toLocal(si.wo), uc, u, lambda, TransportMode::Radiance);
            if (!bs || !bs->isSpecular() || !(bs->pdf > 0.f)) break;
            beta *= bs->f * (std::abs(bs->wi.z) / bs->pdf);
            ray = si.spawnRay(si.toWorld(bs->wi));
        }
        return SampledSpectrum(0.f);
    }

    int m_maxDepth;
    RadiositySolution m_solution;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::TwoPassRenderer)
