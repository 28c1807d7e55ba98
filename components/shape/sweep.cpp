// sweep — a tube: a circle or a closed 2-D profile swept along a helix or along a smooth
// curve through points, generated as a triangle mesh.
//
// Parameters: radius (of the circle) and sides (its segments), or profile (a closed
// polygon "x0 y0, x1 y1, ..." in the plane normal to the path, either orientation);
// path = helix (helix_radius, pitch: rise per turn, turns; about the z axis, starting at
// (helix_radius, 0, 0)) or points ("x y z, ...": a uniform Catmull–Rom spline through
// them, open); samples (path steps per helix turn, or per segment between points); caps
// (close both ends with flat fans: the profile must be star-shaped about its centroid);
// to_world, flip_normals, face_normals, bsdf, emitter.
//
// The profile is carried by rotation-minimising frames computed with the double
// reflection method of Wang et al. 2008 (fourth-order accurate), so the tube does not
// twist about the path as Frenet frames do (and does not flip where the curvature
// vanishes). For such frames the surface normal is exactly the profile's 2-D normal
// placed in the frame (the frame's derivative along the path is parallel to the
// tangent), which is what the vertices carry; polygon profiles keep their corners sharp.
// Mesh, not analytic: a swept tube has no closed-form intersection; the mesh gets every
// accelerator and exact area sampling. Chord error: a circle is inscribed with `sides`
// segments (area factor sin(π/n)/(π/n)), the path with `samples` steps. A tube wider than
// the path's radius of curvature intersects itself (warned). uv = (position around the
// profile, position along the path), both in [0, 1]; caps map the profile's bounding square.
// Reference: W. Wang, B. Jüttler, D. Zheng, Y. Liu, "Computation of rotation minimizing
// frames", ACM Transactions on Graphics 27(1), 2008; Bloomenthal, "Calculation of
// reference frames along a space curve", Graphics Gems I, 1990.
#include "procedural_mesh.hpp"

#include "effigi/core/log.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/render/shape_base.hpp"

#include <numbers>

namespace effigi {
namespace {

using glm::dvec2;

/// A column of the grid: a profile point with its outward 2-D normal and u coordinate.
struct ProfileColumn {
    dvec2 p, n;
    double u;
};

/// A path sample with its rotation-minimising frame (t: unit tangent, r: first normal).
struct PathFrame {
    Vector3d x, t, r;
};

/// Double reflection (Wang et al. 2008, Algorithm 1): from frame i to i+1, reflect in the
/// bisector plane of x_i, x_{i+1}, then in the plane that maps the reflected tangent onto
/// t_{i+1}.
void propagateFrames(std::vector<PathFrame>& f) {
    for (std::size_t i = 0; i + 1 < f.size(); ++i) {
        Vector3d v1 = f[i + 1].x - f[i].x;
        double c1 = glm::dot(v1, v1);
        Vector3d rL = f[i].r - (2.0 / c1) * glm::dot(v1, f[i].r) * v1;
        Vector3d tL = f[i].t - (2.0 / c1) * glm::dot(v1, f[i].t) * v1;
        Vector3d v2 = f[i + 1].t - tL;
        double c2 = glm::dot(v2, v2);
        Vector3d r = c2 > 0.0 ? rL - (2.0 / c2) * glm::dot(v2, rL) * v2 : rL;
        // Rounding only: keep r a unit vector normal to the tangent.
        f[i + 1].r = glm::normalize(r - glm::dot(r, f[i + 1].t) * f[i + 1].t);
    }
}

class Sweep final : public MeshShape {
public:
    static Schema schema() {
        Schema s("shape", "sweep", "A circle or closed profile swept along a helix or a curve through points, as a mesh.");
        s.cite("Wang, Jüttler, Zheng, Liu, Computation of rotation minimizing frames, ACM TOG 27(1), 2008");
        s.real("radius", 0.1, "Radius of the circle swept (when no profile is given)").atLeast(0.0);
        s.integer("sides", 32, "Segments of the circle").range(3, 1 << 16);
        s.optional("profile", ParamType::String, "Closed polygon \"x0 y0, x1 y1, ...\" swept instead of the circle (>= 3 points)");
        s.string("path", "helix", "The curve swept along: helix or points").oneOf({"helix", "points"});
        s.real("helix_radius", 1.0, "Radius of the helix").atLeast(0.0);
        s.real("pitch", 0.5, "Rise of the helix per turn (along z)");
        s.real("turns", 2.0, "Number of turns of the helix").atLeast(0.0);
        s.optional("points", ParamType::String, "Path points \"x0 y0 z0, x1 y1 z1, ...\" (path=points), at least 2");
        s.integer("samples", 64, "Path steps per helix turn, or per segment between points").range(1, 1 << 16);
        s.boolean("caps", false, "Close both ends with flat caps");
        addMeshParams(s);
        // effigi-conform: the default helix tube; a capped square bar along a bent spline;
        // a tiny flipped triangle-profile tube on a steep helix.
        s.addConformance({"helix", {}});
        s.addConformance({"capped bar on spline", {{"path", std::string("points")}, {"points", std::string("0 0 0, 1 0 0.5, 1.5 1 1")},
                                                   {"profile", std::string("-0.1 -0.1, 0.1 -0.1, 0.1 0.1, -0.1 0.1")},
                                                   {"caps", true}, {"samples", std::int64_t(16)}}});
        s.addConformance({"tiny flipped triangle", {{"profile", std::string("0 0.2, -0.2 -0.1, 0.2 -0.1")}, {"pitch", 2.0},
                                                    {"turns", 0.75}, {"flip_normals", true},
                                                    {"to_world", Transform::scale(Vector3f(1e-3f))}}});
        return s;
    }

