// The procedural mesh shapes revolution and sweep: areas against closed forms (the exact
// area of the tessellation, and the true surface's within the chord error), normals
// outward and agreeing with the triangles' winding, uv ranges, rotation-minimising
// frames (no twist), and bad parameters reported with file:line.
#include "shape_helpers.hpp"
#include "xml_helpers.hpp"

#include "effigi/render/scene.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <numbers>

using namespace effigi;
using namespace effigi::test;

namespace {

constexpr double kPi = std::numbers::pi;

Ref<IShape> make(const std::string& type, std::vector<std::pair<std::string, PropertyValue>> params) {
    Properties p("shape", type);
    for (auto& [k, v] : params) p.set(k, v);
    return makeShape(type, p);
}

double meshArea(const TriangleMesh& m) {
    double a = 0.0;
    for (std::size_t i = 0; i < m.triangleCount(); ++i) {
        Point3f p0, p1, p2;
        m.triangle(i, p0, p1, p2);
        a += 0.5 * glm::length(glm::cross(Vector3d(p1 - p0), Vector3d(p2 - p0)));
    }
    return a;
}

/// Every triangle's winding agrees with its vertex normals, and each vertex normal is a
/// unit vector; returns the smallest dot(geometric, vertex normal).
double windingAgreement(const TriangleMesh& m) {
    double worst = 1.0;
    for (std::size_t i = 0; i < m.triangleCount(); ++i) {
        Point3f p0, p1, p2;
        m.triangle(i, p0, p1, p2);
        Vector3d ng = glm::normalize(glm::cross(Vector3d(p1 - p0), Vector3d(p2 - p0)));
        for (int k = 0; k < 3; ++k) {
            Vector3d n(m.normals[m.indices[3 * i + std::size_t(k)]]);
            REQUIRE(glm::length(n) == Approx(1.0).epsilon(1e-5));
            worst = std::min(worst, glm::dot(ng, n));
        }
    }
    return worst;
}

/// "sin θ_k -cos θ_k, ..." for k = 0..K: a half circle of radius 1 from pole to pole.
std::string halfCircle(int K) {
    std::string s;
    for (int k = 0; k <= K; ++k) {
        double t = kPi * k / K;
        s += fmt::format("{}{:.17g} {:.17g}", k ? ", " : "", k == K ? 0.0 : std::sin(t), -std::cos(t));
    }
    return s;
}

/// The message and location of the error loading a scene holding `shape` (one line).
std::string sceneError(const std::string& shape) {
    std::string text = "<scene version=\"3.0.0\">\n" + shape + "\n</scene>\n";
    return errorOf([&] { loadScene(*xml::parseString(text, "procedural.xml")); });
}

} // namespace

TEST_CASE("revolution: a half-circle profile gives a sphere within the chord error", "[shapes][procedural]") {
    // The inscribed mesh's area in closed form: each band is S planar trapezoids with
    // parallel sides 2 r_i sin(π/S) and height sqrt((Δr cos(π/S))² + Δz²).
    auto tessellated = [](int K, int S) {
        double a = 0.0;
        for (int k = 0; k < K; ++k) {
            double r0 = std::sin(kPi * k / K), r1 = k + 1 == K ? 0.0 : std::sin(kPi * (k + 1) / K);
            double dz = std::cos(kPi * k / K) - std::cos(kPi * (k + 1) / K), dr = (r1 - r0) * std::cos(kPi / S);
            a += S * (r0 + r1) * std::sin(kPi / S) * std::sqrt(dr * dr + dz * dz);
        }
        return a;
    };
    double previous = 1.0;
    for (int n : {16, 32, 64}) {
        const int K = n, S = 2 * n;
        Ref<IShape> s = make("revolution", {{"profile", halfCircle(K)}, {"segments", std::int64_t(S)}});
        const double A = s->area(), exact = 4.0 * kPi;
        INFO("K = " << K << ", S = " << S << ", area " << A);
        CHECK(A == Approx(tessellated(K, S)).epsilon(1e-5));
        CHECK(meshArea(*s->mesh()) == Approx(A).epsilon(1e-5));
        // Inscribed, short of 4π by at most (π/S)²·2/3 (around) + (π/K)²/8 (along the profile).
        const double err = 1.0 - A / exact, bound = (kPi / S) * (kPi / S) * 2.0 / 3.0 + (kPi / K) * (kPi / K) / 8.0;
        CHECK(err > 0.0);
        CHECK(err < bound);
        CHECK(err < previous / 3.0);  // second order: halving both steps quarters the error
        previous = err;
        for (const Point3f& p : s->mesh()->positions) CHECK(glm::length(p) == Approx(1.f).epsilon(1e-5));
        CHECK(windingAgreement(*s->mesh()) > 0.9);
    }
}

