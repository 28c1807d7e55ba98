#pragma once
// Shared machinery of the curve shapes (linearcurve, bsplinecurve): the round-cone
// primitive both are traced with, a per-shape BVH over those primitives, and the shape
// base that turns a hit into a SurfaceInteraction (the file reader: curve_file.hpp).
//
// Geometry. Everything is traced as "round cones": the convex hull of two spheres, i.e.
// the sweep of a sphere whose centre and radius move linearly (the cone tangent to both
// spheres plus the spheres). That is exactly Embree's (hence Mitsuba 3's) round linear
// curve segment. A cubic B-spline segment is split into pieces of equal parameter width h,
// each a round cone between spheres on the spline; (c, r) then deviate from the spline by
// at most h²/8·max(|c''| + |r''|) (chord error), and h keeps that below CurveTolerance ×
// the segment's largest radius. Embree's B-spline tube is the sweep of a circle normal to
// the curve rather than of a sphere; the two coincide for constant radius and differ by
// r·k²/2 in radius where the radius changes at rate k = dr/ds along the arc (0.5 % of r at
// k = 0.1; hair and most curve data have k ≪ 0.1).
//
// Conventions (Mitsuba 3): control points are transformed by to_world, radii are not;
// back faces are culled (a ray starting inside the tube does not hit its wall); uv.x runs
// around the tube, uv.y along all segments of the file, (v_local + segment) / segments.
//
// References: Embree 3, round linear curves (cone tangent to the end spheres); M. Han et
// al., "Ray Tracing Generalized Tube Primitives: Method and Applications", EuroVis 2019
// (tangent cone of two spheres); Mitsuba 3 documentation, "Linear curve", "B-spline curve".
#include "curve_file.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/input.hpp"
#include "effigi/render/shape_base.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace effigi::curves {

/// Largest surface deviation of a B-spline segment's piecewise round-cone approximation,
/// relative to the segment's largest radius.
inline constexpr double CurveTolerance = 1e-3;

inline constexpr std::uint32_t NoCut = 0xffffffffu;

/// Open spline ends, cut normal to the curve: kept are q with (q - startAt)·startCut >= 0
/// and (q - endAt)·endCut <= 0 (zero vectors cut nothing).
struct EndCut {
    Vector3d startCut{0.0}, endCut{0.0}, startAt{0.0}, endAt{0.0};
    bool keeps(const Vector3d& q) const {
        return glm::dot(q - startAt, startCut) >= 0.0 && glm::dot(q - endAt, endCut) <= 0.0;
    }
};

/// The convex hull of sphere (p0, r0) and sphere (p1, r1): the sweep of a sphere moving
/// linearly from one to the other. withStart / withEnd say whether the end spheres belong
/// to the surface (a joint sphere is traced by one of its two pieces).
struct RoundCone {
    Vector3d p0, p1;
    double r0, r1;
    std::uint32_t segment;  ///< the segment of the file this piece approximates
    float v0, v1;           ///< its parameter range within the segment
    bool withStart, withEnd;
    std::uint32_t cut = NoCut;  ///< index of its EndCut (pieces near an open end only)
    Vector3d nextAxis{0.0};     ///< unit axis of the piece continuing this one (zero: none)
    double nextSin = 0.0;       ///< and the sine of its cone's half-angle
    /// Whether a point of an end sphere is on the chain's surface, not inside this or the
    /// next piece's cone (beyond the circles where they touch the sphere). Embree cuts the
    /// neighbours' cones away likewise; it matters for rays entering through an open end.
    bool exposed(const Vector3d& q, bool atStart) const {
        double L = glm::length(p1 - p0), sinA = L > 0.0 ? (r0 - r1) / L : 0.0;
        if (L > std::abs(r0 - r1) && (atStart ? glm::dot(q - p0, p1 - p0) > L * r0 * sinA
                                              : glm::dot(q - p1, p1 - p0) < L * r1 * sinA))
            return false;
        return atStart || glm::dot(q - p1, nextAxis) <= r1 * nextSin;
    }

