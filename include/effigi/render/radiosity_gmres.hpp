#pragma once
// Restarted GMRES (Saad & Schultz 1986) on the radiosity system (I − ρF) B = E of a
// RadiositySystem, every bin its own Krylov space, all bins sharing each product with F.
// The inner product is ⟨x, y⟩ = Σ_i w_i x_i y_i with w_i = A_i/ρ_i (A_i where ρ_i = 0),
// in which I − ρF is self-adjoint when the form factors are reciprocal (derivation in
// components/solver/gmres.cpp). Used by solver `gmres` and by ErrorBound, which solves
// (I − ρF) v = 1 for the weights of its max-norm.
#include "effigi/render/radiosity_solver.hpp"

#include <vector>

namespace effigi {

class GmresCycle {
public:
    /// Works on sys.b (the iterate) with right-hand side sys.emission.
    GmresCycle(RadiositySystem& sys, const FormFactorMatrix& F, int restart);

    int restart() const { return m_restart; }
    double weight(std::size_t i, int k) const { return m_w[i * m_bins + k]; }
    /// r = E + ρFB − B.
    void residual(std::vector<double>& r) const;
    /// Begin a cycle at the current B, whose residual is r.
    void start(const std::vector<double>& r);
    /// Whether some bin can still improve (the others broke down: solved exactly).
    bool active() const;
    /// Arnoldi step j = 0, 1, …, restart − 1 (modified Gram–Schmidt, then the Givens
    /// rotation that keeps the least-squares problem triangular).
    void step(int j);
    /// ‖r_k‖_w of the least-squares iterate after j steps (in exact arithmetic).
    double residualNorm(int j, int k) const;
    /// Σ_i A_i Σ_k B_ik of that iterate.
    double power(int j);
    /// Move B to that iterate, then clamp B ≥ E (the solution is ≥ E, so clamping only
    /// moves B toward it).
    void update(int j);

private:
    double& h(int i, int j, int k) { return m_h[(std::size_t(i) * m_restart + j) * m_bins + k]; }
    void dot(const std::vector<double>& x, const std::vector<double>& y, double* out) const;
    void measure(int j);
    void solveY(int j);

    RadiositySystem& m_sys;
    const FormFactorMatrix& m_F;
    int m_restart, m_bins;
    std::vector<double> m_w;
    std::vector<std::vector<double>> m_V;
    std::vector<double> m_h, m_cs, m_sn, m_g, m_z, m_y;
    std::vector<double> m_powerOfV;  // Σ_i A_i V_j[i, k] per basis vector and bin
    double m_power = 0.0;            // Σ A B at the cycle's start
    std::vector<int> m_length;       // per bin: basis vectors in use
    std::vector<char> m_live;
};

/// GMRES until every bin's residual is ≤ relative times its right-hand side (both in
/// the norm ‖·‖_w) or after maxSteps steps; returns the steps taken. sys.b holds the
/// start and the result.
int solveGmres(RadiositySystem& sys, const FormFactorMatrix& F, double relative, int maxSteps, int restart = 30);

} // namespace effigi