TEST_CASE("revolution: a Catmull-Rom half circle is smooth with outward radial normals", "[shapes][procedural]") {
    // The spline's free ends (mirrored phantom points) meet the axis slightly off the
    // perpendicular: the largest departures from the sphere are at the poles.
    Ref<IShape> s = make("revolution", {{"profile", halfCircle(16)}, {"interpolation", std::string("catmullrom")},
                                        {"rings", std::int64_t(8)}, {"segments", std::int64_t(128)}});
    CHECK(s->area() == Approx(4.0 * kPi).epsilon(2e-3));
    const TriangleMesh& m = *s->mesh();
    double worst = 1.0, worstRadius = 0.0;
    for (std::size_t v = 0; v < m.vertexCount(); ++v) {
        worstRadius = std::max(worstRadius, std::abs(double(glm::length(m.positions[v])) - 1.0));
        worst = std::min(worst, double(glm::dot(m.normals[v], glm::normalize(m.positions[v]))));
    }
    CHECK(worstRadius < 5e-4);
    CHECK(worst > 0.9995);
    CHECK(windingAgreement(m) > 0.95);
}

TEST_CASE("revolution: a vertical segment gives a cylinder of area 2 pi r h up to the chord factor", "[shapes][procedural]") {
    const double r = 0.5, h = 2.0;
    for (int S : {3, 7, 48}) {
        Ref<IShape> s = make("revolution", {{"profile", std::string("0.5 -1, 0.5 1")}, {"segments", std::int64_t(S)}});
        // Exactly S rectangles 2 r sin(π/S) × h.
        CHECK(s->area() == Approx(S * 2.0 * r * std::sin(kPi / S) * h).epsilon(1e-6));
        CHECK(s->area() == Approx(2.0 * kPi * r * h * std::sin(kPi / S) / (kPi / S)).epsilon(1e-6));
        for (std::size_t v = 0; v < s->mesh()->vertexCount(); ++v) {
            Point3f p = s->mesh()->positions[v];
            Normal3f n = s->mesh()->normals[v];
            CHECK(n.z == Approx(0.f).margin(1e-6));
            CHECK(glm::dot(n, Vector3f(p.x, p.y, 0.f)) == Approx(r).epsilon(1e-5));  // unit, radial, outward
        }
        CHECK(windingAgreement(*s->mesh()) > 0.45);  // 3 sides: corner normals are 60° off the faces
    }
    // Half a turn: half the area, u over [0, 1]; a profile running down faces inward.
    Ref<IShape> half = make("revolution", {{"profile", std::string("0.5 -1, 0.5 1")}, {"phi_max", 180.0}});
    CHECK(half->area() == Approx(kPi * r * h * std::sin(kPi / 128) / (kPi / 128)).epsilon(1e-6));  // 64 segments over π
    float umin = 1.f, umax = 0.f;
    for (const Point2f& uv : half->mesh()->uvs) umin = std::min(umin, uv.x), umax = std::max(umax, uv.x);
    CHECK(umin == 0.f);
    CHECK(umax == 1.f);
    Ref<IShape> down = make("revolution", {{"profile", std::string("0.5 1, 0.5 -1")}});
    CHECK(down->mesh()->normals[0].x < -0.99f);  // vertex 0: φ = 0, facing the axis
}

