#pragma once
// Parts shared by the radiosity solvers (components/solver/*): the system in double
// precision, the full form-factor matrix, and the log that records residual against
// iteration and time and warns when a solver stops short of its tolerance.
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
    void record(std::uint64_t iteration, double residual);
    double seconds() const;
    /// The report; logs a warning naming solver, residual and limit unless converged.
    SolverReport finish(std::uint64_t iterations, double residual, bool interrupted);

private:
    SolverReport m_report;
    std::chrono::steady_clock::time_point m_start, m_lastInfo;
    std::uint64_t m_nextRecord = 0;
};

} // namespace effigi
