#pragma once
// Piecewise-constant distributions in 1-D and 2-D, sampled by inverting their CDFs.
//
// Distribution1D: n bins of non-negative weight over [0, 1); the density is constant in
// each bin. Distribution2D: an nu × nv grid over [0, 1)²; a point is drawn by first
// choosing v from the marginal of the rows, then u from the chosen row (pbrt-v4 §A.5.2,
// "Piecewise-Constant 2D Distributions"). Environment maps importance-sample their
// texels with it (weights: luminance · sin θ).
//
// Degenerate input: an all-zero (or empty) distribution is sampled uniformly, so the
// sampler never divides by zero; isZero() lets a caller treat it as "emits nothing".
// Weights that are negative, NaN or infinite are an error the caller must rule out
// beforehand (the constructors clamp NaN/negatives to 0 as a last safeguard).
#include "effigi/math/vector.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace effigi {

class Distribution1D {
public:
    Distribution1D() = default;
    explicit Distribution1D(std::vector<float> weights) : m_func(std::move(weights)) {
        std::size_t n = m_func.size();
        m_cdf.assign(n + 1, 0.0);
        // Accumulate in double: maps of millions of texels lose low bins in float.
        for (std::size_t i = 0; i < n; ++i) {
            if (!(m_func[i] > 0.f) || !std::isfinite(m_func[i])) m_func[i] = 0.f;
            m_cdf[i + 1] = m_cdf[i] + double(m_func[i]);
        }
        m_integral = n ? m_cdf[n] / double(n) : 0.0;
        if (!(m_cdf[n] > 0.0)) {
            // All zero: fall back to uniform so sampling stays well defined.
            for (std::size_t i = 0; i <= n; ++i) m_cdf[i] = n ? double(i) / double(n) : 0.0;
        } else {
            for (std::size_t i = 1; i <= n; ++i) m_cdf[i] /= m_cdf[n];
        }
    }

    std::size_t size() const { return m_func.size(); }
    /// ∫ f over [0, 1) (the mean weight).
    double integral() const { return m_integral; }
    bool isZero() const { return !(m_integral > 0.0); }
    float weight(std::size_t i) const { return m_func[i]; }

    /// Density at x ∈ [0, 1) (w.r.t. dx).
    float pdf(float x) const {
        if (m_func.empty()) return 0.f;
        std::size_t i = binOf(x);
        return isZero() ? 1.f : float(double(m_func[i]) / m_integral);
    }
    /// Probability of bin i.
    float binProbability(std::size_t i) const { return float(m_cdf[i + 1] - m_cdf[i]); }

    /// x ∈ [0, 1) distributed by the density; `pdf` receives pdf(x), `bin` its bin.
    float sample(float u, float& pdf, std::size_t& bin) const {
        std::size_t n = m_func.size();
        if (n == 0) return (pdf = 0.f, bin = 0, 0.f);
        // The last bin whose CDF start is ≤ u, skipping bins of zero probability.
        auto it = std::upper_bound(m_cdf.begin(), m_cdf.end(), double(u));
        std::size_t i = std::min<std::size_t>(std::size_t(std::max<std::ptrdiff_t>(it - m_cdf.begin() - 1, 0)), n - 1);
        while (i + 1 < n && !(m_cdf[i + 1] > m_cdf[i])) ++i;
        double width = m_cdf[i + 1] - m_cdf[i];
        double t = width > 0.0 ? (double(u) - m_cdf[i]) / width : 0.5;
        bin = i;
        pdf = float(width * double(n));
        float x = std::min(float((double(i) + std::clamp(t, 0.0, 1.0)) / double(n)), OneMinusEpsilon);
        // Rounding may land x on a neighbouring bin; nudge it back so that pdf(x) is
        // exactly the density reported here.
        while (binOf(x) > i) x = std::nextafter(x, 0.f);
        while (binOf(x) < i) x = std::nextafter(x, 1.f);
        return x;
    }

    std::size_t binOf(float x) const {
        std::ptrdiff_t i = std::ptrdiff_t(std::floor(x * float(m_func.size())));
        return std::size_t(std::clamp<std::ptrdiff_t>(i, 0, std::ptrdiff_t(m_func.size()) - 1));
    }

private:
    std::vector<float> m_func;
    std::vector<double> m_cdf;
    double m_integral = 0.0;
};

class Distribution2D {
public:
    Distribution2D() = default;
    /// weights[v * nu + u], nu columns by nv rows.
    Distribution2D(const std::vector<float>& weights, int nu, int nv) : m_nu(nu), m_nv(nv) {
        std::vector<float> marginal(std::size_t(std::max(nv, 0)));
        m_rows.reserve(marginal.size());
        for (int v = 0; v < nv; ++v) {
            auto first = weights.begin() + std::ptrdiff_t(v) * nu;
            m_rows.emplace_back(std::vector<float>(first, first + nu));
            marginal[std::size_t(v)] = float(m_rows.back().integral());
        }
        m_marginal = Distribution1D(std::move(marginal));
    }

    int nu() const { return m_nu; }
    int nv() const { return m_nv; }
    bool isZero() const { return m_marginal.isZero(); }

    /// A point of [0, 1)² and its density (w.r.t. du dv).
    Point2f sample(const Point2f& u, float& pdf) const {
        if (m_rows.empty()) return (pdf = 0.f, Point2f(0.f));
        float pdfV, pdfU;
        std::size_t row, col;
        float v = m_marginal.sample(u.y, pdfV, row);
        float x = m_rows[row].sample(u.x, pdfU, col);
        pdf = pdfV * pdfU;
        return {x, v};
    }

    float pdf(const Point2f& p) const {
        if (m_rows.empty()) return 0.f;
        std::size_t row = m_marginal.binOf(p.y);
        return m_marginal.pdf(p.y) * m_rows[row].pdf(p.x);
    }

private:
    int m_nu = 0, m_nv = 0;
    std::vector<Distribution1D> m_rows;
    Distribution1D m_marginal;
};

} // namespace effigi
