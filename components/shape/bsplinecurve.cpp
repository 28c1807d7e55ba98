// bsplinecurve — tubes of round cross-section along uniform cubic B-splines read from a
// text file, as Mitsuba 3's `bsplinecurve` (Embree's round B-spline curves).
//
// Parameters: filename (required; one control point "x y z radius" per line, a blank line
// starts a new curve, at least 4 points per curve; a curve of n points has n - 3
// segments), to_world (applied to the control points, NOT to the radii, as in Mitsuba),
// flip_normals, nested bsdf. An emitter is refused.
// As in Mitsuba (Embree) the tube is the sweep of a circle of radius r(v) normal to the
// spline, open-ended (cut normal to the end tangents; set the end radii to 0 to close
// it), with back faces culled. It is traced as the sweep of a sphere instead, as a chain
// of round cones through spheres sampled on the spline (curve_common.hpp): off by at most
// 1e-3 of the segment's largest radius (chord-error bound h²/8·(|c''| + |r''|), at most 64
// pieces a segment); the sphere and circle sweeps coincide for constant radius and differ
// by r·k²/2 where the radius changes at rate k = dr/ds. The hit's curve parameter is then
// refined by Newton on the exact spline; normals follow the circle sweep, as Mitsuba's.
// uv = (angle around the tube / 2π, (segment + v) / segments), as Mitsuba.
// Reference: Mitsuba 3 documentation, "B-spline curve (bsplinecurve)"; Embree 3,
// RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE; C. de Boor, "A Practical Guide to Splines", 1978.
#include "curve_common.hpp"

namespace effigi {
namespace {

class BSplineCurve final : public curves::CurveShape {
public:
    static Schema schema() {
        Schema s("shape", "bsplinecurve", "Round open tubes along uniform cubic B-splines with per-point radii.");
        s.cite("Mitsuba 3 documentation, B-spline curve; de Boor, A Practical Guide to Splines, 1978");
        addCurveParams(s);
        return s;
    }