    BBox3f bounds() const {
        BBox3f b(Point3f(p0 - r0), Point3f(p0 + r0));
        b.expand(BBox3f(Point3f(p1 - r1), Point3f(p1 + r1)));
        // One float ulp of rounding on each side, relative to the magnitude.
        Vector3f pad = 1e-6f * (glm::abs(b.min) + glm::abs(b.max)) + 1e-30f;
        return {b.min - pad, b.max + pad};
    }
};

/// Nearest entry t (o is outside) into a sphere, or none; back faces are culled.
inline bool enterSphere(const Vector3d& o, const Vector3d& d, const Vector3d& ctr, double r, double& t) {
    Vector3d oc = o - ctr;
    double a = glm::dot(d, d), b = glm::dot(oc, d);
    Vector3d perp = oc - (b / a) * d;  // stable discriminant (Ray Tracing Gems ch. 7)
    double disc = a * (r * r - glm::dot(perp, perp));
    if (!(disc >= 0.0) || !(r > 0.0)) return false;
    double q = -(b + std::copysign(std::sqrt(disc), b));
    if (q == 0.0) return false;
    t = std::min((glm::dot(oc, oc) - r * r) / q, q / a);
    return true;
}

/// Closest front-facing entry into the round cone with t in (0, tMax); s in [0, 1] is the
/// sweep parameter of the sphere touching the hit point.
inline bool intersectRoundCone(const RoundCone& c, const EndCut* cut, const Vector3d& oIn, const Vector3d& d,
                               double tMax, double& tHit, double& sHit) {
    auto keeps = [cut](const Vector3d& q) { return !cut || cut->keeps(q); };
    // Solve from the ray point nearest the piece: keeps the quadratics well conditioned
    // for distant origins.
    Vector3d mid = 0.5 * (c.p0 + c.p1);
    double dd = glm::dot(d, d);
    double tc = glm::dot(mid - oIn, d) / dd;
    Vector3d o = oIn + tc * d;
    bool found = false;
    double best = tMax, t;
    for (int end = 0; end < 2; ++end)
        if ((end ? c.withEnd : c.withStart) && enterSphere(o, d, end ? c.p1 : c.p0, end ? c.r1 : c.r0, t) &&
            t + tc > 0.0 && t + tc < best && keeps(o + t * d) && c.exposed(o + t * d, end == 0))
            best = t + tc, sHit = double(end), found = true;

    // The cone tangent to both spheres, half-angle α with sin α = (r0 - r1) / L: in
    // coordinates x along the axis from p0 and ρ from it, ρ cos α = r0 - x sin α, touching
    // the spheres for x in [r0 sin α, L + r1 sin α].
    Vector3d axis = c.p1 - c.p0;
    double L = glm::length(axis);
    if (L > std::abs(c.r0 - c.r1) && (c.r0 > 0.0 || c.r1 > 0.0)) {
        Vector3d a = axis / L;
        double sinA = (c.r0 - c.r1) / L, cos2 = (1.0 - sinA) * (1.0 + sinA);
        Vector3d w = o - c.p0;
        double wx = glm::dot(w, a), dx = glm::dot(d, a);
        // F(t) = cos²α |q|² - x² + 2 r0 sin α x - r0² (negative inside): F = A t² + 2B t + C.
        double A = cos2 * dd - dx * dx;
        double B = cos2 * glm::dot(w, d) - wx * dx + c.r0 * sinA * dx;
        double C = cos2 * glm::dot(w, w) - wx * wx + 2.0 * c.r0 * sinA * wx - c.r0 * c.r0;
        double roots[2], disc = B * B - A * C, q = -(B + std::copysign(std::sqrt(std::max(disc, 0.0)), B));
        int n = 0;
        if (std::abs(A) < 1e-12 * dd) {  // ray parallel to a generator line: linear
            if (B != 0.0) roots[n++] = -C / (2.0 * B);
        } else if (disc >= 0.0) {
            roots[n++] = q / A;
            if (q != 0.0) roots[n++] = C / q;
        }
        for (int i = 0; i < n; ++i) {
            double tr = roots[i], x = wx + tr * dx;
            double lo = c.r0 * sinA, hi = L + c.r1 * sinA;
            // Entering (F decreasing), on the right nappe, between the touching circles.
            if (A * tr + B < 0.0 && c.r0 - x * sinA > 0.0 && x >= lo && x <= hi && tr + tc > 0.0 &&
                tr + tc < best && keeps(o + tr * d))
                best = tr + tc, sHit = std::clamp((x - lo) / (L * cos2), 0.0, 1.0), found = true;
        }
    }
    if (found) tHit = best;
    return found;
}

