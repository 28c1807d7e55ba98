// function "polynomial" — a smooth product polynomial on [0,1)^d with integral 1.
//
// f(x) = Π_{i=1..d} c (1 + x_i^k),  c = (k+1)/(k+2),
// so each factor integrates to c (1 + 1/(k+1)) = 1 and ∫f = 1 exactly. A test integrand
// for numerical integrators and samplers: smooth, every dimension matters, variance
// Π (1 + v) − 1 with v = c² (1 + 2/(k+1) + 1/(2k+1)) − 1 small (0.05 per dimension for
// k = 2), so plain Monte Carlo converges well in all 8 dimensions.
//
// Parameters:
//   dimension  int (default 2, in [1, 8])  d
//   degree     int (default 2, in [1, 8])  k, the degree in each variable
//
// Reference: A. Genz, "Testing multidimensional integration routines", in Tools, Methods
// and Languages for Scientific and Engineering Computation, 1984 (test families with
// known integrals; this product form is in the spirit of his "product peak").
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifunction.hpp"

#include <cmath>

namespace effigi {
namespace {

class Polynomial final : public Implements<IFunction> {
public:
    static Schema schema() {
        Schema s("function", "polynomial", "Smooth test integrand Π (k+1)/(k+2) (1 + x_i^k) on [0,1)^d; ∫ = 1.");
        s.cite("A. Genz, Testing multidimensional integration routines, 1984");
        s.integer("dimension", 2, "Number of variables d").range(1, 8);
        s.integer("degree", 2, "Degree k in each variable").range(1, 8);
        s.addConformance({"default", {}});
        s.addConformance({"1D quintic", {{"dimension", std::int64_t(1)}, {"degree", std::int64_t(5)}}});
        s.addConformance({"8D cubic", {{"dimension", std::int64_t(8)}, {"degree", std::int64_t(3)}}});
        return s;
    }

    explicit Polynomial(const Properties& p) : m_dim(int(p.getInt("dimension"))), m_degree(int(p.getInt("degree"))) {
        m_scale = double(m_degree + 1) / double(m_degree + 2);
    }

    int dimension() const override { return m_dim; }
    void eval(ISampler& u, std::span<double> out) override {
        double f = 1.0;
        for (int i = 0; i < m_dim; ++i) f *= m_scale * (1.0 + std::pow(double(u.get1D()), m_degree));
        out[0] = f;
    }
    std::optional<std::vector<double>> integral() const override { return std::vector<double>{1.0}; }

private:
    int m_dim, m_degree;
    double m_scale;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Polynomial)
