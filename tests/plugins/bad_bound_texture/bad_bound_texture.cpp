// texture "bad_bound_texture" — DELIBERATELY WRONG test plugin: a reflectance that varies
// along u as a periodic Catmull–Rom spline through the control values 0.2, 0.8, 1, 0.5
// (one period per unit of u, constant in v), whose maxValue() is the largest control value,
// 1. A Catmull–Rom spline passes through its control values but is not bounded by them:
// it overshoots to 1.012 after the 1.
//
// Everything else is right: readings are finite everywhere (uv wraps; non-finite uv reads
// as 0), non-negative (the spline dips to 0.19, not below 0), mean() is the exact average
// (for a periodic Catmull–Rom spline, that of its control values), evalFloat() is the
// mean of the flat spectrum eval() returns, and the gradient is the spline's derivative.
// So the texture suite must fail "bounded" alone (tests/plugins/run_plugin_tests.cmake).
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/itexture.hpp"

#include <algorithm>
#include <cmath>

namespace {
using namespace effigi;

class BadBoundTexture final : public Implements<ITexture> {
public:
    static Schema schema() {
        Schema s("texture", "bad_bound_texture",
                 "Test plugin: a spline reflectance along u whose maxValue() ignores the spline's overshoot.");
        s.addConformance({"default", {}});
        return s;
    }

    explicit BadBoundTexture(const Properties&) {}

    SampledSpectrum eval(const SurfaceInteraction& si, const SampledWavelengths&) const override {
        return SampledSpectrum(evalFloat(si));
    }
    float evalFloat(const SurfaceInteraction& si) const override { return spline(si.uv.x, false); }
    Vector2f evalFloatGradient(const SurfaceInteraction& si) const override {
        return Vector2f(spline(si.uv.x, true), 0.f);
    }

    /// The bug: the largest control value, not the largest value of the spline.
    float maxValue() const override { return *std::max_element(std::begin(C), std::end(C)); }
    /// Over a period every control value enters a periodic Catmull–Rom spline's integral
    /// with weight 13/24 + 13/24 − 1/24 − 1/24 = 1: the mean is that of the control values.
    float mean() const override { return (C[0] + C[1] + C[2] + C[3]) / float(N); }

private:
    static constexpr int N = 4;
    static constexpr float C[N] = {0.2f, 0.8f, 1.f, 0.5f};

    /// The spline at u (or its derivative ∂/∂u), u wrapped into [0, 1).
    static float spline(float u, bool derivative) {
        if (!std::isfinite(u)) u = 0.f;
        float x = (u - std::floor(u)) * float(N);
        int i = std::clamp(int(x), 0, N - 1);
        float t = std::clamp(x - float(i), 0.f, 1.f);
        const float p0 = C[(i + N - 1) % N], p1 = C[i], p2 = C[(i + 1) % N], p3 = C[(i + 2) % N];
        // q(t) = ½ (2 p1 + a t + b t² + c t³), the Catmull–Rom segment from p1 to p2.
        const float a = p2 - p0, b = 2.f * p0 - 5.f * p1 + 4.f * p2 - p3, c = -p0 + 3.f * p1 - 3.f * p2 + p3;
        if (derivative) return 0.5f * (a + 2.f * b * t + 3.f * c * t * t) * float(N);
        return 0.5f * (2.f * p1 + t * (a + t * (b + t * c)));
    }
};

} // namespace

EFFIGI_EXPORT_COMPONENT(BadBoundTexture)
