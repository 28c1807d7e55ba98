#pragma once
// ISolver — solves the radiosity system on a mesh,
//
//   B_i = E_i + ρ_i Σ_j F_ij B_j     (per wavelength bin),
//
// with form factors from an IFormFactor, writing B into the mesh. Components: jacobi,
// gaussseidel, southwell, gmres (full matrix), progressive (Cohen et al. 1988, form
// factors on demand).
//
// Residual. Every solver reports the same measure, the relative residual
//
//   R = Σ_i A_i Σ_b |r_ib| / Σ_i A_i Σ_b E_ib,   r = E + ρ F B − B
//
// (or an upper bound of it: the size of the last sweep's update for Jacobi and
// Gauss–Seidel, the unshot radiosity for progressive refinement).
//
// Error bound. R alone does not bound the error of B: B* − B = (I − ρF)⁻¹ r, and
// ‖(I − ρF)⁻¹‖ grows like 1/(1 − ρ) as the spectral radius of ρF approaches 1 (at
// ρ = 0.999 a residual of 1e-4 of the emitted power allows an error of 0.1 of it). So
// every solver also reports, and stops on, a bound of the true relative error
//
//   ε = Σ_i A_i Σ_b |B_ib − B*_ib| / Σ_i A_i Σ_b B*_ib ≤ errorBound,
//
// from a norm in which ρF contracts: per bin, ‖B − B*‖ ≤ ‖r‖ / (1 − ‖ρF‖) (Neumann
// series). The norms and their contraction factors are those of ErrorBound
// (effigi/render/radiosity_solver.hpp): the area-weighted 1-norm, where ‖ρF‖ ≤ max ρ by
// reciprocity and row sums ≤ 1, and a weighted max-norm that needs neither. The
// denominator uses B* ≥ E. The bound is of the solver's B in double precision: storing
// it in the mesh as float adds ≤ 2⁻²⁴ relative, and rounding in evaluating the residual
// (~n·2⁻⁵³/(1 − ‖ρF‖) relative) is not included, so tolerances below ~1e-12 are nominal.
// Solvers stop when errorBound ≤ tolerance (where no norm contracts, errorBound is
// infinite and they fall back to R ≤ tolerance), or after max_iterations; when the limit
// comes first they say so in a warning naming the solver, the residual, the bound and
// the limit. conformance/solver_suite.cpp checks the bound against exact solutions.
#include "effigi/core/component.hpp"
#include "effigi/interfaces/irenderer.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace effigi {

class IMesh;
class IFormFactor;

/// One point of the convergence history.
struct SolverStep {
    std::uint64_t iteration = 0;  ///< sweeps (jacobi, gaussseidel) or relaxations/shots
    double seconds = 0.0;         ///< since the solve began, form factors included
    double residual = 0.0;        ///< relative residual R after this iteration
};

struct SolverReport {
    std::string solver;  ///< "solver 'jacobi'"
    bool converged = false;
    bool interrupted = false;
    std::uint64_t iterations = 0, maxIterations = 0;
    double residual = 0.0, tolerance = 0.0;
    /// Bound of the relative error of B (see above); +∞ when none could be established.
    double errorBound = 0.0;
    double seconds = 0.0;            ///< whole solve
    double formFactorSeconds = 0.0;  ///< of which computing form factors
    std::vector<SolverStep> history;

    /// One line: converged after n iterations in t s, or not, with residual, error bound
    /// and limit.
    std::string summary() const;
};

class ISolver : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("ISolver");
    static constexpr const char* Tag = "solver";

    /// Solve on a built mesh with a prepared IFormFactor; B is written to the mesh
    /// (radiosityChanged() called). control supplies threads, progress and the stop flag.
    virtual SolverReport solve(IMesh& mesh, const IFormFactor& formFactors, const RenderControl& control) = 0;
};

} // namespace effigi
