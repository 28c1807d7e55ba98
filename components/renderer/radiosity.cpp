// renderer "radiosity" — view-independent radiosity, then pictures by ray casting.
//
// First (once per scene) the scene's diffuse and emitting surfaces are meshed (nested
// `mesh`, default uniform), form factors are computed by the nested `formfactor`
// (default hemicube) and B = E + ρ F B is solved by the nested `solver` (default
// gmres) — or a solution saved earlier is loaded (load_solution), so that a
// walk-through renders many views from one solve. Then each pixel sample casts one ray
// from the camera and shows the radiance B/π of the surface it hits: interpolated from
// the vertices (Gouraud 1971) or constant over each element (shading = "constant"). The
// spectral radiosity bins are converted to XYZ exactly once per element and vertex, so
// the image has no colour noise; samples per pixel only antialias. Surfaces that are not
// meshed (specular ones, back faces, analytic shapes) are black: renderer `twopass`
// traces them. Pixels go through the shared tile loop into the film, so every film and
// filter works, and progressive passes reuse the solution.
//
// Parameters:
//   shading        string (default gouraud): gouraud | constant
//   mesh, formfactor, solver, save_solution, load_solution, history: see
//   effigi/render/radiosity_solution.hpp
//
// Reference: C. M. Goral, K. E. Torrance, D. P. Greenberg, B. Battaile, "Modeling the
// Interaction of Light Between Diffuse Surfaces", SIGGRAPH 1984; H. Gouraud, "Continuous
// Shading of Curved Surfaces", IEEE Trans. Computers 20(6), 1971.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/render/radiosity_solution.hpp"
#include "effigi/render/tile_renderer.hpp"

namespace effigi {
namespace {

class RadiosityRenderer final : public Implements<IRenderer, IRadiosityReport> {
public:
    static Schema schema() {
        Schema s("renderer", "radiosity",
                 "Radiosity: mesh, form factors and a solver once, then views by ray casting with Gouraud shading.");
        s.cite("Goral, Torrance, Greenberg & Battaile, Modeling the Interaction of Light Between Diffuse Surfaces, "
               "SIGGRAPH 1984");
        s.string("shading", "gouraud", "Display: interpolate vertex radiosities or show each element's constant value")
            .oneOf({"gouraud", "constant"});
        RadiositySolution::addParams(s);
        s.addConformance({"default", {}});
        s.addConformance({"constant shading", {{"shading", std::string("constant")}}});
        return s;
    }

    explicit RadiosityRenderer(const Properties& p)
        : m_gouraud(p.getString("shading") == "gouraud"), m_solution(p) {}

    RenderStats render(const Scene& scene, const RenderControl& control) override {
        double solveSeconds = m_solution.prepare(scene, control);
        // The solution is colour already (XYZ from its bins), so the wavelengths only
        // serve the camera; its weight is averaged over them.
        RenderStats stats = renderCameraSamples(
            scene, control, [&](const Ray& ray, const SampledWavelengths&, const SampledSpectrum& weight, ISampler&) {
                Vector3f xyz(0.f);
                SurfaceInteraction si;
                if (scene.intersect(ray, si) && m_solution.xyz(si, m_gouraud, xyz)) xyz *= weight.average();
                return xyz;
            });
        stats.seconds += solveSeconds;
        stats.interrupted = stats.interrupted || m_solution.interrupted();
        return stats;
    }

    const SolverReport& solverReport() const override { return m_solution.report(); }

private:
    bool m_gouraud;
    RadiositySolution m_solution;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::RadiosityRenderer)
