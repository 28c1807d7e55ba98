// Shared parts of the radiosity solvers (effigi/render/radiosity_solver.hpp) and the
// default row/column methods of IFormFactor.
#include "effigi/render/radiosity_solver.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/log.hpp"
#include "effigi/core/progress.hpp"
#include "effigi/render/radiosity_gmres.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace effigi {

void IFormFactor::row(std::uint32_t i, std::span<float> out) const {
    tbb::parallel_for(std::size_t(0), out.size(), [&](std::size_t j) { out[j] = float(formFactor(i, std::uint32_t(j))); });
}

void IFormFactor::column(std::uint32_t i, std::span<float> out) const {
    tbb::parallel_for(std::size_t(0), out.size(), [&](std::size_t j) { out[j] = float(formFactor(std::uint32_t(j), i)); });
}

namespace {

constexpr double Inf = std::numeric_limits<double>::infinity();

std::string describeBound(double bound) {
    return std::isfinite(bound) ? fmt::format("error bound {:.3g}", bound)
                                : std::string("no error bound (rho F does not contract in the norms tried)");
}

} // namespace

std::string SolverReport::summary() const {
    std::string time = fmt::format("{:.3g} s (form factors {:.3g} s)", seconds, formFactorSeconds);
    std::string bound = describeBound(errorBound);
    if (converged)
        return fmt::format("{} converged after {} iterations in {}: residual {:.3g}, {} <= tolerance {:.3g}", solver,
                           iterations, time, residual, bound, tolerance);
    if (interrupted)
        return fmt::format("{} was interrupted after {} iterations in {}: residual {:.3g}, {} (tolerance {:.3g})",
                           solver, iterations, time, residual, bound, tolerance);
    return fmt::format("{} did not converge: residual {:.3g}, {} after {} iterations, the limit (max_iterations = "
                       "{}; tolerance {:.3g}), in {}",
                       solver, residual, bound, iterations, maxIterations, tolerance, time);
}

RadiositySystem::RadiositySystem(const IMesh& mesh) : n(mesh.elementCount()), bins(mesh.bins().count()) {
    area.resize(n);
    for (std::size_t i = 0; i < n; ++i) area[i] = mesh.elements()[i].area;
    rho.assign(mesh.reflectance().begin(), mesh.reflectance().end());
    emission.assign(mesh.emission().begin(), mesh.emission().end());
    b = emission;
    for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < bins; ++k) emissionNorm += area[i] * emission[i * bins + k];
}

double RadiositySystem::relative(const std::vector<double>& x) const {
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        double s = 0.0;
        for (int k = 0; k < bins; ++k) s += std::abs(x[i * bins + k]);
        sum += area[i] * s;
    }
    return emissionNorm > 0.0 ? sum / emissionNorm : 0.0;
}

void RadiositySystem::store(IMesh& mesh) const {
    std::span<float> out = mesh.radiosity();
    for (std::size_t k = 0; k < out.size(); ++k) out[k] = float(b[k]);
    mesh.radiosityChanged();
}

FormFactorMatrix::FormFactorMatrix(const IFormFactor& ff, std::size_t n, const RenderControl& control,
                                   const std::string& solver)
    : m_n(n) {
    double bytes = double(n) * double(n) * sizeof(float);
    if (bytes > double(MaxBytes))
        fail("{}: the form-factor matrix of {} elements needs {:.1f} GiB (limit {} GiB); use solver 'progressive', "
             "which computes form factors on demand, or fewer elements",
             solver, n, bytes / double(1 << 30), MaxBytes >> 30);
    m_f.assign(n * n, 0.f);
    ProgressBar bar("Form factors", n, control.progress);
    std::atomic<bool> interrupted{false};
    tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
        if (control.stopRequested()) {
            interrupted = true;
            return;
        }
        ff.row(std::uint32_t(i), std::span<float>(m_f.data() + i * n, n));
        bar.update(1);
    });
    bar.finish();
    m_interrupted = interrupted;
}

