// The view-independent part of the radiosity renderers (effigi/render/radiosity_solution.hpp).
#include "effigi/render/radiosity_solution.hpp"

#include "effigi/core/log.hpp"
#include "effigi/render/radiosity_mesh.hpp"
#include "effigi/render/radiosity_specular.hpp"
#include "effigi/render/spectral_bins.hpp"

#include <tbb/global_control.h>

#include <chrono>
#include <cstdio>
#include <fstream>

namespace effigi {

namespace {

template <typename I> Ref<I> childOrDefault(const Properties& p, const std::string& tag, const std::string& name) {
    Ref<I> r = p.get<I>(tag);
    if (r) return r;
    Properties d(tag, name, p.where());
    return query<I>(Registry::instance().create(tag, name, d));
}

} // namespace

void RadiositySolution::addParams(Schema& s) {
    s.child("mesh", "mesh", "Elements carrying the solution (default: uniform)");
    s.child("formfactor", "formfactor", "Form-factor method (default: hemicube; twopass: analytic)");
    s.child("solver", "solver", "Solver of B = E + ρFB (default: gmres)");
    s.string("save_solution", "", "Write the solved radiosities to this file (relative to the working directory)");
    s.string("load_solution", "", "Read radiosities saved by save_solution instead of solving");
    s.string("history", "", "Write the solver's residual against iteration and time to this CSV file");
}

RadiositySolution::RadiositySolution(const Properties& p, const std::string& defaultFormFactor)
    : m_mesh(childOrDefault<IMesh>(p, "mesh", "uniform")),
      m_formFactor(childOrDefault<IFormFactor>(p, "formfactor", defaultFormFactor)),
      m_solver(childOrDefault<ISolver>(p, "solver", "gmres")), m_save(p.getString("save_solution")),
      m_load(p.getString("load_solution")), m_history(p.getString("history")),
      m_saveWhere(p.whereOf("save_solution")), m_loadWhere(p.whereOf("load_solution")),
      m_historyWhere(p.whereOf("history")) {
    m_map = query<IIlluminationMap>(Ref<IComponent>(m_mesh));
    if (!m_map)
        failAt(p.whereOf("mesh"), "{}: mesh {} is not an illumination map, which the renderer needs", p.describe(),
               m_mesh->typeName());
}

double RadiositySolution::prepare(const Scene& scene, const RenderControl& control) {
    if (m_prepared == &scene) return 0.0;
    auto start = std::chrono::steady_clock::now();
    std::unique_ptr<tbb::global_control> limit;
    if (control.threads > 0)
        limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      std::size_t(control.threads));
    if (!scene.environments().empty())
        log::warn("radiosity: environment emitters are not part of the radiosity solution");
    for (const IEmitter* e : scene.emitters())
        if (!(e->flags() & EmitterSurface) && !e->isInfinite())
            log::warn("radiosity: {} is not an area emitter and is not part of the solution", e->typeName());
    m_mesh->build(scene.shapes());
    double meshSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!m_load.empty()) {
        try {
            loadRadiositySolution(*m_mesh, m_load);
        } catch (const Error& e) {
            throw Error(m_loadWhere, e.what());
        }
        m_report = SolverReport{};
        m_report.solver = "loaded from " + m_load;
        m_report.converged = true;
    } else {
        FormFactorContext ctx;
        ctx.mesh = m_mesh.get();
        ctx.shapes = scene.shapes();
        ctx.visibility = &scene.accelerator();
        ctx.seed = control.seed;
        Ref<IFormFactor> ff = m_formFactor;
        if (m_specularRays > 0) ff = std::make_shared<SpecularTransfer>(m_formFactor, m_specularRays, m_specularDepth);
        ff->prepare(ctx);
        m_report = m_solver->solve(*m_mesh, *ff, control);
    }
    if (!m_save.empty() && !m_report.interrupted) {
        try {
            saveRadiositySolution(*m_mesh, m_save);
        } catch (const Error& e) {
            throw Error(m_saveWhere, e.what());
        }
    }
    if (!m_history.empty()) {
        std::ofstream h(m_history);
        if (!h) failAt(m_historyWhere, "cannot write solver history {}", m_history);
        h << "iteration,seconds,residual\n";
        for (const SolverStep& s : m_report.history) h << s.iteration << ',' << s.seconds << ',' << s.residual << '\n';
    }
    cacheXYZ();
    m_prepared = &scene;
    double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::string line = fmt::format("radiosity: {} elements, {} bins, mesh {:.2f} s; {}; {:.2f} s in all",
                                   m_mesh->elementCount(), m_mesh->bins().count(), meshSeconds,
                                   m_load.empty() ? m_report.summary() : m_report.solver, seconds);
    if (control.progress) std::fprintf(stderr, "%s\n", line.c_str());
    else log::info("{}", line);
    return seconds;
}

void RadiositySolution::cacheXYZ() {
    const SpectralBinning& bins = m_mesh->bins();
    const int nb = bins.count();
    std::vector<double> edges(std::size_t(nb) + 1);
    for (int b = 0; b <= nb; ++b) edges[b] = bins.edge(b);
    std::vector<Vector3f> w = spectral_exr::xyzWeights(edges);  // XYZ = Σ_b L_b · w_b
    auto toXYZ = [&](const float* B) {
        Vector3f xyz(0.f);
        for (int b = 0; b < nb; ++b) xyz += (B[b] * InvPi) * w[b];  // L = B / π
        return xyz;
    };
    std::span<const float> eb = m_mesh->radiosity(), vb = m_mesh->vertexRadiosity();
    m_elementXYZ.resize(m_mesh->elementCount());
    for (std::size_t i = 0; i < m_elementXYZ.size(); ++i) m_elementXYZ[i] = toXYZ(&eb[i * nb]);
    m_vertexXYZ.resize(m_mesh->vertices().size());
    for (std::size_t v = 0; v < m_vertexXYZ.size(); ++v) m_vertexXYZ[v] = toXYZ(&vb[v * nb]);
}

bool RadiositySolution::xyz(const SurfaceInteraction& si, bool gouraud, Vector3f& out) const {
    if (!(dot(si.n, si.wo) > 0.f)) return false;  // elements are one-sided
    std::optional<MeshPoint> p = m_mesh->locate(si);
    if (!p) return false;
    if (!gouraud) {
        out = m_elementXYZ[p->element];
        return true;
    }
    const MeshElement& e = m_mesh->elements()[p->element];
    out = Vector3f(0.f);
    for (int k = 0; k < e.corners(); ++k) out += p->weights[k] * m_vertexXYZ[e.vertices[k]];
    return true;
}

} // namespace effigi
