// Shared parts of the radiosity solvers (effigi/render/radiosity_solver.hpp) and the
// default row/column methods of IFormFactor.
#include "effigi/render/radiosity_solver.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/log.hpp"
#include "effigi/core/progress.hpp"

#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>

namespace effigi {

void IFormFactor::row(std::uint32_t i, std::span<float> out) const {
    tbb::parallel_for(std::size_t(0), out.size(), [&](std::size_t j) { out[j] = float(formFactor(i, std::uint32_t(j))); });
}

void IFormFactor::column(std::uint32_t i, std::span<float> out) const {
    tbb::parallel_for(std::size_t(0), out.size(), [&](std::size_t j) { out[j] = float(formFactor(std::uint32_t(j), i)); });
}

std::string SolverReport::summary() const {
    std::string time = fmt::format("{:.3g} s (form factors {:.3g} s)", seconds, formFactorSeconds);
    if (converged)
        return fmt::format("{} converged after {} iterations in {}: residual {:.3g} <= tolerance {:.3g}", solver,
                           iterations, time, residual, tolerance);
    if (interrupted)
        return fmt::format("{} was interrupted after {} iterations in {}: residual {:.3g} (tolerance {:.3g})", solver,
                           iterations, time, residual, tolerance);
    return fmt::format("{} did not converge: residual {:.3g} after {} iterations, the limit (max_iterations = {}; "
                       "tolerance {:.3g}), in {}",
                       solver, residual, iterations, maxIterations, tolerance, time);
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

void SolverLog::record(std::uint64_t iteration, double residual) {
    if (iteration < 1000 || iteration >= m_nextRecord) {
        m_report.history.push_back({iteration, seconds(), residual});
        m_nextRecord = iteration + iteration / 100 + 1;
    }
    auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - m_lastInfo).count() >= 1.0) {
        m_lastInfo = now;
        log::info("{}: iteration {}, residual {:.3g}, {:.1f} s", m_report.solver, iteration, residual, seconds());
    }
}

SolverReport SolverLog::finish(std::uint64_t iterations, double residual, bool interrupted) {
    m_report.iterations = iterations;
    m_report.residual = residual;
    m_report.seconds = seconds();
    m_report.interrupted = interrupted;
    m_report.converged = !interrupted && residual <= m_report.tolerance;
    if (m_report.history.empty() || m_report.history.back().iteration != iterations)
        m_report.history.push_back({iterations, m_report.seconds, residual});
    if (m_report.converged) log::info("{}", m_report.summary());
    else log::warn("{}", m_report.summary());
    return m_report;
}

} // namespace effigi
