// solver "southwell" — Southwell relaxation on the full form-factor matrix: keep the
// residual vector r = E + ρ F B − B and repeatedly relax the element with the largest
// residual |r_i| (summed over bins), which zeroes r_i and passes ρ_j F_ji r_i on to
// every other element:
//
//   B_i += r_i;   r_j += ρ_j F_ji r_i (j ≠ i);   r_i = 0.       (B = 0, r = E at start)
//
// The residual is exact at every step (not a bound); the error bound (ISolver,
// ErrorBound) is computed from it. Progressive refinement is the same
// process with the choice weighted by area (largest unshot power) and form factors
// computed on demand (Gortler, Cohen & Slusallek 1994). One iteration = one relaxation.
//
// Parameters:
//   max_iterations  int (default 0 = 100 × elements)  relaxations at most
//   tolerance       float (default 1e-4, > 0)         bound of the relative error to stop at
//
// Reference: R. V. Southwell, "Relaxation Methods in Theoretical Physics", 1946;
// S. J. Gortler, M. F. Cohen, P. Slusallek, "Radiosity and Relaxation Methods", IEEE
// CG&A 14(6), 1994.
#include "effigi/core/registry.hpp"
#include "effigi/render/radiosity_solver.hpp"

#include <algorithm>
#include <cmath>

namespace effigi {
namespace {

class SouthwellSolver final : public Implements<ISolver> {
public:
    static Schema schema() {
        Schema s("solver", "southwell", "Southwell relaxation: relax the element of largest residual (full matrix).");
        s.cite("Gortler, Cohen & Slusallek, Radiosity and Relaxation Methods, IEEE CG&A 14(6), 1994");
        s.integer("max_iterations", 0, "Relaxations at most; 0: 100 times the element count").range(0, 1e12);
        s.real("tolerance", 1e-4, "Bound of the relative error of B (Σ A|B − B*| / Σ A B*) to stop at")
            .range(1e-15, 1.0);
        return s;
    }

    explicit SouthwellSolver(const Properties& p)
        : m_maxIterations(std::uint64_t(p.getInt("max_iterations"))), m_tolerance(p.getFloat("tolerance")) {}

    SolverReport solve(IMesh& mesh, const IFormFactor& ff, const RenderControl& control) override {
        RadiositySystem sys(mesh);
        std::uint64_t limit = m_maxIterations ? m_maxIterations : 100 * std::uint64_t(sys.n);
        SolverLog log("solver 'southwell'", limit, m_tolerance);
        FormFactorMatrix F(ff, sys.n, control, "solver 'southwell'");
        log.formFactorsDone();
        ErrorBound bound(sys, F);
        const int nb = sys.bins;
        std::vector<double> r = sys.emission;
        std::fill(sys.b.begin(), sys.b.end(), 0.0);
        auto magnitude = [&](std::size_t i) {
            double s = 0.0;
            for (int k = 0; k < nb; ++k) s += std::abs(r[i * nb + k]);
            return s;
        };
        std::size_t pick = 0;
        for (std::size_t i = 1; i < sys.n; ++i)
            if (magnitude(i) > magnitude(pick)) pick = i;
        std::uint64_t it = 0;
        double residual = sys.relative(r), error = bound.relative(sys, r, false);
        // The bound's inputs are kept up to date in the relaxation loop (no extra pass):
        // the residual's norms per bin and Σ A B.
        ResidualNorms norms = bound.norms(sys, r);
        double power = 0.0;
        bool interrupted = F.interrupted();
        double ri[SpectralBinning::MaxBins];
        while (!interrupted && !log.reached(residual, error) && it < limit) {
            for (int k = 0; k < nb; ++k) {
                ri[k] = r[pick * nb + k];
                sys.b[pick * nb + k] += ri[k];
                power += sys.area[pick] * ri[k];
                r[pick * nb + k] = 0.0;
            }
            // Pass the relaxed residual on, and find the next pick and the new norms.
            double norm = 0.0, best = -1.0;
            std::size_t next = pick;
            std::fill(norms.areaSum.begin(), norms.areaSum.end(), 0.0);
            std::fill(norms.weightedMax.begin(), norms.weightedMax.end(), 0.0);
            for (std::size_t j = 0; j < sys.n; ++j) {
                double f = F.at(j, pick), m = 0.0;
                for (int k = 0; k < nb; ++k) {
                    std::size_t jk = j * nb + k;
                    if (f != 0.0) r[jk] += sys.rho[jk] * f * ri[k];
                    double a = std::abs(r[jk]);
                    m += a;
                    norms.areaSum[k] += sys.area[j] * a;
                    norms.weightedMax[k] = std::max(norms.weightedMax[k], a / bound.weight(j, k));
                }
                norm += sys.area[j] * m;
                if (m > best) best = m, next = j;
            }
            pick = next;
            residual = sys.emissionNorm > 0.0 ? norm / sys.emissionNorm : 0.0;
            error = ErrorBound::relative(bound.binErrors(norms, false), power, sys.emissionNorm);
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

EFFIGI_EXPORT_COMPONENT(effigi::SouthwellSolver)
