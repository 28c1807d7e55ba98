// linearcurve — tubes of round cross-section along polylines read from a text file, as
// Mitsuba 3's `linearcurve` (Embree's round linear curves).
//
// Parameters: filename (required; one control point "x y z radius" per line, a blank line
// starts a new curve, at least 2 points per curve), to_world (applied to the control
// points, NOT to the radii, as in Mitsuba), flip_normals, nested bsdf. An emitter is refused.
// Each segment is the convex hull of the spheres at its two control points (the cone
// tangent to both plus the spheres), so joints are smooth spherical blends and the curve
// ends are hemispherical caps. Intersection is exact (curve_common.hpp). Back faces are
// culled: a ray starting inside the tube does not hit it (Mitsuba's note).
// uv = (angle around the tube / 2π, (segment + v) / segments) with v the parameter of the
// sphere that touches the hit point, measured from Mitsuba's frame (z made perpendicular
// to the axis).
// Reference: Mitsuba 3 documentation, "Linear curve (linearcurve)"; Embree 3,
// RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE; M. Han et al., "Ray Tracing Generalized Tube
// Primitives", EuroVis 2019.
#include "curve_common.hpp"

namespace effigi {
namespace {

class LinearCurve final : public curves::CurveShape {
public:
    static Schema schema() {
        Schema s("shape", "linearcurve",
                 "Round tubes along polylines with per-point radii, spherical joints and end caps.");
        s.cite("Mitsuba 3 documentation, Linear curve; Han et al., Ray Tracing Generalized Tube Primitives, 2019");
        addCurveParams(s);
        return s;
    }

    explicit LinearCurve(const Properties& p) : CurveShape(p, 2, "linear curve") {
        std::vector<curves::RoundCone> pieces;
        for (std::size_t k = 0; k + 1 < m_file.first.size(); ++k) {
            std::uint32_t a = m_file.first[k], b = m_file.first[k + 1];
            for (std::uint32_t i = a; i + 1 < b; ++i) {
                m_segmentStart.push_back(i);
                const curves::ControlPoint &c0 = m_file.points[i], &c1 = m_file.points[i + 1];
                // Every joint sphere is traced once, with the segment that ends there.
                pieces.push_back({c0.p, c1.p, c0.r, c1.r, std::uint32_t(m_segmentStart.size() - 1), 0.f, 1.f,
                                  i == a, true});
            }
        }
        setPieces(std::move(pieces), m_segmentStart.size());
    }

protected:
    curves::CurvePoint eval(std::uint32_t segment, double v) const override {
        std::uint32_t i = m_segmentStart[segment];
        const curves::ControlPoint &c0 = m_file.points[i], &c1 = m_file.points[i + 1];
        return {(1.0 - v) * c0.p + v * c1.p, c1.p - c0.p, Vector3d(0.0),
                (1.0 - v) * c0.r + v * c1.r, c1.r - c0.r, 0.0};
    }

private:
    std::vector<std::uint32_t> m_segmentStart;  // first control point of each segment
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::LinearCurve)