void multiplyRhoF(const RadiositySystem& sys, const FormFactorMatrix& F, const std::vector<double>& x,
                  std::vector<double>& y) {
    const int nb = sys.bins;
    y.resize(x.size());
    // Rows per task: ~16k multiply-adds each, so that small systems (stiff test rooms,
    // 10⁵ products) do not pay a task spawn per row.
    std::size_t grain = std::max<std::size_t>(1, 16384 / std::max<std::size_t>(1, sys.n * nb));
    using Rows = tbb::blocked_range<std::size_t>;
    tbb::parallel_for(Rows(0, sys.n, grain), [&](const Rows& rows) {
        for (std::size_t i = rows.begin(); i < rows.end(); ++i) {
            double acc[SpectralBinning::MaxBins] = {};
            F.gather(i, x.data(), nb, acc);
            for (int k = 0; k < nb; ++k) y[i * nb + k] = sys.rho[i * nb + k] * acc[k];
        }
    });
}

ErrorBound::ErrorBound(const RadiositySystem& sys, const FormFactorMatrix& F)
    : m_bins(sys.bins), m_q1(sys.bins, 0.0), m_theta(sys.bins, 0.0), m_vArea(sys.bins, 0.0) {
    const int nb = sys.bins;
    const std::size_t n = sys.n;
    // q1: the largest area-weighted column sum, c_jk = Σ_i A_i ρ_ik F_ij / A_j. Columns
    // in parallel blocks, each block reading its slice of every row.
    std::vector<double> column(n * nb, 0.0);
    using Columns = tbb::blocked_range<std::size_t>;
    tbb::parallel_for(Columns(0, n, 64), [&](const Columns& range) {
        for (std::size_t i = 0; i < n; ++i) {
            const float* row = F.row(i);
            for (std::size_t j = range.begin(); j < range.end(); ++j) {
                if (row[j] == 0.f) continue;
                double f = sys.area[i] * double(row[j]);
                for (int k = 0; k < nb; ++k) column[j * nb + k] += f * sys.rho[i * nb + k];
            }
        }
    });
    for (std::size_t j = 0; j < n; ++j)
        for (int k = 0; k < nb; ++k) {
            double c = column[j * nb + k];
            if (c > 0.0) m_q1[k] = std::max(m_q1[k], sys.area[j] > 0.0 ? c / sys.area[j] : Inf);
        }
    // v = 1 + ρF(1 + ρF(1 + ...)), NeumannTerms deep: ≥ 1 everywhere, and close to the
    // Perron vector of ρF where the form factors are accurate. θ from one more product,
    // computed rather than assumed, so any v > 0 gives a valid bound.
    m_v.assign(n * nb, 1.0);
    std::vector<double> product;
    for (int l = 0; l < NeumannTerms; ++l) {
        multiplyRhoF(sys, F, m_v, product);
        for (std::size_t x = 0; x < m_v.size(); ++x) m_v[x] = 1.0 + product[x];
    }
    auto contraction = [&](const std::vector<double>& v) {
        std::vector<double> theta(nb, 0.0);
        multiplyRhoF(sys, F, v, product);
        for (std::size_t i = 0; i < n; ++i)
            for (int k = 0; k < nb; ++k) theta[k] = std::max(theta[k], product[i * nb + k] / v[i * nb + k]);
        return theta;
    };
    m_theta = contraction(m_v);
    // Where that barely contracts (rows summing to more than 1/ρ somewhere, as coarse
    // quadrature of form factors does near corners, or white surfaces), take the best
    // weights instead: v = (I − ρF)⁻¹ 1, for which ρFv = v − 1 and θ = 1 − 1/max v is
    // the max-norm of (I − ρF)⁻¹ itself. GMRES solves for it roughly (a residual s with
    // |s| < 1 still gives θ ≤ 1 − (1 − max|s|)/max v < 1); per bin the better v is kept.
    if (*std::max_element(m_theta.begin(), m_theta.end()) > 0.9) {
        RadiositySystem ones = sys;
        ones.emission.assign(n * nb, 1.0);
        ones.b = ones.emission;
        solveGmres(ones, F, 1e-3, 100);
        std::vector<double> theta = contraction(ones.b);
        for (int k = 0; k < nb; ++k)
            if (theta[k] < m_theta[k]) {
                m_theta[k] = theta[k];
                for (std::size_t i = 0; i < n; ++i) m_v[i * nb + k] = ones.b[i * nb + k];
            }
    }
    for (std::size_t i = 0; i < n; ++i)
        for (int k = 0; k < nb; ++k) m_vArea[k] += sys.area[i] * m_v[i * nb + k];
    // Float form factors carry ~1e-7 relative round-off; closer to 1 than 1e-5, B is
    // amplified so much that this round-off, not the scene, decides it.
    double worst = 0.0;
    for (int k = 0; k < nb; ++k) worst = std::max(worst, std::min(m_q1[k], m_theta[k]));
    if (worst >= 1.0)
        log::warn("radiosity: rho F does not contract (a closed room of reflectance 1?): B may grow without "
                  "bound, and no error bound exists");
    else if (worst > 1.0 - 1e-5)
        log::warn("radiosity: rho F contracts only by {:.3g} (a closed room of reflectance 1?): B is amplified up "
                  "to {:.3g} times, as set by round-off in the form factors",
                  1.0 - worst, 1.0 / (1.0 - worst));
}

