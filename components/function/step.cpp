// function "step" — Genz's discontinuous integrand on [0,1)^d.
//
// f(x) = exp(a Σ x_i) where x_1 < w and x_2 < w (only x_1 for d = 1), 0 elsewhere, with
// ∫f = Π_{i <= min(d,2)} (e^{a w} − 1)/a · Π_{i > 2} (e^a − 1)/a  (a → 0: w and 1).
// The jump across the planes x_i = w slows quasi-Monte Carlo and stratified methods to
// their discontinuous rates.
//
// Parameters:
//   dimension  int (default 2, in [1, 8])          d
//   threshold  float (default 0.6, in [0.01, 1])   w, where the step is
//   slope      float (default 0.5, in [0, 5])      a, growth inside the box
//
// Reference: A. Genz, "Testing multidimensional integration routines", 1984 (family 6,
// "discontinuous").
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifunction.hpp"

#include <cmath>

namespace effigi {
namespace {

class Step final : public Implements<IFunction> {
public:
    static Schema schema() {
        Schema s("function", "step", "Discontinuous test integrand exp(a Σx) inside x_1, x_2 < w (Genz), exact integral.");
        s.cite("A. Genz, Testing multidimensional integration routines, 1984 (discontinuous family)");
        s.integer("dimension", 2, "Number of variables d").range(1, 8);
        s.real("threshold", 0.6, "Position w of the step in x_1 and x_2").range(0.01, 1.0);
        s.real("slope", 0.5, "Exponential growth a of the value inside the step").range(0.0, 5.0);
        s.addConformance({"default", {}});
        s.addConformance({"1D", {{"dimension", std::int64_t(1)}, {"threshold", 0.3}}});
        s.addConformance({"8D", {{"dimension", std::int64_t(8)}, {"slope", 0.2}}});
        s.addConformance({"corner", {{"dimension", std::int64_t(3)}, {"threshold", 0.1}, {"slope", 0.0}}});
        return s;
    }

    explicit Step(const Properties& p)
        : m_dim(int(p.getInt("dimension"))), m_w(p.getFloat("threshold")), m_a(p.getFloat("slope")) {}

    int dimension() const override { return m_dim; }
    void eval(ISampler& u, std::span<double> out) override {
        double s = 0.0;
        bool inside = true;
        for (int i = 0; i < m_dim; ++i) {
            double x = u.get1D();  // draw every variable so the sample layout is fixed
            if (i < 2 && !(x < m_w)) inside = false;
            s += x;
        }
        out[0] = inside ? std::exp(m_a * s) : 0.0;
    }
    std::optional<std::vector<double>> integral() const override {
        // ∫_0^t e^{a x} dx = expm1(a t)/a, accurate for a → 0 too.
        auto segment = [&](double t) { return m_a > 0.0 ? std::expm1(m_a * t) / m_a : t; };
        double v = 1.0;
        for (int i = 0; i < m_dim; ++i) v *= segment(i < 2 ? m_w : 1.0);
        return std::vector<double>{v};
    }

private:
    int m_dim;
    double m_w, m_a;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Step)
