// function "gaussian" — a Gaussian peak on [0,1)^d (Genz's "Gaussian" family).
//
// f(x) = exp(−Σ (x_i − c)² / (2σ²)), with the exact integral
// ∫f = Π σ sqrt(π/2) [erf((1 − c)/(σ√2)) + erf(c/(σ√2))].
// Narrow peaks (small σ) in few dimensions make the integrand hard for uniform sampling.
//
// Parameters:
//   dimension  int (default 2, in [1, 8])         d
//   width      float (default 0.2, in [1e-3, 10]) σ
//   center     float (default 0.45, in [0, 1])    c, the peak's position in every variable
//
// Reference: A. Genz, "Testing multidimensional integration routines", 1984 (family 4).
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifunction.hpp"

#include <cmath>

namespace effigi {
namespace {

class Gaussian final : public Implements<IFunction> {
public:
    static Schema schema() {
        Schema s("function", "gaussian", "Gaussian peak exp(−Σ (x_i − c)²/(2σ²)) on [0,1)^d, exact integral.");
        s.cite("A. Genz, Testing multidimensional integration routines, 1984 (Gaussian family)");
        s.integer("dimension", 2, "Number of variables d").range(1, 8);
        s.real("width", 0.2, "Standard deviation σ of the peak").range(1e-3, 10.0);
        s.real("center", 0.45, "Position c of the peak in every variable").range(0.0, 1.0);
        s.addConformance({"default", {}});
        s.addConformance({"1D narrow", {{"dimension", std::int64_t(1)}, {"width", 0.02}}});
        s.addConformance({"8D", {{"dimension", std::int64_t(8)}, {"width", 0.4}, {"center", 0.3}}});
        return s;
    }

    explicit Gaussian(const Properties& p)
        : m_dim(int(p.getInt("dimension"))), m_sigma(p.getFloat("width")), m_center(p.getFloat("center")) {}

    int dimension() const override { return m_dim; }
    void eval(ISampler& u, std::span<double> out) override {
        double s = 0.0;
        for (int i = 0; i < m_dim; ++i) {
            double d = double(u.get1D()) - m_center;
            s += d * d;
        }
        out[0] = std::exp(-s / (2.0 * m_sigma * m_sigma));
    }
    std::optional<std::vector<double>> integral() const override {
        const double k = m_sigma * std::sqrt(2.0);
        double one = m_sigma * std::sqrt(std::numbers::pi / 2.0) * (std::erf((1.0 - m_center) / k) + std::erf(m_center / k));
        return std::vector<double>{std::pow(one, m_dim)};
    }

private:
    int m_dim;
    double m_sigma, m_center;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Gaussian)