ErrorBound::ErrorBound(const RadiositySystem& sys)
    : m_bins(sys.bins), m_q1(sys.bins, 0.0), m_theta(sys.bins, 0.0), m_vArea(sys.bins, 0.0) {
    for (std::size_t i = 0; i < sys.n; ++i)
        for (int k = 0; k < sys.bins; ++k) {
            m_q1[k] = std::max(m_q1[k], sys.rho[i * sys.bins + k]);
            m_vArea[k] += sys.area[i];
        }
    m_theta = m_q1;
}

ResidualNorms ErrorBound::norms(const RadiositySystem& sys, const std::vector<double>& x) const {
    ResidualNorms out{std::vector<double>(m_bins, 0.0), std::vector<double>(m_bins, 0.0)};
    for (std::size_t i = 0; i < sys.n; ++i)
        for (int k = 0; k < m_bins; ++k) {
            double a = std::abs(x[i * m_bins + k]);
            out.areaSum[k] += sys.area[i] * a;
            out.weightedMax[k] = std::max(out.weightedMax[k], a / weight(i, k));
        }
    return out;
}

double ErrorBound::elementScale(const ResidualNorms& n, bool update, int k) const {
    double r = n.weightedMax[k];
    if (r == 0.0) return 0.0;
    if (!(m_theta[k] < 1.0)) return Inf;
    return (update ? m_theta[k] * r : r) / (1.0 - m_theta[k]);
}

std::vector<double> ErrorBound::binErrors(const ResidualNorms& n, bool update) const {
    std::vector<double> e(m_bins, 0.0);
    for (int k = 0; k < m_bins; ++k) {
        if (n.areaSum[k] == 0.0 && n.weightedMax[k] == 0.0) continue;  // B solves the bin exactly
        double best = m_vArea[k] * elementScale(n, update, k);
        if (m_q1[k] < 1.0) best = std::min(best, (update ? m_q1[k] : 1.0) * n.areaSum[k] / (1.0 - m_q1[k]));
        e[k] = best;
    }
    return e;
}

double ErrorBound::relative(const RadiositySystem& sys, const std::vector<double>& binErrors) const {
    double power = 0.0;
    for (std::size_t i = 0; i < sys.n; ++i)
        for (int k = 0; k < m_bins; ++k) power += sys.area[i] * sys.b[i * m_bins + k];
    return relative(binErrors, power, sys.emissionNorm);
}

double ErrorBound::relative(const std::vector<double>& binErrors, double power, double emissionNorm) {
    double error = 0.0;
    for (double e : binErrors) error += e;
    if (error == 0.0) return 0.0;
    if (!std::isfinite(error)) return Inf;
    double floor = std::max(emissionNorm, power - error);
    return floor > 0.0 ? error / floor : Inf;
}

