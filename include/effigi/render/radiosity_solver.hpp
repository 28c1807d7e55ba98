#pragma once
// Parts shared by the radiosity solvers (components/solver/*): the system in double
// precision, the full form-factor matrix, the error bound every solver stops on (see
// ISolver), and the log that records residual against iteration and time and warns when
// a solver stops short of its tolerance.
#include "effigi/interfaces/iformfactor.hpp"
#include "effigi/interfaces/imesh.hpp"
#include "effigi/interfaces/isolver.hpp"

#include <chrono>
#include <string>
#include <vector>

namespace effigi {

/// B = E + ρ F B copied out of a mesh: per element its area, per element and bin ρ, E
/// and the current B (double, so that stiff systems with ρ → 1 keep their digits).
struct RadiositySystem {
    std::size_t n = 0;
    int bins = 0;
    std::vector<double> area, rho, emission, b;
    double emissionNorm = 0.0;  ///< Σ_i A_i Σ_b E_ib, the residual's scale

    /// B starts at E.
    explicit RadiositySystem(const IMesh& mesh);
    /// Σ_i A_i Σ_b |x_ib| / emissionNorm: the relative residual of ISolver for x = r.
    double relative(const std::vector<double>& x) const;
    /// Write B into the mesh (and update its vertex values).
    void store(IMesh& mesh) const;
};

/// The N × N matrix F_ij (float, row-major), filled row by row in parallel from an
/// IFormFactor. Refuses (effigi::Error) above MaxBytes, naming the progressive solver.
class FormFactorMatrix {
public:
    static constexpr std::size_t MaxBytes = std::size_t(4) << 30;

    FormFactorMatrix(const IFormFactor& ff, std::size_t n, const RenderControl& control, const std::string& solver);
    std::size_t size() const { return m_n; }
    const float* row(std::size_t i) const { return m_f.data() + i * m_n; }
    float at(std::size_t i, std::size_t j) const { return m_f[i * m_n + j]; }
    /// acc[k] = Σ_j F_ij b[j·bins + k]: the radiosity gathered by element i (acc zeroed
    /// by the caller), as Jacobi and Gauss–Seidel sweeps need it.
    void gather(std::size_t i, const double* b, int bins, double* acc) const {
        const float* r = row(i);
        for (std::size_t j = 0; j < m_n; ++j) {
            const double f = r[j];
            if (f == 0.0) continue;
            const double* bj = b + j * std::size_t(bins);
            for (int k = 0; k < bins; ++k) acc[k] += f * bj[k];
        }
    }
    bool interrupted() const { return m_interrupted; }

private:
    std::size_t m_n = 0;
    std::vector<float> m_f;
    bool m_interrupted = false;
};

/// y = ρ ∘ (F x) for all bins (element-major, like RadiositySystem::b), rows in parallel:
/// the one matrix–vector product of Jacobi, GMRES and the error bound.
void multiplyRhoF(const RadiositySystem& sys, const FormFactorMatrix& F, const std::vector<double>& x,
                  std::vector<double>& y);

/// Per-bin sizes of a residual (or of an update) x, as ErrorBound needs them:
/// areaSum[k] = Σ_i A_i |x_ik|, weightedMax[k] = max_i |x_ik| / v_ik.
struct ResidualNorms {
    std::vector<double> areaSum, weightedMax;
};

/// A bound on the true error of an iterate B from its residual r = E + ρFB − B, valid
/// whatever the spectral radius (derivation in ISolver). Per bin k the error
/// B − B* = −(I − ρF)⁻¹ r is bounded in two norms, and the smaller bound is used:
///  - area-weighted 1-norm: ‖ρF‖₁,A = q1 = max_j Σ_i A_i ρ_i F_ij / A_j (power is
///    conserved: with reciprocity and rows summing to ≤ 1, q1 ≤ max ρ), so
///    Σ A |B − B*| ≤ Σ A |r| / (1 − q1);
///  - max-norm weighted by v > 0: if ρF v ≤ θ v elementwise, ‖ρF‖_v ≤ θ, so
///    |B_i − B*_i| ≤ v_i max_j |r_j|/v_j / (1 − θ). v is the Neumann sum
///    Σ_{l≤L} (ρF)ˡ 1 or, where that gives θ > 0.9, an approximation of (I − ρF)⁻¹ 1 by
///    GMRES (the ideal weights); θ is computed from v either way. This needs neither
///    reciprocity nor rows summing to ≤ 1 nor ρ < 1 everywhere (an open box of white
///    walls has θ < 1); for a closed enclosure of uniform ρ, θ = ρ.
/// B* ≥ E ≥ 0, so Σ A B* ≥ max(Σ A E, Σ A B − Σ A |B − B*|); the relative bound is
/// Σ_k e_k / that. It is infinite when q1 ≥ 1 and θ ≥ 1 in some bin with r ≠ 0.
class ErrorBound {
public:
    static constexpr int NeumannTerms = 3;
    /// q1 and θ computed from the matrix (NeumannTerms + 1 products and one pass, plus a
    /// rough GMRES solve in stiff systems).
    ErrorBound(const RadiositySystem& sys, const FormFactorMatrix& F);
    /// Without the matrix (progressive refinement): v = 1 and q1 = θ = max ρ per bin,
    /// which assumes reciprocity and rows summing to ≤ 1 (true of every form-factor
    /// component's columns: analytic and hemicube complete them by reciprocity).
    explicit ErrorBound(const RadiositySystem& sys);