/// Bounding-volume hierarchy over the round cones of one shape (median split on the
/// longest axis of the centroids).
class ConeBvh {
public:
    void build(std::vector<RoundCone> pieces, std::vector<EndCut> cuts) {
        m_pieces = std::move(pieces), m_cuts = std::move(cuts);
        m_nodes.clear();
        if (!m_pieces.empty()) buildNode(0, std::uint32_t(m_pieces.size()));
    }

    /// Closest hit in (0, ray.tMax): piece index and sweep parameter (front to back order
    /// is not needed: leaves shrink `best`, which culls the remaining boxes).
    bool intersect(const Ray& ray, double& tHit, std::uint32_t& piece, double& s) const {
        if (m_nodes.empty()) return false;
        Vector3d o(ray.o), d(ray.d);
        Vector3f inv = 1.f / ray.d;
        double best = ray.tMax;
        bool found = false;
        std::uint32_t stack[64], top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const Node& node = m_nodes[stack[--top]];
            if (!hitsBox(node.box, ray.o, inv, float(best))) continue;
            if (node.count > 0) {
                for (std::uint32_t i = node.start; i < node.start + node.count; ++i) {
                    double t, si;
                    const RoundCone& c = m_pieces[i];
                    if (intersectRoundCone(c, c.cut == NoCut ? nullptr : &m_cuts[c.cut], o, d, best, t, si)) {
                        best = t, piece = i, s = si, found = true;
                    }
                }
            } else {
                stack[top++] = node.right;
                stack[top++] = std::uint32_t(&node - m_nodes.data()) + 1;
            }
        }
        if (found) tHit = best;
        return found;
    }

    const std::vector<RoundCone>& pieces() const { return m_pieces; }
    BBox3f bbox() const { return m_nodes.empty() ? BBox3f() : m_nodes[0].box; }

private:
    struct Node {
        BBox3f box;
        std::uint32_t start = 0, count = 0;  ///< leaf: pieces [start, start+count); inner: count 0
        std::uint32_t right = 0;             ///< inner: the second child (the first is next)
    };

    /// Slab test; NaN from 0·inf compares false and keeps the box (conservative).
    static bool hitsBox(const BBox3f& b, const Point3f& o, const Vector3f& inv, float tMax) {
        float t0 = 0.f, t1 = tMax;
        for (int k = 0; k < 3; ++k) {
            float a = (b.min[k] - o[k]) * inv[k], c = (b.max[k] - o[k]) * inv[k];
            if (a > c) std::swap(a, c);
            if (a > t0) t0 = a;
            if (c * (1.f + 4e-7f) < t1) t1 = c * (1.f + 4e-7f);  // rounding slack
        }
        return t0 <= t1;
    }

    /// Median split: depth <= log2(n) + 1, far below the traversal stack's 64.
    std::uint32_t buildNode(std::uint32_t begin, std::uint32_t end) {
        std::uint32_t index = std::uint32_t(m_nodes.size());
        m_nodes.emplace_back();
        BBox3f box, centres;
        for (std::uint32_t i = begin; i < end; ++i) {
            BBox3f b = m_pieces[i].bounds();
            box.expand(b), centres.expand(b.center());
        }
        m_nodes[index].box = box;
        if (end - begin <= 2) {
            m_nodes[index].start = begin, m_nodes[index].count = end - begin;
            return index;
        }
        Vector3f ext = centres.extents();
        int axis = ext.x > ext.y ? (ext.x > ext.z ? 0 : 2) : (ext.y > ext.z ? 1 : 2);
        std::uint32_t mid = (begin + end) / 2;
        std::nth_element(m_pieces.begin() + begin, m_pieces.begin() + mid, m_pieces.begin() + end,
                         [axis](const RoundCone& a, const RoundCone& b) {
                             return a.p0[axis] + a.p1[axis] < b.p0[axis] + b.p1[axis];
                         });
        buildNode(begin, mid);
        m_nodes[index].right = buildNode(mid, end);
        return index;
    }

    std::vector<RoundCone> m_pieces;
    std::vector<EndCut> m_cuts;
    std::vector<Node> m_nodes;
};

