// solver "progressive" — progressive refinement radiosity (Cohen, Chen, Wallace &
// Greenberg 1988): shoot instead of gather. Each step takes the element with the most
// unshot power A_i ΔB_i, computes its column of form factors on demand (no matrix is
// stored: memory O(elements)) and distributes the unshot radiosity:
//
//   B_j += ρ_j F_ji ΔB_i,   ΔB_j += ρ_j F_ji ΔB_i,   ΔB_i = 0.
//
// Everything but the unshot radiosity has been shot, B = E + ρF(B − ΔB), so the residual
// is r = ρFΔB and the reported residual is the unshot power Σ A ΔB / Σ A E. The error
// bound (ISolver, ErrorBound) follows from |r| ≤ ρF ΔB; without the matrix its
// contraction factor is max ρ, which holds for reciprocal columns with rows summing to
// ≤ 1 (scenes with a white, ρ = 1, surface get no bound and stop on the residual).
// When the solve stops short of the tolerance, the estimate is completed for display
// with the ambient term of the paper: the unshot power spread uniformly and reflected by
// an average room,
//   ambient = (Σ A ΔB / Σ A) / (1 − ρ̄),  ρ̄ = Σ A ρ / Σ A,   B_i += ρ_i · ambient,
// and the bound reported is that of B with the ambient term (B ≤ B*, so the error of
// element i is at most max(ambient_i, the max-norm error bound)). A converged solution
// needs no ambient term. Columns are cached (cache_mb) because in stiff scenes the same
// elements shoot again and again.
//
// Parameters:
//   max_iterations  int (default 0 = 100 × elements)  shots at most
//   tolerance       float (default 1e-4, > 0)         bound of the relative error to stop at
//   ambient         bool (default true)               add the ambient term when stopped short
//   cache_mb        int (default 512, >= 0)           memory for cached columns [MiB]
//
// Reference: M. F. Cohen, S. E. Chen, J. R. Wallace, D. P. Greenberg, "A Progressive
// Refinement Approach to Fast Radiosity Image Generation", SIGGRAPH 1988.
#include "effigi/core/registry.hpp"
#include "effigi/render/radiosity_solver.hpp"

#include <algorithm>
#include <cmath>

namespace effigi {
namespace {

class ProgressiveSolver final : public Implements<ISolver> {
public:
    static Schema schema() {
        Schema s("solver", "progressive",
                 "Progressive refinement: shoot the element with the most unshot power; form factors on demand.");
        s.cite("Cohen, Chen, Wallace & Greenberg, A Progressive Refinement Approach to Fast Radiosity Image "
               "Generation, SIGGRAPH 1988");
        s.integer("max_iterations", 0, "Shots at most; 0: 100 times the element count").range(0, 1e12);
        s.real("tolerance", 1e-4, "Bound of the relative error of B (Σ A|B − B*| / Σ A B*) to stop at")
            .range(1e-15, 1.0);
        s.boolean("ambient", true, "Add the ambient term (unshot power spread uniformly) when stopped short");
        s.integer("cache_mb", 512, "Memory for cached form-factor columns").range(0, 1 << 20).withUnit("MiB");
        return s;
    }

    explicit ProgressiveSolver(const Properties& p)
        : m_maxIterations(std::uint64_t(p.getInt("max_iterations"))), m_tolerance(p.getFloat("tolerance")),
          m_ambient(p.getBool("ambient")), m_cacheBytes(std::size_t(p.getInt("cache_mb")) << 20) {}