TEST_CASE("revolution: a linear vase keeps sharp profile corners and outward normals", "[shapes][procedural]") {
    Ref<IShape> s = make("revolution", {{"profile", std::string("0 0, 0.6 0, 0.7 0.3, 0.35 1.2, 0.45 1.6")},
                                        {"to_world", Transform::translate({1.f, 2.f, 3.f})}});
    CHECK(windingAgreement(*s->mesh()) > 0.99);  // frustums: normals constant along each generator
    const BBox3f b = s->bbox();
    CHECK(b.min.z == Approx(3.f));
    CHECK(b.max.z == Approx(4.6f));
    CHECK(b.max.x == Approx(1.7f).epsilon(1e-5));
    // No triangle is degenerate (the bottom's apex is fanned, not stitched).
    for (std::size_t i = 0; i < s->mesh()->triangleCount(); ++i) CHECK(s->mesh()->triangleArea(i) > 0.f);
}

TEST_CASE("sweep: a straight circle sweep has area 2 pi r L", "[shapes][procedural]") {
    const double r = 0.25, L = 3.0;
    for (int sides : {5, 32}) {
        Ref<IShape> s = make("sweep", {{"path", std::string("points")}, {"points", std::string("1 1 0, 1 1 3")},
                                       {"radius", r}, {"sides", std::int64_t(sides)}, {"samples", std::int64_t(4)}});
        CHECK(s->area() == Approx(2.0 * kPi * r * L * std::sin(kPi / sides) / (kPi / sides)).epsilon(1e-6));
        for (std::size_t v = 0; v < s->mesh()->vertexCount(); ++v) {
            Vector3f d = s->mesh()->positions[v] - Point3f(1.f, 1.f, s->mesh()->positions[v].z);
            CHECK(glm::length(d) == Approx(r).epsilon(1e-5));
            CHECK(glm::dot(s->mesh()->normals[v], d) == Approx(r).epsilon(1e-5));  // radial, outward
        }
    }
    // Capped: the two discs are added (inscribed polygons of area (n/2) r² sin(2π/n)).
    Ref<IShape> capped = make("sweep", {{"path", std::string("points")}, {"points", std::string("0 0 0, 0 0 3")},
                                        {"radius", r}, {"caps", true}});
    CHECK(capped->area() == Approx(2.0 * kPi * r * L * std::sin(kPi / 32) / (kPi / 32) + 2.0 * 16.0 * r * r * std::sin(2.0 * kPi / 32))
                                .epsilon(1e-6));
    CHECK(windingAgreement(*capped->mesh()) > 0.98);
}

TEST_CASE("sweep: a helix tube has area 2 pi r times the helix length and does not twist", "[shapes][procedural]") {
    const double R = 1.0, pitch = 0.8, turns = 2.5, r = 0.15;
    const double length = turns * std::sqrt(4.0 * kPi * kPi * R * R + pitch * pitch);
    Ref<IShape> s = make("sweep", {{"helix_radius", R}, {"pitch", pitch}, {"turns", turns}, {"radius", r},
                                   {"sides", std::int64_t(64)}, {"samples", std::int64_t(128)}});
    // Pappus for tubes: exact while r < the radius of curvature; the chord error of the
    // 64-gon is 0.16 %, of the path steps far less.
    CHECK(s->area() == Approx(2.0 * kPi * r * length).epsilon(2.5e-3));
    CHECK(s->area() < 2.0 * kPi * r * length);
    const TriangleMesh& m = *s->mesh();
    CHECK(windingAgreement(m) > 0.9);  // no normal flips anywhere
    // Every ring stays a circle of radius r about the helix, in the plane normal to it.
    const std::size_t cols = 65;
    for (std::size_t i = 0; i < m.vertexCount() / cols; ++i) {
        double a = 2.0 * kPi * turns * double(i) / double(m.vertexCount() / cols - 1);
        Vector3d c(R * std::cos(a), R * std::sin(a), pitch * a / (2.0 * kPi));
        Vector3d t = glm::normalize(Vector3d(-R * std::sin(a), R * std::cos(a), pitch / (2.0 * kPi)));
        for (std::size_t j = 0; j < cols; j += 16) {
            Vector3d d = Vector3d(m.positions[i * cols + j]) - c;
            CHECK(glm::length(d) == Approx(r).epsilon(1e-4));
            CHECK(glm::dot(d, t) == Approx(0.0).margin(1e-5));
        }
    }
    // No twist: along a rotation-minimising frame the frame turns about the tangent at
    // the rate -τ·(ds) relative to the Frenet frame, so the first column's offset,
    // measured against the Frenet normal (towards the axis), has turned by -τ·length.
    const double c = pitch / (2.0 * kPi), tau = c / (R * R + c * c);
    const std::size_t last = (m.vertexCount() / cols - 1) * cols;
    const double a = 2.0 * kPi * turns;
    Vector3d centre(R * std::cos(a), R * std::sin(a), c * a), d = glm::normalize(Vector3d(m.positions[last]) - centre);
    Vector3d t = glm::normalize(Vector3d(-R * std::sin(a), R * std::cos(a), c)), n(-std::cos(a), -std::sin(a), 0.0);
    double angle = std::atan2(glm::dot(glm::cross(n, d), t), glm::dot(n, d));
    double expected = std::remainder(-tau * length, 2.0 * kPi);
    CHECK(std::remainder(angle - expected, 2.0 * kPi) == Approx(0.0).margin(1e-3));
}