std::vector<double> solveDirect(const RadiositySystem& sys, const FormFactorMatrix& F) {
    const std::size_t n = sys.n;
    const int nb = sys.bins;
    std::vector<double> out(n * nb), M(n * n), x(n);
    for (int k = 0; k < nb; ++k) {
        for (std::size_t i = 0; i < n; ++i) {
            double rho = sys.rho[i * nb + k];
            for (std::size_t j = 0; j < n; ++j) M[i * n + j] = (i == j ? 1.0 : 0.0) - rho * double(F.at(i, j));
            x[i] = sys.emission[i * nb + k];
        }
        for (std::size_t c = 0; c < n; ++c) {
            std::size_t p = c;
            for (std::size_t r = c + 1; r < n; ++r)
                if (std::abs(M[r * n + c]) > std::abs(M[p * n + c])) p = r;
            if (p != c) {
                std::swap_ranges(M.begin() + c * n, M.begin() + (c + 1) * n, M.begin() + p * n);
                std::swap(x[c], x[p]);
            }
            for (std::size_t r = c + 1; r < n; ++r) {
                double f = M[r * n + c] / M[c * n + c];
                if (f == 0.0) continue;
                for (std::size_t j = c; j < n; ++j) M[r * n + j] -= f * M[c * n + j];
                x[r] -= f * x[c];
            }
        }
        for (std::size_t c = n; c-- > 0;) {
            double s = x[c];
            for (std::size_t j = c + 1; j < n; ++j) s -= M[c * n + j] * x[j];
            x[c] = s / M[c * n + c];
        }
        for (std::size_t i = 0; i < n; ++i) out[i * nb + k] = x[i];
    }
    return out;
}

double relativeError(const IMesh& mesh, const std::vector<double>& exact) {
    const int nb = mesh.bins().count();
    std::span<const float> b = mesh.radiosity();
    double diff = 0.0, sum = 0.0;
    for (std::size_t i = 0; i < mesh.elementCount(); ++i)
        for (int k = 0; k < nb; ++k) {
            double a = mesh.elements()[i].area;
            diff += a * std::abs(double(b[i * nb + k]) - exact[i * nb + k]);
            sum += a * exact[i * nb + k];
        }
    return sum > 0.0 ? diff / sum : (diff > 0.0 ? Inf : 0.0);
}

SolverLog::SolverLog(std::string solver, std::uint64_t maxIterations, double tolerance)
    : m_start(std::chrono::steady_clock::now()), m_lastInfo(m_start) {
    m_report.solver = std::move(solver);
    m_report.maxIterations = maxIterations;
    m_report.tolerance = tolerance;
}

double SolverLog::seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
}

void SolverLog::formFactorsDone() { m_report.formFactorSeconds = seconds(); }

void SolverLog::record(std::uint64_t iteration, double residual, double errorBound) {
    if (iteration < 1000 || iteration >= m_nextRecord) {
        m_report.history.push_back({iteration, seconds(), residual});
        m_nextRecord = iteration + iteration / 100 + 1;
    }
    auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - m_lastInfo).count() >= 1.0) {
        m_lastInfo = now;
        log::info("{}: iteration {}, residual {:.3g}, {}, {:.1f} s", m_report.solver, iteration, residual,
                  describeBound(errorBound), seconds());
    }
}

bool SolverLog::reached(double residual, double errorBound) const {
    return std::isfinite(errorBound) ? errorBound <= m_report.tolerance : residual <= m_report.tolerance;
}

SolverReport SolverLog::finish(std::uint64_t iterations, double residual, double errorBound, bool interrupted) {
    m_report.iterations = iterations;
    m_report.residual = residual;
    m_report.errorBound = errorBound;
    m_report.seconds = seconds();
    m_report.interrupted = interrupted;
    m_report.converged = !interrupted && reached(residual, errorBound);
    if (m_report.history.empty() || m_report.history.back().iteration != iterations)
        m_report.history.push_back({iterations, m_report.seconds, residual});
    if (m_report.converged) log::info("{}", m_report.summary());
    else log::warn("{}", m_report.summary());
    return m_report;
}

} // namespace effigi
