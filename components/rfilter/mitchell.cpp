/*
 * rfilter "mitchell" — the Mitchell–Netravali family of cubic filters.
 *
 * A piecewise cubic k(x) on |x| < 2 (radius 2), chosen by Mitchell and Netravali so
 * that it is C¹, interpolates a constant exactly, and trades blur (B) against ringing
 * (C):
 *
 *   6·k(x) = (12 − 9B − 6C)|x|³ + (−18 + 12B + 6C)|x|² + (6 − 2B)              |x| < 1
 *          = (−B − 6C)|x|³ + (6B + 30C)|x|² + (−12B − 48C)|x| + (8B + 24C)     1 <= |x| < 2
 *          = 0                                                                 otherwise
 *
 * B = C = 1/3 is the authors' recommendation; B = 0, C = 1/2 is Catmull–Rom. The
 * negative lobes (for C > 0) sharpen edges; weight sums can then be small or negative
 * near isolated samples, which the film handles by dividing by the signed weight.
 *
 * Parameters (Mitsuba 3 compatible):
 *   B  float, default 1/3
 *   C  float, default 1/3
 * Reference: D. P. Mitchell, A. N. Netravali, "Reconstruction Filters in Computer
 * Graphics", SIGGRAPH 1988, 221–228.
 */
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifilter.hpp"

#include <cmath>

namespace effigi {
namespace {

class MitchellFilter final : public Implements<IFilter> {
public:
    static Schema schema() {
        Schema s("rfilter", "mitchell", "Mitchell-Netravali cubic filter of radius 2 with parameters B and C.");
        s.cite("D. P. Mitchell, A. N. Netravali, Reconstruction Filters in Computer Graphics, SIGGRAPH 1988");
        s.real("B", 1.0 / 3.0, "Blur parameter B").range(-10.0, 10.0);
        s.real("C", 1.0 / 3.0, "Ringing parameter C").range(-10.0, 10.0);
        s.addConformance({"catmullrom", {{"B", PropertyValue(0.0)}, {"C", PropertyValue(0.5)}}});
        s.addConformance({"bspline", {{"B", PropertyValue(1.0)}, {"C", PropertyValue(0.0)}}});
        return s;
    }
    explicit MitchellFilter(const Properties& p) : m_b(p.getFloat("B")), m_c(p.getFloat("C")) {}

    float radius() const override { return 2.f; }
    float eval(float x) const override {
        const float a = std::abs(x), a2 = a * a, a3 = a2 * a;
        const float B = m_b, C = m_c;
        if (a < 1.f)
            return ((12.f - 9.f * B - 6.f * C) * a3 + (-18.f + 12.f * B + 6.f * C) * a2 + (6.f - 2.f * B)) *
                   (1.f / 6.f);
        if (a < 2.f)
            return ((-B - 6.f * C) * a3 + (6.f * B + 30.f * C) * a2 + (-12.f * B - 48.f * C) * a +
                    (8.f * B + 24.f * C)) *
                   (1.f / 6.f);
        return 0.f;
    }

private:
    float m_b, m_c;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::MitchellFilter)
