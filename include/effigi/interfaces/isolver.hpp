#pragma once
// ISolver — solves the radiosity system on a mesh,
//
//   B_i = E_i + ρ_i Σ_j F_ij B_j     (per wavelength bin),
//
// with form factors from an IFormFactor, writing B into the mesh. Components: jacobi,
// gaussseidel, southwell (full matrix), progressive (Cohen et al. 1988, form factors on
// demand).
//
// Residual. Every solver reports the same measure, the relative residual
//
//   R = Σ_i A_i Σ_b |r_ib| / Σ_i A_i Σ_b E_ib,   r = E + ρ F B − B
//
// (or an upper bound of it: the size of the last sweep's update for Jacobi and
// Gauss–Seidel, the unshot radiosity for progressive refinement). Because reciprocity
// makes the area-weighted 1-norm of ρF at most max ρ · max row sum, the error of B is
// bounded by the residual: Σ A |B − B*| ≤ Σ A |r| / (1 − max ρ). In a closed enclosure
// of uniform ρ, where Σ A B* = Σ A E / (1 − ρ), R is a bound on the relative error of B.
// Solvers stop when R ≤ tolerance or after max_iterations; when the limit is reached
// first they say so in a warning naming the solver, the residual and the limit.
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
    double seconds = 0.0;            ///< whole solve
    double formFactorSeconds = 0.0;  ///< of which computing form factors
    std::vector<SolverStep> history;

    /// One line: converged after n iterations in t s, or not, with residual and limit.
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
