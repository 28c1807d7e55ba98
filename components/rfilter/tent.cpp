/*
 * rfilter "tent" — the tent (triangle, linear-interpolation) reconstruction filter.
 *
 *   eval(x) = max(0, 1 − |x| / r);   radius r (default 1).
 *
 * The tent is the box convolved with itself (scaled): it reconstructs by linear
 * interpolation between samples and suppresses the box's side lobes as 1/f² instead
 * of 1/f, at the cost of some blur.
 *
 * Parameters (Mitsuba 3 compatible):
 *   radius  float, default 1   support radius in pixels
 * Reference: M. Pharr, W. Jakob, G. Humphreys, Physically Based Rendering, 4th ed.,
 * 2023, §8.8.2 (triangle filter).
 */
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifilter.hpp"

#include <algorithm>
#include <cmath>

namespace effigi {
namespace {

class TentFilter final : public Implements<IFilter> {
public:
    static Schema schema() {
        Schema s("rfilter", "tent", "Tent (triangle) filter: linear interpolation, eval(x) = max(0, 1 - |x|/radius).");
        s.cite("M. Pharr, W. Jakob, G. Humphreys, Physically Based Rendering, 4th ed., 2023, §8.8.2");
        s.real("radius", 1.0, "Support radius").withUnit("pixels").range(0.01, 64.0);
        s.addConformance({"narrow", {{"radius", PropertyValue(0.5)}}});
        s.addConformance({"wide", {{"radius", PropertyValue(4.0)}}});
        return s;
    }
    explicit TentFilter(const Properties& p) : m_radius(p.getFloat("radius")) {
        if (!(m_radius > 0.f))
            failAt(p.whereOf("radius"), "{}: 'radius' must be positive, got {}", p.describe(), m_radius);
    }

    float radius() const override { return m_radius; }
    float eval(float x) const override { return std::max(0.f, 1.f - std::abs(x) / m_radius); }

private:
    float m_radius;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::TentFilter)