    explicit Sweep(const Properties& p) : MeshShape(p) {
        std::vector<ProfileColumn> cols = profile(p);
        std::vector<PathFrame> path = p.getString("path") == "helix" ? helix(p) : spline(p);
        propagateFrames(path);

        double extent = 0.0, kappa = 0.0;  // the profile's reach, the path's largest curvature
        for (const ProfileColumn& c : cols) extent = std::max(extent, glm::length(c.p));
        for (std::size_t i = 0; i + 1 < path.size(); ++i)
            kappa = std::max(kappa, std::acos(std::clamp(glm::dot(path[i].t, path[i + 1].t), -1.0, 1.0)) /
                                        glm::length(path[i + 1].x - path[i].x));
        if (extent * kappa >= 1.0)
            log::warn("{}: the tube reaches {:.4g} from the path, beyond its radius of curvature {:.4g}: it intersects itself",
                      p.describe(), extent, 1.0 / kappa);

        TriangleMesh m;
        auto place = [&](const PathFrame& f, dvec2 q) { return f.x + q.x * f.r + q.y * glm::cross(f.t, f.r); };
        auto vertex = [&](std::size_t i, std::size_t j) {
            const PathFrame& f = path[i];
            return procedural::GridVertex{Point3f(place(f, cols[j].p)), Normal3f(place({Vector3d(0.0), f.t, f.r}, cols[j].n)),
                                          Point2f(float(cols[j].u), float(double(i) / double(path.size() - 1)))};
        };
        const bool circle = !p.has("profile");
        procedural::appendGrid(m, path.size(), cols.size(), vertex, [](std::size_t) { return true; },
                               [&](std::size_t j) { return circle || j % 2 == 0; });
        if (m.indices.empty()) failAt(p.whereOf(circle ? "radius" : "profile"), "{}: the profile has no extent", p.describe());
        if (p.getBool("caps")) {
            dvec2 centre(0.0);  // the circle's, or the mean of the polygon's points (each twice in cols)
            if (!circle)
                for (const ProfileColumn& c : cols) centre += c.p / double(cols.size());
            for (std::size_t j = 0; j + 1 < cols.size(); ++j)
                if ((circle || j % 2 == 0) && glm::determinant(glm::dmat2(cols[j].p - centre, cols[j + 1].p - centre)) <= 0.0)
                    failAt(p.whereOf("caps"), "{}: the profile is not star-shaped about its centroid: its caps cannot be "
                           "fanned (set caps=false)", p.describe());
            for (bool end : {false, true}) {
                const PathFrame& f = end ? path.back() : path.front();
                auto base = std::uint32_t(m.positions.size());
                auto add = [&](dvec2 q) {
                    m.positions.emplace_back(place(f, q));
                    m.normals.emplace_back(end ? f.t : -f.t);
                    m.uvs.emplace_back(float(0.5 + 0.5 * q.x / extent), float(0.5 + 0.5 * q.y / extent));
                };
                add(centre);
                for (const ProfileColumn& c : cols) add(c.p);
                for (std::uint32_t j = 0; j + 1 < cols.size(); ++j) {
                    if (!circle && j % 2) continue;
                    std::uint32_t a = base + 1 + j, b = a + 1;  // counter-clockwise about +t
                    m.indices.insert(m.indices.end(), {base, end ? a : b, end ? b : a});
                }
            }
        }
        setMesh(std::move(m), p.describe());
    }

private:
    /// The profile's columns: the circle's (seam repeated), or each polygon edge's two ends
    /// with the edge's normal, counter-clockwise so that normals face out.
    static std::vector<ProfileColumn> profile(const Properties& p) {
        std::vector<ProfileColumn> cols;
        if (!p.has("profile")) {
            const double r = p.getFloat("radius");
            const auto n = std::size_t(p.getInt("sides"));
            for (std::size_t j = 0; j <= n; ++j) {
                double a = j == n ? 0.0 : 2.0 * std::numbers::pi * double(j) / double(n);
                dvec2 d(std::cos(a), std::sin(a));
                cols.push_back({r * d, d, double(j) / double(n)});
            }
            return cols;
        }
        std::vector<dvec2> pts;
        for (const std::vector<double>& t : procedural::parseTuples(p, "profile", 2, 3)) pts.emplace_back(t[0], t[1]);
        double area = 0.0, perimeter = 0.0;
        for (std::size_t k = 0; k < pts.size(); ++k) {
            const dvec2 &a = pts[k], &b = pts[(k + 1) % pts.size()];
            area += a.x * b.y - a.y * b.x;
            perimeter += glm::length(b - a);
        }
        if (area < 0.0) std::reverse(pts.begin(), pts.end());
        double u = 0.0;
        for (std::size_t k = 0; k < pts.size(); ++k) {
            const dvec2 &a = pts[k], &b = pts[(k + 1) % pts.size()];
            double len = glm::length(b - a);
            if (!(len > 0.0)) failAt(p.whereOf("profile"), "{}: profile points {} and {} coincide", p.describe(), k + 1,
                                     (k + 1) % pts.size() + 1);
            dvec2 n(b.y - a.y, a.x - b.x);
            cols.push_back({a, n / len, u / perimeter});
            u += len;
            cols.push_back({b, n / len, u / perimeter});
        }
        return cols;
    }

