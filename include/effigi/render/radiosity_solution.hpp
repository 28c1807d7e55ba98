#pragma once
// RadiositySolution — what the renderers `radiosity` and `twopass` share: their nested
// mesh, form-factor and solver components (with defaults), the view-independent solve
// done once per scene (or loaded from a file, and saved to one), and fast XYZ lookups of
// the solution for display.
//
// Renderer parameters it adds (see addParams): the children `mesh` (default uniform),
// `formfactor` (default hemicube, or as the renderer says) and `solver` (default gmres), and the strings
// save_solution, load_solution and history (file names, relative to the working
// directory, "" = none). A scene exposes them to the command line with a <default>:
//   <default name="load_solution" value=""/> ... <string name="load_solution" value="$load_solution"/>
// and `effigi render scene.xml -D load_solution=room.rad`.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iformfactor.hpp"
#include "effigi/interfaces/iilluminationmap.hpp"
#include "effigi/interfaces/imesh.hpp"
#include "effigi/interfaces/isolver.hpp"
#include "effigi/render/scene.hpp"

#include <optional>
#include <string>

namespace effigi {

/// Implemented by renderers built on a RadiositySolution (radiosity, twopass): the report
/// of their last solve, whose errorBound states how far the solution may be from the
/// exact solution of its radiosity system (ISolver). conformance/renderer_suite.cpp reads it.
class IRadiosityReport : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IRadiosityReport");
    static constexpr const char* Tag = "renderer";

    /// The last solve's report (empty before the first render).
    virtual const SolverReport& solverReport() const = 0;
};

class RadiositySolution {
public:
    /// Schema entries: mesh, formfactor, solver, save_solution, load_solution, history.
    static void addParams(Schema& s);
    /// defaultFormFactor: the formfactor component used when the renderer nests none.
    explicit RadiositySolution(const Properties& props, const std::string& defaultFormFactor = "hemicube");
    /// Add light carried by specular paths to the form factors (SpecularTransfer,
    /// effigi/render/radiosity_specular.hpp): `rays` per element, up to maxDepth bounces.
    void setSpecularTransfer(int rays, int maxDepth) {
        m_specularRays = rays;
        m_specularDepth = maxDepth;
    }

    /// Build the mesh and solve (or load), then save if asked; only the first call for a
    /// scene does work. Returns the seconds it took (0 when already prepared).
    double prepare(const Scene& scene, const RenderControl& control);
    bool interrupted() const { return m_report.interrupted; }

    IMesh& mesh() const { return *m_mesh; }
    /// The solution as an illumination map (the mesh component must implement it).
    const IIlluminationMap& map() const { return *m_map; }
    const SolverReport& report() const { return m_report; }

    /// XYZ of the radiance leaving si toward si.wo: interpolated from the vertices
    /// (Gouraud) or the element's constant value; false where the mesh does not cover si.
    bool xyz(const SurfaceInteraction& si, bool gouraud, Vector3f& out) const;

private:
    void cacheXYZ();

    Ref<IMesh> m_mesh;
    Ref<IIlluminationMap> m_map;
    Ref<IFormFactor> m_formFactor;
    Ref<ISolver> m_solver;
    int m_specularRays = 0, m_specularDepth = 0;
    std::string m_save, m_load, m_history;
    SourceLocation m_saveWhere, m_loadWhere, m_historyWhere;
    const Scene* m_prepared = nullptr;
    SolverReport m_report;
    std::vector<Vector3f> m_elementXYZ, m_vertexXYZ;
};

} // namespace effigi
