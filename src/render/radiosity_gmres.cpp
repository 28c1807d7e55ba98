// Restarted GMRES on the radiosity system (effigi/render/radiosity_gmres.hpp).
#include "effigi/render/radiosity_gmres.hpp"

#include <algorithm>
#include <cmath>

namespace effigi {

GmresCycle::GmresCycle(RadiositySystem& sys, const FormFactorMatrix& F, int restart)
    : m_sys(sys), m_F(F), m_restart(restart), m_bins(sys.bins), m_w(sys.b.size()), m_V(restart + 1),
      m_h(std::size_t(restart + 1) * restart * sys.bins), m_cs(restart * sys.bins), m_sn(restart * sys.bins),
      m_g((restart + 1) * sys.bins), m_y(restart * sys.bins), m_powerOfV((restart + 1) * sys.bins),
      m_length(sys.bins), m_live(sys.bins) {
    for (std::size_t i = 0; i < sys.n; ++i)
        for (int k = 0; k < m_bins; ++k) {
            double rho = sys.rho[i * m_bins + k];
            m_w[i * m_bins + k] = rho > 0.0 ? sys.area[i] / rho : sys.area[i];
        }
    for (auto& v : m_V) v.resize(sys.b.size());
}

void GmresCycle::dot(const std::vector<double>& x, const std::vector<double>& y, double* out) const {
    std::fill(out, out + m_bins, 0.0);
    for (std::size_t i = 0; i < m_sys.n; ++i)
        for (int k = 0; k < m_bins; ++k) out[k] += m_w[i * m_bins + k] * x[i * m_bins + k] * y[i * m_bins + k];
}

void GmresCycle::residual(std::vector<double>& r) const {
    multiplyRhoF(m_sys, m_F, m_sys.b, r);
    for (std::size_t x = 0; x < r.size(); ++x) r[x] += m_sys.emission[x] - m_sys.b[x];
}

bool GmresCycle::active() const {
    return std::any_of(m_live.begin(), m_live.end(), [](char c) { return c != 0; });
}

void GmresCycle::measure(int j) {
    double* p = &m_powerOfV[std::size_t(j) * m_bins];
    std::fill(p, p + m_bins, 0.0);
    for (std::size_t i = 0; i < m_sys.n; ++i)
        for (int k = 0; k < m_bins; ++k) p[k] += m_sys.area[i] * m_V[j][i * m_bins + k];
}

void GmresCycle::start(const std::vector<double>& r) {
    double beta[SpectralBinning::MaxBins];
    dot(r, r, beta);
    std::fill(m_g.begin(), m_g.end(), 0.0);
    for (int k = 0; k < m_bins; ++k) {
        beta[k] = std::sqrt(beta[k]);
        m_g[k] = beta[k];
        m_live[k] = beta[k] > 0.0;
        m_length[k] = 0;
    }
    for (std::size_t x = 0; x < r.size(); ++x) {
        double b = beta[x % m_bins];
        m_V[0][x] = b > 0.0 ? r[x] / b : 0.0;
    }
    measure(0);
    m_power = 0.0;
    for (std::size_t i = 0; i < m_sys.n; ++i)
        for (int k = 0; k < m_bins; ++k) m_power += m_sys.area[i] * m_sys.b[i * m_bins + k];
}

void GmresCycle::step(int j) {
    const int nb = m_bins;
    multiplyRhoF(m_sys, m_F, m_V[j], m_z);
    for (std::size_t x = 0; x < m_z.size(); ++x) m_z[x] = m_V[j][x] - m_z[x];
    double before[SpectralBinning::MaxBins], d[SpectralBinning::MaxBins];
    dot(m_z, m_z, before);
    for (int i = 0; i <= j; ++i) {
        dot(m_z, m_V[i], d);
        for (int k = 0; k < nb; ++k) h(i, j, k) = d[k];
        for (std::size_t x = 0; x < m_z.size(); ++x) m_z[x] -= d[x % nb] * m_V[i][x];
    }
    dot(m_z, m_z, d);
    for (int k = 0; k < nb; ++k) {
        double next = std::sqrt(d[k]);
        // Happy breakdown: M maps the basis into its own span, so this bin's
        // least-squares solution is exact; its later basis vectors are zero.
        bool breakdown = !(next > 1e-13 * std::sqrt(before[k]));
        h(j + 1, j, k) = breakdown ? 0.0 : next;
        d[k] = m_live[k] && !breakdown ? 1.0 / next : 0.0;
    }
    for (std::size_t x = 0; x < m_z.size(); ++x) m_V[j + 1][x] = m_z[x] * d[x % nb];
    measure(j + 1);
    for (int k = 0; k < nb; ++k) {
        if (!m_live[k]) continue;
        double* cs = &m_cs[k];
        double* sn = &m_sn[k];
        for (int i = 0; i < j; ++i) {
            double a = h(i, j, k), b = h(i + 1, j, k);
            h(i, j, k) = cs[i * nb] * a + sn[i * nb] * b;
            h(i + 1, j, k) = -sn[i * nb] * a + cs[i * nb] * b;
        }
        double a = h(j, j, k), b = h(j + 1, j, k), r = std::hypot(a, b);
        if (!(r > 0.0)) {  // M singular on this space (ρF has eigenvalue 1): stop the bin
            m_live[k] = 0;
            continue;
        }
        cs[j * nb] = a / r;
        sn[j * nb] = b / r;
        h(j, j, k) = r;
        h(j + 1, j, k) = 0.0;
        m_g[(j + 1) * nb + k] = -sn[j * nb] * m_g[j * nb + k];
        m_g[j * nb + k] *= cs[j * nb];
        m_length[k] = j + 1;
        if (d[k] == 0.0) m_live[k] = 0;
    }
}

double GmresCycle::residualNorm(int j, int k) const {
    return std::abs(m_g[std::min(j, m_length[k]) * m_bins + k]);
}

void GmresCycle::solveY(int j) {
    std::fill(m_y.begin(), m_y.end(), 0.0);
    for (int k = 0; k < m_bins; ++k) {
        int len = std::min(j, m_length[k]);
        for (int i = len - 1; i >= 0; --i) {
            double s = m_g[i * m_bins + k];
            for (int l = i + 1; l < len; ++l) s -= h(i, l, k) * m_y[l * m_bins + k];
            m_y[i * m_bins + k] = s / h(i, i, k);
        }
    }
}

double GmresCycle::power(int j) {
    solveY(j);
    double p = m_power;
    for (int i = 0; i < j; ++i)
        for (int k = 0; k < m_bins; ++k) p += m_y[i * m_bins + k] * m_powerOfV[i * m_bins + k];
    return p;
}

void GmresCycle::update(int j) {
    solveY(j);
    std::vector<double>& b = m_sys.b;
    for (int i = 0; i < j; ++i)
        for (std::size_t x = 0; x < b.size(); ++x) b[x] += m_y[i * m_bins + x % m_bins] * m_V[i][x];
    for (std::size_t x = 0; x < b.size(); ++x) b[x] = std::max(b[x], m_sys.emission[x]);
}

int solveGmres(RadiositySystem& sys, const FormFactorMatrix& F, double relative, int maxSteps, int restart) {
    GmresCycle c(sys, F, restart);
    std::vector<double> r;
    double target[SpectralBinning::MaxBins] = {};
    for (std::size_t i = 0; i < sys.n; ++i)
        for (int k = 0; k < sys.bins; ++k) {
            double e = sys.emission[i * sys.bins + k];
            target[k] += c.weight(i, k) * e * e;
        }
    for (int k = 0; k < sys.bins; ++k) target[k] = relative * std::sqrt(target[k]);
    auto done = [&](auto norm) {
        for (int k = 0; k < sys.bins; ++k)
            if (norm(k) > target[k]) return false;
        return true;
    };
    int steps = 0;
    c.residual(r);
    for (;;) {
        c.start(r);
        int j = 0;
        while (j < restart && steps < maxSteps && c.active()) {
            c.step(j++);
            ++steps;
            if (done([&](int k) { return c.residualNorm(j, k); })) break;
        }
        if (j == 0) return steps;  // every bin broke down: nothing more to gain
        c.update(j);
        c.residual(r);
        double norm[SpectralBinning::MaxBins];
        std::fill(norm, norm + sys.bins, 0.0);
        for (std::size_t i = 0; i < sys.n; ++i)
            for (int k = 0; k < sys.bins; ++k) norm[k] += c.weight(i, k) * r[i * sys.bins + k] * r[i * sys.bins + k];
        if (steps >= maxSteps || done([&](int k) { return std::sqrt(norm[k]); })) return steps;
    }
}

} // namespace effigi