/// Centre, radius and their first two derivatives along a segment at parameter v.
struct CurvePoint {
    Vector3d c, dc, ddc;
    double r, dr, ddr;
};

/// Base of both curve shapes: reads the file, traces the pieces, builds interactions.
class CurveShape : public ShapeBase {
public:
    static void addCurveParams(Schema& s) {
        s.optional("filename", ParamType::String,
                   "Control points 'x y z radius' per line, blank lines between curves; relative to the scene file")
            .isRequired();
        addCommonParams(s);
        // effigi-conform: the two curves of tests/data/curves, also stretched far away.
        const std::string file = "tests/data/curves/curves.txt";
        s.addConformance({"default", {{"filename", file}}});
        s.addConformance({"stretched far", {{"filename", file}, {"to_world", Transform::translate({1e3f, 0.f, 0.f}) *
                                                                               Transform::scale({1e2f, 1.f, 1.f})}}});
    }

    CurveShape(const Properties& p, std::size_t minPoints, const char* kind) : ShapeBase(p) {
        if (m_emitter)
            failAt(p.whereOf("emitter"), "{}: a {} cannot be an area emitter (as in Mitsuba 3, curves "
                   "have no area sampling)", p.describe(), kind);
        std::string file = p.getPath("filename").string();
        try {
            regularFileSize(file, fmt::format("{} file", kind));  // no device, FIFO, folder: getline reads to the end
            m_file = readCurveFile(file, m_toWorld, minPoints, kind);
        } catch (const Error& e) {  // the file's own problem, prefixed with where the scene names it
            failAt(p.whereOf("filename"), "{}: {}", p.describe(), e.what());
        }
        m_fileName = file;
    }

    BBox3f bbox() const override { return m_bvh.bbox(); }
    /// Lateral area of the traced pieces (the spherical joints are not counted).
    float area() const override { return m_area; }
    /// Curves cannot be emitters (the constructor refuses one): a sample of density zero.
    PositionSample samplePosition(const Point2f&) const override { return {}; }

    /// uv carries (piece index, sweep parameter) to interaction(); float holds piece
    /// indices exactly up to 2^24, which setPieces() enforces.
    bool intersect(const Ray& ray, float& t, Point2f& uv) const override {
        double th, s;
        std::uint32_t piece;
        if (!m_bvh.intersect(ray, th, piece, s) || !(float(th) > 0.f) || !(float(th) < ray.tMax)) return false;
        t = float(th), uv = Point2f(float(piece), float(s));
        return true;
    }

