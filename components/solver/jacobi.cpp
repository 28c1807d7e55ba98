// solver "jacobi" — Jacobi iteration on the full form-factor matrix:
//
//   B⁽ᵏ⁺¹⁾ = E + ρ F B⁽ᵏ⁾,   B⁽⁰⁾ = E,
//
// i.e. the Neumann series of (I − ρF)⁻¹ E summed one bounce per sweep: after k sweeps B
// holds light of at most k reflections. The residual reported after a sweep is the size
// of its update Δ = B⁽ᵏ⁾ − B⁽ᵏ⁻¹⁾, Σ A |Δ| / Σ A E; the true residual of the new iterate
// is ρFΔ, which is what the error bound (ISolver, ErrorBound) is computed from. Both
// shrink by about the mean reflectance per sweep: in a closed enclosure of uniform ρ and
// E the residual is ρᵏ and the relative error ρᵏ⁺¹, so a tolerance τ takes about
// ln τ / ln ρ sweeps (ten times more for each factor 10 closer to ρ = 1: use gmres
// there). Rows are computed in parallel.
//
// Parameters:
//   max_iterations  int (default 1000, >= 1)  sweeps at most
//   tolerance       float (default 1e-4, > 0) bound of the relative error to stop at
//
// Reference: M. F. Cohen, J. R. Wallace, "Radiosity and Realistic Image Synthesis", 1993,
// §5.3 (iterative solutions: Jacobi).
#include "effigi/core/registry.hpp"
#include "effigi/render/radiosity_solver.hpp"

namespace effigi {
namespace {

class JacobiSolver final : public Implements<ISolver> {
public:
    static Schema schema() {
        Schema s("solver", "jacobi", "Jacobi iteration on the full form-factor matrix (one bounce per sweep).");
        s.cite("M. F. Cohen, J. R. Wallace, Radiosity and Realistic Image Synthesis, 1993, §5.3");
        s.integer("max_iterations", 1000, "Sweeps at most; stopping earlier than the tolerance is reported")
            .range(1, 1e12);
        s.real("tolerance", 1e-4, "Bound of the relative error of B (Σ A|B − B*| / Σ A B*) to stop at")
            .range(1e-15, 1.0);
        return s;
    }

    explicit JacobiSolver(const Properties& p)
        : m_maxIterations(std::uint64_t(p.getInt("max_iterations"))), m_tolerance(p.getFloat("tolerance")) {}

    SolverReport solve(IMesh& mesh, const IFormFactor& ff, const RenderControl& control) override {
        SolverLog log("solver 'jacobi'", m_maxIterations, m_tolerance);
        RadiositySystem sys(mesh);
        FormFactorMatrix F(ff, sys.n, control, "solver 'jacobi'");
        log.formFactorsDone();
        ErrorBound bound(sys, F);
        std::vector<double> next, delta(sys.b.size());
        std::uint64_t it = 0;
        double residual = sys.emissionNorm > 0.0 ? 1.0 : 0.0, error = residual;
        bool interrupted = F.interrupted();
        while (!interrupted && !log.reached(residual, error) && it < m_maxIterations) {
            multiplyRhoF(sys, F, sys.b, next);
            for (std::size_t x = 0; x < next.size(); ++x) {
                next[x] += sys.emission[x];
                delta[x] = next[x] - sys.b[x];
            }
            sys.b.swap(next);
            residual = sys.relative(delta);
            error = bound.relative(sys, delta, true);
            log.record(++it, residual, error);
            interrupted = control.stopRequested();
        }
        sys.store(mesh);
        return log.finish(it, residual, error, interrupted);
    }

private:
    std::uint64_t m_maxIterations;
    double m_tolerance;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::JacobiSolver)
