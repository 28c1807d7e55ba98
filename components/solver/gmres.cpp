// solver "gmres" — restarted GMRES on the full form-factor matrix, for stiff scenes
// (reflectance near 1), where Jacobi and Gauss–Seidel need sweeps in proportion to
// 1/(1 − ρ) (ten times more for each factor 10 closer to ρ = 1). The default solver of
// the renderers `radiosity` and `twopass`; the iteration itself is GmresCycle
// (effigi/render/radiosity_gmres.hpp), which ErrorBound shares.
//
// Each bin's system M B = E, M = I − ρF, is solved by GMRES (Saad & Schultz 1986): after
// j matrix–vector products B is the point of B₀ + span{r₀, M r₀, …, M^{j−1} r₀} of least
// residual. A closed room's stiffness sits in few eigenvalues (1 − ρλ for the largest
// eigenvalues λ ≈ 1 of F, the nearly uniform modes), which a Krylov space captures in a
// few steps, so the count hardly grows as ρ → 1.
//
// Inner product. The residual is measured in ⟨x, y⟩ = Σ_i w_i x_i y_i with w_i = A_i/ρ_i
// (A_i where ρ_i = 0; those rows are solved by B = E from the start and stay so). Why:
// reciprocity, A_i F_ij = A_j F_ji, makes D M = diag(A/ρ) − diag(A) F symmetric for
// D = diag(A/ρ), and, as rows sum to ≤ 1 ≤ 1/ρ_i, diagonally dominant, hence positive
// (semi-)definite by Gershgorin. So M is self-adjoint and positive in this inner
// product: the Arnoldi matrix is tridiagonal and GMRES is MINRES on the symmetrised
// system D^½ M D^-½ (Paige & Saunders 1975), the short-recurrence case for which
// conjugate gradients were designed — but full orthogonalisation keeps it correct where
// the form factors are not reciprocal (the hemi-cube's rows, specular transfer), where
// CG on the symmetrised system would solve a different system or break down.
//
// Stopping. Within a cycle the least-squares residual ‖r‖_w bounds the norms the error
// bound needs (Cauchy–Schwarz: Σ A|r| ≤ (Σ A ρ)^½ ‖r‖_w, max |r_i|/v_i ≤
// max 1/(v_i √w_i) ‖r‖_w); when that estimate reaches the tolerance, or after `restart`
// steps, B is updated, clamped to B ≥ E (B* ≥ E, so clamping only moves B toward B*),
// and the true residual E + ρFB − B is computed (one more product) and the error bound
// (ISolver, ErrorBound) taken from it. The solve ends when that bound is ≤ tolerance;
// otherwise GMRES restarts from the new B. One iteration = one Arnoldi step (one
// product with the matrix for all bins together).
//
// Parameters:
//   max_iterations  int (default 1000, >= 1)   Arnoldi steps at most
//   tolerance       float (default 1e-4, > 0)  bound of the relative error to stop at
//   restart         int (default 30, 1..1000)  Krylov vectors per cycle; memory is
//                                              (restart + 1) × elements × bins doubles
//
// References: Y. Saad, M. H. Schultz, "GMRES: A Generalized Minimal Residual Algorithm
// for Solving Nonsymmetric Linear Systems", SIAM J. Sci. Stat. Comput. 7(3), 1986;
// C. C. Paige, M. A. Saunders, "Solution of Sparse Indefinite Systems of Linear
// Equations", SIAM J. Numer. Anal. 12(4), 1975; M. F. Cohen, J. R. Wallace, "Radiosity
// and Realistic Image Synthesis", 1993 (form-factor reciprocity, iterative solutions).
#include "effigi/core/registry.hpp"
#include "effigi/render/radiosity_gmres.hpp"

#include <algorithm>
#include <cmath>