    SurfaceInteraction interaction(const Ray& ray, const Hit& hit) const override {
        const RoundCone& pc = m_bvh.pieces()[std::min<std::size_t>(std::size_t(hit.uv.x), m_bvh.pieces().size() - 1)];
        Vector3d p = Vector3d(ray.o) + double(hit.t) * Vector3d(ray.d);
        // The curve parameter of p, by Newton from the piece's estimate, kept in [0, 1]:
        // for a swept sphere (linear) the sphere touching p, (p - c)·c' + r r' = 0; for a
        // swept circle (spline, as Embree) the foot of the perpendicular, (p - c)·c' = 0.
        double lambda = m_sweptCircle ? 0.0 : 1.0;
        double v = pc.v0 + double(hit.uv.y) * (pc.v1 - pc.v0);
        CurvePoint cp = eval(pc.segment, v);
        for (int it = 0; it < 8; ++it) {
            Vector3d w = p - cp.c;
            double g = glm::dot(w, cp.dc) + lambda * cp.r * cp.dr;
            double dg = -glm::dot(cp.dc, cp.dc) + glm::dot(w, cp.ddc) + lambda * (cp.dr * cp.dr + cp.r * cp.ddr);
            if (!(dg < 0.0)) break;  // not a maximum-distance configuration: keep the estimate
            double vn = std::clamp(v - g / dg, 0.0, 1.0);
            std::swap(v, vn);
            cp = eval(pc.segment, v);
            if (std::abs(vn - v) < 1e-9) break;
        }
        Vector3d radial = p - cp.c;
        double len = glm::length(radial);
        // Coincident control points leave no direction: any tangent keeps uv finite.
        Vector3d tangent = glm::length(cp.dc) > 0.0 ? glm::normalize(cp.dc) : Vector3d(1, 0, 0);
        Vector3d n = len > 0.0 ? radial / len : Vector3d(0, 0, 1), ng = n;
        // Normal of the swept circle p = c(v) + r(v) e, e ⟂ c'(v): the radial direction
        // tilted by the radius change and the curvature (as Mitsuba's bsplinecurve).
        Vector3d m = (glm::dot(cp.dc, cp.dc) - glm::dot(radial, cp.ddc)) * radial - (cp.dr * cp.r) * cp.dc;
        if (m_sweptCircle && glm::length(m) > 0.0) ng = glm::normalize(m);

        SurfaceInteraction si;
        si.t = hit.t;
        // Exact for linear curves (the pieces are the surface); within the tolerance for splines.
        si.p = Point3f(len > 0.0 && !m_sweptCircle ? cp.c + cp.r * n : p);
        si.prim = pc.segment;
        si.primUV = Point2f(float(v), 0.f);
        // Mitsuba's frame around the tangent: "rot" is the z axis made perpendicular to it.
        Vector3d rot = Vector3d(0, 0, 1) - tangent * tangent.z;
        rot = glm::length(rot) > 1e-12 ? glm::normalize(rot) : Vector3d(0, 1, 0);
        double u = std::atan2(glm::dot(rot, n), glm::dot(glm::cross(rot, tangent), n)) * (0.5 / double(Pi));
        u += u < 0.0 ? 1.0 : 0.0;
        si.uv = Point2f(std::min(float(u), OneMinusEpsilon), float((v + pc.segment) / double(m_segments)));
        si.dpdu = Vector3f(2.0 * double(Pi) * glm::cross(tangent, cp.r * n));
        si.dpdv = Vector3f(double(m_segments) * (cp.dc + cp.dr * n));
        Vector3f nf = normalize(Vector3f(ng));
        si.n = m_flipNormals ? -nf : nf;
        Vector3f s = si.dpdu - si.n * dot(si.n, si.dpdu);
        si.shading = dot(s, s) > 1e-20f ? Frame(normalize(s), cross(si.n, normalize(s)), si.n) : Frame(si.n);
        finish(si, ray);
        return si;
    }

protected:
    /// Called at the end of the subclass constructor with the segments' pieces.
    void setPieces(std::vector<RoundCone> pieces, std::size_t segments, std::vector<EndCut> cuts = {}) {
        if (pieces.size() >= (1u << 24))  // interaction() receives the index as a float
            failAt({m_fileName, 0}, "too many curve segments ({} pieces; at most 2^24)", pieces.size());
        double area = 0.0;
        for (const RoundCone& c : pieces)
            area += double(Pi) * (c.r0 + c.r1) * std::hypot(glm::length(c.p1 - c.p0), c.r1 - c.r0);
        m_area = float(area);
        // Chain each piece to the one continuing it (same joint sphere, no own start sphere).
        for (std::size_t i = 0; i + 1 < pieces.size(); ++i) {
            const RoundCone& n = pieces[i + 1];
            double L = glm::length(n.p1 - n.p0);
            if (n.withStart || n.p0 != pieces[i].p1 || n.r0 != pieces[i].r1 || !(L > std::abs(n.r0 - n.r1))) continue;
            pieces[i].nextAxis = (n.p1 - n.p0) / L;
            pieces[i].nextSin = (n.r0 - n.r1) / L;
        }
        m_segments = segments;
        m_bvh.build(std::move(pieces), std::move(cuts));
    }
    virtual CurvePoint eval(std::uint32_t segment, double v) const = 0;

    CurveFile m_file;
    bool m_sweptCircle = false;  ///< spline convention (see interaction())
    std::string m_fileName;

private:
    ConeBvh m_bvh;
    float m_area = 0.f;
    std::size_t m_segments = 0;
};

} // namespace effigi::curves
