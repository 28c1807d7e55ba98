// Shape suite: an IShape, in each of its configurations, is checked for what the
// interface promises (include/effigi/interfaces/ishape.hpp). The shape is built alone
// into an `embree` accelerator, the one scenes use by default, so "the surface" is what
// that intersector reports. Lengths are judged relative to R, the radius of the sphere
// around the shape's bounding box, so tiny and huge configurations get the same checks.
//  - position samples: samplePosition() at random inputs and at the corners and edges of
//    [0, 1)² gives finite points with unit normals, inside bbox(), with pdf = 1/area()
//    (the interface: uniform by area);
//  - on surface: a ray toward a sampled point from 1e-4 R away (against its normal and
//    obliquely) crosses the shape at that point, and the crossing's geometric normal is
//    the sampled one, sign included (Mitsuba: both honour flip_normals);
//  - extreme references: sampleDirection() and pdfDirection() from points on the surface,
//    1e-6 R off it, at the centre and 1e6 R away stay finite and non-negative;
//  - intersections, area and sampling density against ray casting: shape_measure.cpp;
//  - direction sampling (samples on the surface, pdf values, E[1/pdf], chi-square):
//    shape_directions.cpp.
// A shape that cannot carry an area emitter (curves) need not be sampleable: its
// sampling checks are skipped with that reason; one that can must sample. A shapegroup is
// no IShape (only its instances are drawn): it is skipped, and checked through the
// configuration of `instance`.
#include "conformance/shape_common.hpp"

#include "effigi/interfaces/iemitter.hpp"
#include "effigi/math/warp_functions.hpp"