    ResidualNorms norms(const RadiositySystem& sys, const std::vector<double>& x) const;
    /// Per-bin error bounds e_k = bound on Σ_i A_i |B_ik − B*_ik|. update = true: the
    /// norms are of the last update Δ of a Jacobi or Gauss–Seidel sweep, or of the unshot
    /// radiosity of progressive refinement, whose residual is |r| ≤ ρF|Δ| elementwise.
    std::vector<double> binErrors(const ResidualNorms& n, bool update) const;
    /// Relative bound for sys.b: Σ_k e_k / (lower bound of Σ A B*).
    double relative(const RadiositySystem& sys, const std::vector<double>& binErrors) const;
    /// The same for an iterate of total power Σ_i A_i Σ_k B_ik = power.
    static double relative(const std::vector<double>& binErrors, double power, double emissionNorm);
    double relative(const RadiositySystem& sys, const std::vector<double>& x, bool update) const {
        return relative(sys, binErrors(norms(sys, x), update));
    }
    /// max_i |B_ik − B*_ik| ≤ v_ik · this (per element; infinite when θ_k ≥ 1).
    double elementScale(const ResidualNorms& n, bool update, int k) const;

    double areaContraction(int k) const { return m_q1[k]; }
    double maxContraction(int k) const { return m_theta[k]; }
    /// v_ik (1 without a matrix).
    double weight(std::size_t i, int k) const { return m_v.empty() ? 1.0 : m_v[i * m_bins + k]; }

private:
    int m_bins = 0;
    std::vector<double> m_q1, m_theta, m_vArea;  // per bin; m_vArea = Σ_i A_i v_ik
    std::vector<double> m_v;                     // per element and bin; empty = 1
};

/// The exact solution of B = E + ρFB, per bin by Gaussian elimination with partial
/// pivoting in double (O(n³): small systems only). The reference against which tests
/// and the conformance suite measure solvers and their error bounds.
std::vector<double> solveDirect(const RadiositySystem& sys, const FormFactorMatrix& F);

/// The measure of ISolver's error bound, Σ_i A_i Σ_b |B_ib − B*_ib| / Σ_i A_i Σ_b B*_ib,
/// for the radiosity stored in the mesh against B* (element-major, like the mesh).
double relativeError(const IMesh& mesh, const std::vector<double>& exact);

/// Residual history, timing and the final report of one solve.
class SolverLog {
public:
    SolverLog(std::string solver, std::uint64_t maxIterations, double tolerance);
    /// Time spent so far counts as form-factor time.
    void formFactorsDone();
    /// Add form-factor time measured by the solver (form factors computed on demand).
    void addFormFactorSeconds(double s) { m_report.formFactorSeconds += s; }
    /// Record the residual after an iteration (every iteration up to 1000, then thinned
    /// to one entry per 1 % growth of the count); prints an info line at most once a second.
    void record(std::uint64_t iteration, double residual, double errorBound);
    double seconds() const;
    /// The stopping rule of every solver: the error bound reaches the tolerance; where no
    /// bound exists (‖ρF‖ ≥ 1 in both norms of ErrorBound) the residual does.
    bool reached(double residual, double errorBound) const;
    /// The report; logs it (info) when converged, else a warning naming solver, residual,
    /// bound and limit.
    SolverReport finish(std::uint64_t iterations, double residual, double errorBound, bool interrupted);

private:
    SolverReport m_report;
    std::chrono::steady_clock::time_point m_start, m_lastInfo;
    std::uint64_t m_nextRecord = 0;
};

} // namespace effigi