    explicit BSplineCurve(const Properties& p) : CurveShape(p, 4, "B-spline curve") {
        m_sweptCircle = true;
        std::vector<curves::RoundCone> pieces;
        for (std::size_t k = 0; k + 1 < m_file.first.size(); ++k) {
            std::uint32_t a = m_file.first[k], b = m_file.first[k + 1];
            for (std::uint32_t i = a; i + 3 < b; ++i) {
                std::uint32_t seg = std::uint32_t(m_segmentStart.size());
                m_segmentStart.push_back(i);
                bool firstSeg = i == a;
                // c'' and r'' are linear in v: their largest norms are at the ends.
                curves::CurvePoint e0 = eval(seg, 0.0), e1 = eval(seg, 1.0);
                double bend = std::max(glm::length(e0.ddc), glm::length(e1.ddc)) +
                              std::max(std::abs(e0.ddr), std::abs(e1.ddr));
                double rMax = 0.0, extent = 0.0;
                for (std::uint32_t j = i; j < i + 4; ++j) {
                    rMax = std::max(rMax, m_file.points[j].r);
                    extent = std::max(extent, glm::length(m_file.points[j].p - m_file.points[i].p));
                }
                double tol = curves::CurveTolerance * std::max(rMax, 1e-6 * extent);
                int n = tol > 0.0 ? int(std::ceil(std::sqrt(bend / (8.0 * tol)))) : 1;
                n = std::clamp(n, 1, MaxPieces);
                curves::CurvePoint prev = e0;
                for (int q = 0; q < n; ++q) {
                    double v1 = double(q + 1) / n;
                    curves::CurvePoint next = q + 1 == n ? e1 : eval(seg, v1);
                    // Inner joints: the sphere is traced once, by the piece ending there.
                    pieces.push_back({prev.c, next.c, prev.r, next.r, seg, float(double(q) / n), float(v1),
                                      firstSeg && q == 0, true});
                    prev = next;
                }
            }
        }
        std::vector<curves::EndCut> cuts = cutOpenEnds(pieces);
        setPieces(std::move(pieces), m_segmentStart.size(), std::move(cuts));
    }

protected:
    /// Uniform cubic B-spline basis (de Boor) and its derivatives, on position and radius.
    curves::CurvePoint eval(std::uint32_t segment, double v) const override {
        const curves::ControlPoint* c = &m_file.points[m_segmentStart[segment]];
        double w = 1.0 - v;
        double b[4] = {w * w * w / 6.0, (3.0 * v * v * v - 6.0 * v * v + 4.0) / 6.0,
                       (-3.0 * v * v * v + 3.0 * v * v + 3.0 * v + 1.0) / 6.0, v * v * v / 6.0};
        double db[4] = {-0.5 * w * w, 1.5 * v * v - 2.0 * v, -1.5 * v * v + v + 0.5, 0.5 * v * v};
        double ddb[4] = {w, 3.0 * v - 2.0, -3.0 * v + 1.0, v};
        curves::CurvePoint r{Vector3d(0.0), Vector3d(0.0), Vector3d(0.0), 0.0, 0.0, 0.0};
        for (int k = 0; k < 4; ++k) {
            r.c += b[k] * c[k].p, r.dc += db[k] * c[k].p, r.ddc += ddb[k] * c[k].p;
            r.r += b[k] * c[k].r, r.dr += db[k] * c[k].r, r.ddr += ddb[k] * c[k].r;
        }
        return r;
    }

private:
    /// Embree's round B-spline tubes are open, cut perpendicular to the end tangents.
    /// Every piece whose spheres reach across a curve's end plane (near that end) is cut
    /// there, or the spheres of short pieces would round the end off.
    std::vector<curves::EndCut> cutOpenEnds(std::vector<curves::RoundCone>& pieces) const {
        std::vector<curves::EndCut> cuts;
        std::size_t firstPiece = 0;
        for (std::size_t k = 0; k + 1 < m_file.first.size(); ++k) {
            std::uint32_t segs = m_file.first[k + 1] - m_file.first[k] - 3;
            std::size_t end = firstPiece;
            std::uint32_t lastSeg = pieces[firstPiece].segment + segs - 1;
            while (end < pieces.size() && pieces[end].segment <= lastSeg) ++end;
            curves::CurvePoint a = eval(pieces[firstPiece].segment, 0.0), b = eval(lastSeg, 1.0);
            // (A degenerate end with no tangent is left uncut.)
            auto unit = [](const Vector3d& v) { return glm::length(v) > 0.0 ? v / glm::length(v) : Vector3d(0.0); };
            Vector3d ta = unit(a.dc), tb = unit(b.dc);
            for (std::size_t i = firstPiece; i < end; ++i) {
                curves::RoundCone& c = pieces[i];
                auto reaches = [&](const Vector3d& centre, double r, const Vector3d& at, double rAt, const Vector3d& t) {
                    return std::abs(glm::dot(centre - at, t)) < r && glm::length(centre - at) < 2.0 * (r + rAt);
                };
                curves::EndCut cut;
                if (reaches(c.p0, c.r0, a.c, a.r, ta) || reaches(c.p1, c.r1, a.c, a.r, ta))
                    cut.startCut = ta, cut.startAt = a.c;
                if (reaches(c.p0, c.r0, b.c, b.r, tb) || reaches(c.p1, c.r1, b.c, b.r, tb))
                    cut.endCut = tb, cut.endAt = b.c;
                if (cut.startCut == Vector3d(0.0) && cut.endCut == Vector3d(0.0)) continue;
                c.cut = std::uint32_t(cuts.size());
                cuts.push_back(cut);
            }
            firstPiece = end;
        }
        return cuts;
    }

    // Per segment (memory: ~120 bytes a piece). Reached only for radii far below the
    // curvature radius; there the deviation is h²/8·bend with h = 1/64 instead.
    static constexpr int MaxPieces = 64;
    std::vector<std::uint32_t> m_segmentStart;  // first control point of each segment
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::BSplineCurve)