    static std::vector<PathFrame> helix(const Properties& p) {
        const double R = p.getFloat("helix_radius"), c = p.getFloat("pitch") / (2.0 * std::numbers::pi),
                     span = 2.0 * std::numbers::pi * p.getFloat("turns");
        if (!(span > 0.0) || (R == 0.0 && c == 0.0))
            failAt(p.whereOf(span > 0.0 ? "pitch" : "turns"),
                   "{}: the helix has no length (turns, or both helix_radius and pitch, are 0)", p.describe());
        const auto n = std::max<std::size_t>(1, std::size_t(std::ceil(double(p.getInt("samples")) * p.getFloat("turns"))));
        std::vector<PathFrame> f;
        for (std::size_t i = 0; i <= n; ++i) {
            double a = span * double(i) / double(n);
            f.push_back({{R * std::cos(a), R * std::sin(a), c * a},
                         glm::normalize(Vector3d(-R * std::sin(a), R * std::cos(a), c)), Vector3d(0.0)});
        }
        f[0].r = {-1.0, 0.0, 0.0};  // towards the axis: normal to the tangent at a = 0
        if (R == 0.0) f[0].r = {1.0, 0.0, 0.0};
        return f;
    }

    static std::vector<PathFrame> spline(const Properties& p) {
        if (!p.has("points")) failAt(p.where(), "{}: path=points needs the parameter 'points'", p.describe());
        procedural::CatmullRom<Vector3d> curve;
        for (const std::vector<double>& t : procedural::parseTuples(p, "points", 3, 2)) curve.pts.emplace_back(t[0], t[1], t[2]);
        const auto n = std::size_t(p.getInt("samples"));
        std::vector<PathFrame> f;
        for (std::size_t k = 0; k < curve.segments(); ++k)
            for (std::size_t i = (k == 0 ? 0 : 1); i <= n; ++i) {
                Vector3d x, dx;
                curve.eval(k, double(i) / double(n), x, dx);
                if (!(glm::length(dx) > 0.0) || (!f.empty() && x == f.back().x))
                    failAt(p.whereOf("points"), "{}: the path stops (zero tangent) near point {}", p.describe(), k + 1);
                f.push_back({x, glm::normalize(dx), Vector3d(0.0)});
            }
        // Any normal to the first tangent: across the axis it is least aligned with.
        Vector3d t = f[0].t, a = std::abs(t.x) < 0.6 ? Vector3d(1, 0, 0) : Vector3d(0, 1, 0);
        f[0].r = glm::normalize(glm::cross(t, a));
        return f;
    }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Sweep)