namespace effigi {
namespace {

class GmresSolver final : public Implements<ISolver> {
public:
    static Schema schema() {
        Schema s("solver", "gmres",
                 "Restarted GMRES on the full form-factor matrix: few iterations even as reflectance approaches 1.");
        s.cite("Y. Saad, M. H. Schultz, GMRES, SIAM J. Sci. Stat. Comput. 7(3), 1986");
        s.integer("max_iterations", 1000, "Arnoldi steps (matrix products) at most; stopping short is reported")
            .range(1, 1e12);
        s.real("tolerance", 1e-4, "Bound of the relative error of B (Σ A|B − B*| / Σ A B*) to stop at")
            .range(1e-15, 1.0);
        s.integer("restart", 30, "Krylov vectors kept per cycle before restarting").range(1, 1000);
        s.addConformance({"default", {}});
        s.addConformance({"restart 1", {{"restart", std::int64_t(1)}}});
        s.addConformance({"restart 1000", {{"restart", std::int64_t(1000)}}});
        s.addConformance({"tolerance 1e-15", {{"tolerance", 1e-15}}});
        s.addConformance({"tolerance 1", {{"tolerance", 1.0}}});
        s.addConformance({"one iteration", {{"max_iterations", std::int64_t(1)}}});
        return s;
    }

    explicit GmresSolver(const Properties& p)
        : m_maxIterations(std::uint64_t(p.getInt("max_iterations"))), m_tolerance(p.getFloat("tolerance")),
          m_restart(int(p.getInt("restart"))) {}

    SolverReport solve(IMesh& mesh, const IFormFactor& ff, const RenderControl& control) override {
        SolverLog log("solver 'gmres'", m_maxIterations, m_tolerance);
        RadiositySystem sys(mesh);
        FormFactorMatrix F(ff, sys.n, control, "solver 'gmres'");
        log.formFactorsDone();
        ErrorBound bound(sys, F);
        GmresCycle c(sys, F, m_restart);
        // ‖r‖_w → the norms of ErrorBound, by Cauchy–Schwarz (see the doc block).
        const int nb = sys.bins;
        std::vector<double> toArea(nb, 0.0), toMax(nb, 0.0);
        for (std::size_t i = 0; i < sys.n; ++i)
            for (int k = 0; k < nb; ++k) {
                double w = c.weight(i, k);
                if (!(w > 0.0)) continue;  // zero-area element: weighs nothing in Σ A|r|
                toArea[k] += sys.area[i] * sys.area[i] / w;
                toMax[k] = std::max(toMax[k], 1.0 / (bound.weight(i, k) * std::sqrt(w)));
            }
        for (double& t : toArea) t = std::sqrt(t);
        auto estimate = [&](int j) {
            ResidualNorms n{std::vector<double>(nb), std::vector<double>(nb)};
            double area = 0.0;
            for (int k = 0; k < nb; ++k) {
                double rw = c.residualNorm(j, k);
                n.areaSum[k] = toArea[k] * rw;
                n.weightedMax[k] = toMax[k] * rw;
                area += n.areaSum[k];
            }
            double residual = sys.emissionNorm > 0.0 ? area / sys.emissionNorm : 0.0;
            return std::pair{residual, ErrorBound::relative(bound.binErrors(n, false), c.power(j), sys.emissionNorm)};
        };

        std::vector<double> r;
        c.residual(r);
        double residual = sys.relative(r), error = bound.relative(sys, r, false);
        std::uint64_t it = 0;
        bool interrupted = F.interrupted();
        while (!interrupted && !log.reached(residual, error) && it < m_maxIterations) {
            c.start(r);
            int j = 0;
            while (j < m_restart && it < m_maxIterations && c.active()) {
                c.step(j++);
                auto [estimatedResidual, estimatedError] = estimate(j);
                log.record(++it, estimatedResidual, estimatedError);
                if (log.reached(estimatedResidual, estimatedError)) break;
                if ((interrupted = control.stopRequested())) break;
            }
            if (j == 0) break;  // every bin broke down (singular): nothing more to gain
            c.update(j);
            c.residual(r);
            residual = sys.relative(r);
            error = bound.relative(sys, r, false);
        }
        sys.store(mesh);
        return log.finish(it, residual, error, interrupted);
    }

private:
    std::uint64_t m_maxIterations;
    double m_tolerance;
    int m_restart;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::GmresSolver)