    SolverReport solve(IMesh& mesh, const IFormFactor& ff, const RenderControl& control) override {
        RadiositySystem sys(mesh);
        std::uint64_t limit = m_maxIterations ? m_maxIterations : 100 * std::uint64_t(sys.n);
        SolverLog log("solver 'progressive'", limit, m_tolerance);
        ErrorBound bound(sys);
        const int nb = sys.bins;
        std::vector<double> unshot = sys.emission;
        std::vector<std::vector<float>> cache(sys.n);
        std::size_t cached = 0;
        std::vector<float> column(sys.n);
        auto unshotPower = [&](std::size_t i) {
            double s = 0.0;
            for (int k = 0; k < nb; ++k) s += unshot[i * nb + k];
            return sys.area[i] * s;
        };
        std::size_t pick = 0;
        for (std::size_t i = 1; i < sys.n; ++i)
            if (unshotPower(i) > unshotPower(pick)) pick = i;
        std::uint64_t it = 0;
        double residual = sys.relative(unshot), error = bound.relative(sys, unshot, true);
        // The bound's inputs are kept up to date in the shot loop (no extra pass per
        // shot): the unshot norms per bin and Σ A B.
        ResidualNorms norms = bound.norms(sys, unshot);
        double power = sys.emissionNorm;
        bool interrupted = false;
        double shot[SpectralBinning::MaxBins];
        while (!interrupted && !log.reached(residual, error) && it < limit) {
            const float* col = cache[pick].data();
            if (cache[pick].empty()) {
                double t0 = log.seconds();
                ff.column(std::uint32_t(pick), column);
                log.addFormFactorSeconds(log.seconds() - t0);
                col = column.data();
                if ((cached + 1) * sys.n * sizeof(float) <= m_cacheBytes) {
                    cache[pick] = column;
                    ++cached;
                }
            }
            for (int k = 0; k < nb; ++k) {
                shot[k] = unshot[pick * nb + k];
                unshot[pick * nb + k] = 0.0;
            }
            double norm = 0.0, best = -1.0;
            std::size_t next = pick;
            std::fill(norms.areaSum.begin(), norms.areaSum.end(), 0.0);
            std::fill(norms.weightedMax.begin(), norms.weightedMax.end(), 0.0);
            for (std::size_t j = 0; j < sys.n; ++j) {
                double f = col[j], s = 0.0;
                for (int k = 0; k < nb; ++k) {
                    std::size_t jk = j * nb + k;
                    if (f != 0.0) {
                        double d = sys.rho[jk] * f * shot[k];
                        sys.b[jk] += d;
                        unshot[jk] += d;
                        power += sys.area[j] * d;
                    }
                    s += unshot[jk];
                    norms.areaSum[k] += sys.area[j] * unshot[jk];
                    norms.weightedMax[k] = std::max(norms.weightedMax[k], unshot[jk]);  // v = 1, ΔB ≥ 0
                }
                norm += sys.area[j] * s;
                if (sys.area[j] * s > best) best = sys.area[j] * s, next = j;
            }
            pick = next;
            residual = sys.emissionNorm > 0.0 ? norm / sys.emissionNorm : 0.0;
            error = ErrorBound::relative(bound.binErrors(norms, true), power, sys.emissionNorm);
            log.record(++it, residual, error);
            interrupted = control.stopRequested();
        }
        if (m_ambient && !log.reached(residual, error)) error = addAmbient(sys, unshot, bound);
        sys.store(mesh);
        return log.finish(it, residual, error, interrupted);
    }

private:
    /// Cohen et al. 1988, §4: the unshot power as a uniform ambient radiosity a_i = ρ_i ·
    /// ambient. Returns the error bound of B + a: with d = B* − B, 0 ≤ d_i ≤ D (the
    /// max-norm bound), |a_i − d_i| ≤ max(a_i, D), and Σ A |a − d| ≤ Σ A a + Σ A d.
    static double addAmbient(RadiositySystem& sys, const std::vector<double>& unshot, const ErrorBound& bound) {
        const int nb = sys.bins;
        ResidualNorms norms = bound.norms(sys, unshot);
        std::vector<double> errors = bound.binErrors(norms, true);
        double area = 0.0;
        for (double a : sys.area) area += a;
        if (!(area > 0.0)) return bound.relative(sys, errors);
        for (int k = 0; k < nb; ++k) {
            double u = 0.0, rho = 0.0;
            for (std::size_t i = 0; i < sys.n; ++i) {
                u += sys.area[i] * unshot[i * nb + k];
                rho += sys.area[i] * sys.rho[i * nb + k];
            }
            rho /= area;
            double ambient = rho < 1.0 ? u / area / (1.0 - rho) : 0.0;
            double D = bound.elementScale(norms, true, k), added = 0.0, viaMax = 0.0;
            for (std::size_t i = 0; i < sys.n; ++i) {
                double a = sys.rho[i * nb + k] * ambient;
                sys.b[i * nb + k] += a;
                added += sys.area[i] * a;
                viaMax += sys.area[i] * std::max(a, D);
            }
            errors[k] = std::min(errors[k] + added, viaMax);
        }
        return bound.relative(sys, errors);
    }

    std::uint64_t m_maxIterations;
    double m_tolerance;
    bool m_ambient;
    std::size_t m_cacheBytes;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::ProgressiveSolver)
