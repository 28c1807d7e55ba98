// solver "bad_residual_solver" — DELIBERATELY WRONG test plugin: Jacobi iteration that
// stops when an iterate changes little, Σ A|B⁽ᵏ⁾ − B⁽ᵏ⁻¹⁾| / Σ A B⁽ᵏ⁾ ≤ tolerance, and
// reports that relative change as its error bound.
//
// The change per sweep is not the error: what is still missing is the whole tail of the
// Neumann series, about ρ/(1 − ρ) times the last change (ISolver), so near ρ = 1 the
// solver stops far from B* while claiming to be within the tolerance. Its B is finite,
// its report truthful in every other way (iterations, history, its name), and its claim
// of convergence matches the bound it reports, so effigi-conform must fail it on the
// "honest bound" checks only: in the closed cube of ρ = 0.99 the true error is about
// 99 times the bound (tests/plugins/run_plugin_tests.cmake).
#include "effigi/core/registry.hpp"
#include "effigi/render/radiosity_solver.hpp"

namespace {
using namespace effigi;

class BadResidualSolver final : public Implements<ISolver> {
public:
    static Schema schema() {
        Schema s("solver", "bad_residual_solver", "Test plugin: Jacobi that takes the change per sweep for the error.");
        s.integer("max_iterations", 1000, "Sweeps at most").range(1, 1e12);
        s.real("tolerance", 1e-4, "Relative change per sweep to stop at (the bug: not an error bound)").range(1e-15, 1.0);
        return s;
    }

    explicit BadResidualSolver(const Properties& p)
        : m_maxIterations(std::uint64_t(p.getInt("max_iterations"))), m_tolerance(p.getFloat("tolerance")) {}

    SolverReport solve(IMesh& mesh, const IFormFactor& ff, const RenderControl& control) override {
        const std::string name = "solver 'bad_residual_solver'";
        SolverLog log(name, m_maxIterations, m_tolerance);
        RadiositySystem sys(mesh);
        FormFactorMatrix F(ff, sys.n, control, name);
        log.formFactorsDone();
        std::vector<double> next, delta(sys.b.size());
        std::uint64_t it = 0;
        double residual = sys.emissionNorm > 0.0 ? 1.0 : 0.0, change = residual;
        bool interrupted = F.interrupted();
        while (!interrupted && !log.reached(residual, change) && it < m_maxIterations) {
            multiplyRhoF(sys, F, sys.b, next);
            for (std::size_t x = 0; x < next.size(); ++x) {
                next[x] += sys.emission[x];
                delta[x] = next[x] - sys.b[x];
            }
            sys.b.swap(next);
            residual = sys.relative(delta);
            double total = sys.relative(sys.b);
            change = total > 0.0 ? residual / total : 0.0;  // the bug: taken for the error bound
            log.record(++it, residual, change);
            interrupted = control.stopRequested();
        }
        sys.store(mesh);
        return log.finish(it, residual, change, interrupted);
    }

private:
    std::uint64_t m_maxIterations;
    double m_tolerance;
};

} // namespace

EFFIGI_EXPORT_COMPONENT(BadResidualSolver)