TEST_CASE("sweep: a polygon profile keeps its corners and is oriented outward either way round", "[shapes][procedural]") {
    for (std::string square : {"-0.1 -0.1, 0.1 -0.1, 0.1 0.1, -0.1 0.1", "-0.1 0.1, 0.1 0.1, 0.1 -0.1, -0.1 -0.1"}) {
        Ref<IShape> s = make("sweep", {{"path", std::string("points")}, {"points", std::string("0 0 0, 1 0 0.5, 1.5 1 1")},
                                       {"profile", square}, {"caps", true}});
        CHECK(windingAgreement(*s->mesh()) > 0.99);  // flat sides: vertex normals are the face normals
    }
    // A straight square bar: 4 sides of 0.2 × L plus two 0.2² caps.
    Ref<IShape> bar = make("sweep", {{"path", std::string("points")}, {"points", std::string("0 0 0, 2 0 0")},
                                     {"profile", std::string("-0.1 -0.1, 0.1 -0.1, 0.1 0.1, -0.1 0.1")}, {"caps", true}});
    CHECK(bar->area() == Approx(4 * 0.2 * 2.0 + 2 * 0.04).epsilon(1e-5));
}

TEST_CASE("procedural shapes: bad parameters give one line naming file:line and the parameter", "[shapes][procedural]") {
    auto check = [](const std::string& shape, const std::string& needle) {
        std::string msg = sceneError(shape);
        INFO(msg);
        CHECK(msg.find("procedural.xml:2") != std::string::npos);
        CHECK(msg.find(needle) != std::string::npos);
        CHECK(msg.find('\n') == std::string::npos);
    };
    check(R"(<shape type="revolution"><string name="profile" value="1 0, -1 1"/></shape>)", "r = -1 < 0");
    check(R"(<shape type="revolution"><string name="profile" value="1 0"/></shape>)", "'profile': needs at least 2");
    check(R"(<shape type="revolution"><string name="profile" value="1 0, 1 x"/></shape>)", "'profile': tuple 2");
    check(R"(<shape type="revolution"><string name="profile" value="1 0, 1 0"/></shape>)", "coincide");
    check(R"(<shape type="revolution"><string name="profile" value="0 0, 0 1"/></shape>)", "on the axis");
    check(R"(<shape type="revolution"><string name="profile" value="1 0, 1 nan"/></shape>)", "non-finite");
    check(R"(<shape type="revolution"><string name="profile" value="1 0, 1 1"/><float name="phi_max" value="0"/></shape>)",
          "phi_max");
    check(R"(<shape type="sweep"><string name="path" value="points"/></shape>)", "needs the parameter 'points'");
    check(R"(<shape type="sweep"><string name="path" value="points"/><string name="points" value="0 0 0, 0 0 0"/></shape>)",
          "zero tangent");
    check(R"(<shape type="sweep"><float name="turns" value="0"/></shape>)", "no length");
    check(R"(<shape type="sweep"><string name="profile" value="0 0, 1 0, 1 1, 0.5 0.2, 0 1"/>)"
          R"(<boolean name="caps" value="true"/></shape>)",
          "star-shaped");
}
