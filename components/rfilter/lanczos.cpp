/*
 * rfilter "lanczos" — the Lanczos-windowed sinc filter.
 *
 *   eval(x) = sinc(πx) · sinc(πx / n)   for |x| < n,   0 otherwise,
 *   sinc(t) = sin(t) / t,  sinc(0) = 1,  radius n = lobes.
 *
 * The sinc is the ideal low-pass reconstruction filter for band-limited signals;
 * windowing it with the central lobe of a wider sinc gives a finite support with
 * little ringing. Sharpest of the filters here; its negative lobes can ring at edges.
 *
 * Parameters (Mitsuba 3 compatible):
 *   lobes  int, default 3   number of sinc lobes on each side (= radius in pixels)
 * Reference: C. E. Duchon, "Lanczos Filtering in One and Two Dimensions", Journal of
 * Applied Meteorology 18(8), 1979, 1016–1022; K. Turkowski, "Filters for Common
 * Resampling Tasks", Graphics Gems, 1990.
 */
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifilter.hpp"

#include <cmath>

namespace effigi {
namespace {

class LanczosFilter final : public Implements<IFilter> {
public:
    static Schema schema() {
        Schema s("rfilter", "lanczos", "Lanczos-windowed sinc filter with the given number of lobes.");
        s.cite("C. E. Duchon, Lanczos Filtering in One and Two Dimensions, J. Appl. Meteorology 18(8), 1979");
        s.integer("lobes", 3, "Number of sinc lobes on each side; also the support radius").withUnit("pixels").range(1, 32);
        s.addConformance({"two-lobes", {{"lobes", PropertyValue(std::int64_t(2))}}});
        return s;
    }
    explicit LanczosFilter(const Properties& p) {
        std::int64_t lobes = p.getInt("lobes");
        if (lobes < 1 || lobes > 32)
            failAt(p.whereOf("lobes"), "{}: 'lobes' must be in [1, 32], got {}", p.describe(), lobes);
        m_lobes = float(lobes);
    }

    float radius() const override { return m_lobes; }
    float eval(float x) const override {
        const float a = std::abs(x);
        if (a >= m_lobes) return 0.f;
        return sinc(Pi * a) * sinc(Pi * a / m_lobes);
    }

private:
    static float sinc(float t) {
        // Below 1e-4 the Taylor series 1 − t²/6 is exact to float precision, and it
        // avoids 0/0 at the centre.
        return t < 1e-4f ? 1.f - t * t * (1.f / 6.f) : std::sin(t) / t;
    }
    float m_lobes = 3.f;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::LanczosFilter)