namespace effigi::conform::shape {

namespace {

/// Shapes whose area() and samplePosition() are documented estimates, with the relative
/// slack their area checks get and why (their component files say so); a negative slack
/// reports the area without judging it.
struct Approximation {
    const char* component;
    double slack;
    const char* reason;
};
constexpr Approximation Approximations[] = {
    {"sdfgrid", 0.05, "area() and samplePosition() are estimates from the grid edges the surface crosses, with "
                      "the normal of one of the cells there (components/shape/sdfgrid.cpp; it cannot emit): its samples "
                      "sit on the creases between cells, where rays may only touch the surface"},
    {"linearcurve", -1.0, "area() is the lateral area of the round cones without joints and caps, and back faces "
                          "are culled as in Mitsuba, so lines see only where they enter (curve_common.hpp)"},
    {"bsplinecurve", -1.0, "area() is the lateral area of the round cones without joints, and back faces are "
                           "culled as in Mitsuba, so lines see only where they enter (curve_common.hpp)"},
};

/// The area the configuration's parameters give, for the shapes whose geometry is known
/// in closed form (Mitsuba's definitions): nothing for meshes from files, curves, grids.
std::optional<double> analyticArea(const Target& t) {
    Properties p(t.tag(), t.component());
    for (const auto& [name, value] : t.configuration().params) p.set(name, value);
    t.registry().info(t.tag(), t.component()).schema.validate(p);
    glm::dmat3 m(1.0);
    if (p.has("to_world")) m = glm::dmat3(glm::mat3(p.getAnimatedTransform("to_world").first().matrix()));
    auto par = [&](int i, int j) { return glm::length(glm::cross(m[i], m[j])); };  // |M e_i × M e_j|
    const std::string& c = t.component();
    const double pi = std::numbers::pi;
    if (c == "rectangle") return 4.0 * par(0, 1);
    if (c == "disk") return pi * par(0, 1);
    if (c == "cube") return 8.0 * (par(0, 1) + par(1, 2) + par(2, 0));
    if (c == "sphere") {
        double r = p.getFloat("radius") * std::cbrt(std::abs(glm::determinant(m)));
        return 4.0 * pi * r * r;
    }
    if (c == "cylinder") {
        Vector3f axis = p.getPoint("p1") - p.getPoint("p0");
        Frame f(normalize(axis));
        double r = glm::length(m * Vector3d(f.s)) * double(p.getFloat("radius"));
        double tube = 2.0 * pi * r * glm::length(m * Vector3d(axis));
        return p.getBool("caps") ? tube + 2.0 * pi * r * r : tube;  // caps: two end disks
    }
    return std::nullopt;
}

/// Whether the component takes a nested area emitter (then it must be sampleable).
bool takesEmitter(const Target& t) {
    if (!t.hasParameter("emitter")) return false;
    try {
        Properties e("emitter", "area");
        Ref<IComponent> emitter = t.registry().create("emitter", "area", e);
        t.create({{"emitter", ComponentValue{"emitter", emitter}}});
        return true;
    } catch (const std::exception&) {
        return false;
    }
}

bool inBounds(const BBox3f& b, const Point3f& p, double tol) {
    for (int a = 0; a < 3; ++a)
        if (!(double(p[a]) >= double(b.min[a]) - tol && double(p[a]) <= double(b.max[a]) + tol)) return false;
    return true;
}

/// Position samples: finite, unit normal, inside the bounds, pdf = 1/area().
void checkPositions(Target& t, const Setup& s) {
    const IShape& shape = *s.shape;
    const BBox3f box = shape.bbox();
    const double area = shape.area();
    std::vector<Point2f> us;
    const float edge[] = {0.f, 1e-7f, 0.5f, 1.f - 1e-7f, OneMinusEpsilon};
    for (float x : edge)
        for (float y : edge) us.emplace_back(x, y);
    PCG32 rng = t.rng("position samples");
    for (std::uint64_t i = 0, n = t.count(20000, 4000); i < n; ++i) us.push_back(uniform2(rng));
    Tally fin, bounds, pdf;
    for (const Point2f& u : us) {
        PositionSample ps = shape.samplePosition(u);
        std::string at = fmt::format("u = ({:.9g}, {:.9g}): p = {}, n = {}, pdf = {:.7g}", u.x, u.y, str(ps.p), str(ps.n), ps.pdf);
        bool ok = isFinite(ps.p) && isFinite(ps.n) && std::abs(length(ps.n) - 1.f) <= 1e-4f && std::isfinite(ps.uv.x) &&
                  std::isfinite(ps.uv.y) && std::isfinite(ps.pdf) && ps.pdf > 0.f;
        fin.note(ok, at);
        if (!ok) continue;
        bounds.note(inBounds(box, ps.p, s.tolerance(ps.p)), at);
        pdf.note(std::abs(double(ps.pdf) * area - 1.0) <= 1e-4, at + fmt::format(", 1/area() = {:.7g}", 1.0 / area));
    }
    t.expect("position samples", fin.bad == 0, fin.figure(),
             fin.detail("finite points, unit normals, finite uv and a finite pdf > 0 at random inputs and at the "
                        "corners and edges of [0, 1)²"));
    t.expect("samples in bounds", bounds.bad == 0, bounds.figure(),
             bounds.detail(fmt::format("every sampled point inside bbox() (to 1e-5 R = {:.3g} and rounding)", 1e-5 * s.radius)));
    t.expect("position pdf", pdf.bad == 0, pdf.figure(),
             pdf.detail("pdf · area() = 1 within 1e-4 (samplePosition is uniform by area)"));
}

/// Sampled points lie on the surface the intersector sees, with the normal it reports.
void checkOnSurface(Target& t, const Setup& s) {
    const IShape& shape = *s.shape;
    PCG32 rng = t.rng("on surface");
    Tally hit, normal;
    double worstAngle = 0.0;
    for (std::uint64_t i = 0, n = t.count(5000, 1000); i < n; ++i) {
        PositionSample ps = shape.samplePosition(uniform2(rng));
        if (!(ps.pdf > 0.f) || !isFinite(ps.p) || !isFinite(ps.n)) continue;  // position samples says so
        for (int k = 0; k < 2; ++k) {
            // Toward the point against its normal, then obliquely: cos θ to the normal
            // uniform in [0.2, 1].
            Vector3f w = ps.n;
            if (k == 1) {
                float c = 0.2f + 0.8f * rng.nextFloat(), phi = 2.f * Pi * rng.nextFloat(), sn = safeSqrt(1.f - c * c);
                w = Frame(ps.n).toWorld(Vector3f(sn * std::cos(phi), sn * std::sin(phi), c));
            }
            std::optional<SurfaceInteraction> si = crossingAt(s, ps.p, ps.n, -w);
            double err = si ? glm::length(Vector3d(si->p) - Vector3d(ps.p)) : HUGE_VAL;
            hit.worst = std::max(hit.worst, err / s.tolerance(ps.p));
            hit.note(si.has_value(), fmt::format("sample {} (n = {}): a ray toward it {} crosses the surface nowhere "
                                                 "near it", str(ps.p), str(ps.n), k ? "obliquely" : "against its normal"));
            if (!si) continue;
            double angle = std::atan2(glm::length(glm::cross(Vector3d(si->n), Vector3d(ps.n))),
                                      glm::dot(Vector3d(si->n), Vector3d(ps.n)));
            worstAngle = std::max(worstAngle, angle);
            normal.note(angle <= 1e-3, fmt::format("at {}: sampled normal {}, intersection normal {}", str(ps.p),
                                                   str(ps.n), str(si->n)));
        }
    }
    judge(t, s, "on surface", hit.bad == 0, fmt::format("{}; worst {:.3g} of tolerance", hit.figure(), hit.worst),
          hit.detail("rays toward each sampled point from 1e-4 R (or 256u·|p|) away (against its normal; obliquely, "
                     "cos θ ≥ 0.2) cross the shape there, within 1e-5 R + 64u·|p| (at a rim: a ray aimed 1e-5 R + "
                     "256u·|p| beside it, within twice that more)"));
    judge(t, s, "sampled normals", normal.bad == 0, fmt::format("{}; worst {:.2g} rad", normal.figure(), worstAngle),
          normal.detail("the sampled normal is the intersection's geometric normal, same sign, within 1e-3 rad"));
}

/// sampleDirection() and pdfDirection() from references on, near, inside and far away.
void checkExtremeReferences(Target& t, const Setup& s) {
    const IShape& shape = *s.shape;
    PCG32 rng = t.rng("extreme references");
    std::vector<Point3f> refs = {s.centre, Point3f(Vector3d(s.centre) + 1e6 * s.radius * Vector3d(0.36, -0.48, 0.8))};
    for (int k = 0; k < 6; ++k) {
        PositionSample ps = shape.samplePosition(uniform2(rng));
        if (!(ps.pdf > 0.f) || !isFinite(ps.p) || !isFinite(ps.n)) continue;
        for (double off : {0.0, 1e-6, -1e-6, 1e6}) refs.push_back(Point3f(Vector3d(ps.p) + off * s.radius * Vector3d(ps.n)));
    }
    Tally tally;
    const Point2f us[] = {Point2f(0.f), Point2f(0.5f), Point2f(OneMinusEpsilon), Point2f(0.25f, 0.75f), Point2f(1e-7f, 0.5f)};
    for (const Point3f& ref : refs)
        for (const Point2f& u : us) {
            DirectionSample ds = shape.sampleDirection(ref, u);
            bool ok = std::isfinite(ds.pdf) && ds.pdf >= 0.f;
            float back = 0.f;
            if (ok && ds.pdf > 0.f) {
                ok = isFinite(ds.p) && isFinite(ds.n) && isFinite(ds.wi) && std::abs(length(ds.wi) - 1.f) <= 1e-4f &&
                     std::isfinite(ds.dist) && ds.dist >= 0.f;
                SurfaceInteraction si;
                si.p = ds.p, si.n = ds.n, si.shading = Frame(ds.n), si.wo = -ds.wi, si.shape = &shape;
                back = shape.pdfDirection(ref, si);
                ok = ok && std::isfinite(back) && back >= 0.f;
            }
            tally.note(ok, fmt::format("ref {}, u = ({:g}, {:g}): pdf {}, p {}, wi {}, dist {}, pdfDirection {}", str(ref),
                                       u.x, u.y, ds.pdf, str(ds.p), str(ds.wi), ds.dist, back));
        }
    t.expect("extreme references", tally.bad == 0, tally.figure(),
             tally.detail("sampleDirection() and pdfDirection() finite, pdf ≥ 0, unit wi, from the centre, from points on "
                          "the surface, 1e-6 R either side of it and 1e6 R away"));
}

void runShapeSuite(Target& t) {
    Ref<IShape> shape = t.as<IShape>();
    if (!shape) {
        if (t.component() == "shapegroup")
            t.skip("interface", "a shapegroup is no IShape: only its instances are drawn (checked in the "
                                "configurations of shape/instance)");
        else t.expect("interface", false, "-", "component does not implement IShape");
        return;
    }
    Setup s;
    s.shape = shape;
    const BBox3f box = shape->bbox();
    const float area = shape->area();
    bool ok = box.valid() && isFinite(box.min) && isFinite(box.max) && std::isfinite(area) && area > 0.f;
    t.expect("geometry", ok, fmt::format("area {:.7g}", area),
             fmt::format("bbox [{}, {}] valid and finite, area() finite and > 0", str(box.min), str(box.max)));
    if (!ok) return;
    s.centre = box.center();
    s.radius = std::max(double(box.boundingRadius()), 1e-30);
    for (const Approximation& a : Approximations)
        if (t.component() == a.component) s.areaSlack = a.slack, s.approximate = a.reason;
    Properties ap("accelerator", "embree");
    s.accel = query<IIntersect>(t.registry().create("accelerator", "embree", ap));
    if (!s.accel) {
        t.expect("geometry", false, "-", "accelerator/embree is not an IIntersect");
        return;
    }
    const IShape* members[] = {shape.get()};
    s.accel->build(members);

    s.samples = shape->samplePosition(Point2f(0.5f)).pdf > 0.f || shape->samplePosition(Point2f(0.3f, 0.7f)).pdf > 0.f;
    // A shape that takes an area emitter must sample: "position samples" then fails on
    // its pdf 0.
    if (!s.samples && takesEmitter(t)) s.samples = true;
    const char* noSampling = "the shape cannot carry an area emitter and gives no area samples (pdf 0), as in Mitsuba";
    if (s.samples) {
        checkPositions(t, s);
        checkOnSurface(t, s);
    } else {
        for (const char* c : {"position samples", "on surface"}) t.skip(c, noSampling);
    }
    checkArea(t, s, analyticArea(t));
    if (s.samples) checkDirections(t, s);
    else t.skip("direction sampling", noSampling);
    checkExtremeReferences(t, s);
}

} // namespace

} // namespace effigi::conform::shape

EFFIGI_CONFORMANCE_SUITE("shape",
                         "area samples on the surface the intersector sees (points, normals, pdf), area and sampling "
                         "density against ray casting, direction sampling (pdf values, E[1/pdf], chi-square), bounds, "
                         "finite values at extreme references",
                         effigi::conform::shape::runShapeSuite);
