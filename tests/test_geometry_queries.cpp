// Geometry on request (IShape::localGeometry, effigi::curvature): the curvature of
// spheres (1/r, 1/r², also scaled by to_world and turned inside out), cylinders (1/(2r),
// 0), rectangles (0) and tessellated spheres (within the tessellation's error), through
// an instance, and the object-space point; the `curvature` texture and the aov
// renderer's curvature, gaussian_curvature, object_position and shape_index outputs; and
// laziness: a render that asks for none of it never calls localGeometry().
#include "shape_helpers.hpp"

#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/render/scene.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <atomic>
#include <mutex>
#include <numbers>
#include <vector>

using namespace effigi;
using namespace effigi::test;

namespace {

Ref<IShape> make(const std::string& type, std::vector<std::pair<std::string, PropertyValue>> params) {
    Properties p("shape", type);
    for (auto& [k, v] : params) p.set(k, v);
    return makeShape(type, p);
}

/// The surface hits of n random rays from a sphere of radius 10 around `at` aimed near it
/// (seeded), each with its local geometry and curvature.
struct Probe {
    SurfaceInteraction si;
    LocalGeometry g;
    Curvature c;
};
std::vector<Probe> probe(const IShape& shape, int n, std::uint64_t seed, Point3f at = Point3f(0.f), float spread = 1.f) {
    PCG32 rng(seed, 7);
    std::vector<Probe> out;
    for (int i = 0; i < n; ++i) {
        Point3f o = at + 10.f * warp::squareToUniformSphere({rng.nextFloat(), rng.nextFloat()});
        Point3f target = at + spread * Vector3f(rng.nextFloat() - 0.5f, rng.nextFloat() - 0.5f, rng.nextFloat() - 0.5f);
        Ray ray{o, normalize(target - o), Infinity};
        Hit hit;
        if (!trace(shape, ray, hit)) continue;
        Probe p;
        p.si = shape.interaction(ray, hit);
        p.g = localGeometry(p.si);
        p.c = curvature(p.si, p.g);
        out.push_back(p);
    }
    return out;
}

/// Hits away from the parametrisation's degenerate points (a sphere's poles, where dp/du
/// vanishes and the curvature reads 0 by contract).
bool regular(const Probe& p) {
    return length(cross(p.si.dpdu, p.si.dpdv)) > 1e-3f * length(p.si.dpdu) * length(p.si.dpdv) && length(p.si.dpdu) > 1e-4f;
}

/// Every regular probe has mean curvature H and Gaussian K within tol (relative to |H|
/// and H²); returns how many were checked.
int checkCurvature(const std::vector<Probe>& probes, double H, double K, double tol) {
    int checked = 0;
    for (const Probe& p : probes) {
        if (!regular(p)) continue;
        ++checked;
        INFO("hit at " << p.si.p.x << ", " << p.si.p.y << ", " << p.si.p.z);
        CHECK(p.c.mean == Approx(H).margin(tol * std::abs(H)).epsilon(tol));
        CHECK(p.c.gaussian == Approx(K).margin(tol * H * H).epsilon(tol));
        CHECK(p.c.k1 >= p.c.k2);
        CHECK(double(p.c.k1 + p.c.k2) == Approx(2.0 * H).margin(2.0 * tol * std::abs(H) + 1e-6));
    }
    return checked;
}

/// A UV sphere of radius r as triangles with exact vertex normals and NO uv (so the
/// barycentric parametrisation is the one queried), from a test-only MeshShape.
class LatLongSphere final : public MeshShape {
public:
    LatLongSphere(float r, int nu, int nv) : MeshShape(Properties("shape", "test_latlong")) {
        TriangleMesh m;
        for (int j = 0; j <= nv; ++j)
            for (int i = 0; i <= nu; ++i) {
                double th = std::numbers::pi * j / nv, ph = 2.0 * std::numbers::pi * i / nu;
                Vector3f n(float(std::sin(th) * std::cos(ph)), float(std::sin(th) * std::sin(ph)), float(std::cos(th)));
                m.positions.push_back(Point3f(r * n));
                m.normals.push_back(n);
            }
        auto at = [&](int i, int j) { return std::uint32_t(j * (nu + 1) + i); };
        for (int j = 0; j < nv; ++j)
            for (int i = 0; i < nu; ++i) {
                // Outward winding: (θ, φ) increase along (south, east), whose cross is outward.
                if (j > 0) m.indices.insert(m.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j)});
                if (j < nv - 1) m.indices.insert(m.indices.end(), {at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)});
            }
        setMesh(std::move(m), "test lat-long sphere");
    }
};

/// How often localGeometry() was called on test_counting_sphere shapes.
std::atomic<int> g_localGeometryCalls{0};

/// A sphere (radius 0.5 at (3, 0, 0)) that counts the local-geometry queries it answers.
class CountingSphere final : public Implements<IShape> {
public:
    CountingSphere() {
        Properties p("shape", "sphere");
        p.set("radius", 0.5);
        p.set("center", PointValue{{3.f, 0.f, 0.f}});
        m_inner = query<IShape>(Registry::instance().create("shape", "sphere", p));
    }
    BBox3f bbox() const override { return m_inner->bbox(); }
    bool intersect(const Ray& r, float& t, Point2f& uv) const override { return m_inner->intersect(r, t, uv); }
    SurfaceInteraction interaction(const Ray& r, const Hit& h) const override {
        SurfaceInteraction si = m_inner->interaction(r, h);
        si.shape = this;
        return si;
    }
    LocalGeometry localGeometry(const SurfaceInteraction& si) const override {
        ++g_localGeometryCalls;
        return m_inner->localGeometry(si);
    }
    float area() const override { return m_inner->area(); }
    PositionSample samplePosition(const Point2f& u) const override { return m_inner->samplePosition(u); }
    const IBSDF* bsdf() const override { return m_inner->bsdf(); }
    const IEmitter* emitter() const override { return nullptr; }
    IEmitter* emitter() override { return nullptr; }

private:
    Ref<IShape> m_inner;
};

void registerCountingSphere() {
    static std::once_flag once;
    std::call_once(once, [] {
        Schema s("shape", "test_counting_sphere", "test component (tests/test_geometry_queries.cpp)");
        Registry::instance().add(
            ComponentInfo{s, [](const Properties&) -> Ref<IComponent> { return std::make_shared<CountingSphere>(); }, {}});
    });
}

/// A 16×16 scene looking down −z at `shape` (centred at x = 3) with `integrator`.
std::unique_ptr<Scene> sceneWith(const std::string& integrator, const std::string& shape) {
    const std::string text = "<scene version=\"3.0.0\">" + integrator +
                             "<sensor type=\"perspective\"><float name=\"fov\" value=\"10\"/>"
                             "<transform name=\"to_world\"><lookat origin=\"3, 0, 5\" target=\"3, 0, 0\" up=\"0, 1, 0\"/></transform>"
                             "<sampler type=\"independent\"><integer name=\"sample_count\" value=\"4\"/></sampler>"
                             "<film type=\"hdrfilm\"><integer name=\"width\" value=\"16\"/><integer name=\"height\" value=\"16\"/>"
                             "<rfilter type=\"box\"/></film></sensor>" +
                             shape + "</scene>";
    return loadScene(*xml::parseString(text, "geometry_queries.xml"));
}

Image render(Scene& scene) {
    RenderControl control;
    control.progress = false;
    control.seed = 3;
    scene.renderer().render(scene, control);
    return scene.camera().film().develop();
}

int channel(const Image& img, const std::string& name) {
    auto it = std::find(img.channelNames.begin(), img.channelNames.end(), name);
    INFO("channel " << name);
    REQUIRE(it != img.channelNames.end());
    return int(it - img.channelNames.begin());
}

const std::string SphereAt3 = "<shape type=\"sphere\"><float name=\"radius\" value=\"0.5\"/>"
                              "<transform name=\"to_world\"><translate x=\"3\"/></transform></shape>";

} // namespace

TEST_CASE("geometry queries: sphere curvature is 1/r and 1/r² and its object point is before to_world", "[geometry]") {
    // Object radius 0.8 scaled by 2.5: world radius 2, mean 0.5, Gaussian 0.25.
    const Transform tw = Transform::translate({4.f, -1.f, 2.f}) * Transform::rotate({1.f, 2.f, 0.5f}, 35.f) *
                         Transform::scale(Vector3f(2.5f));
    Ref<IShape> s = make("sphere", {{"radius", 0.8}, {"to_world", tw}});
    auto probes = probe(*s, 200, 1, Point3f(4.f, -1.f, 2.f), 3.f);
    CHECK(checkCurvature(probes, 0.5, 0.25, 1e-4) > 150);
    for (const Probe& p : probes) {
        // objectP lies on the object-space sphere and maps back to the hit.
        CHECK(length(Vector3f(p.g.objectP)) == Approx(0.8f).epsilon(1e-4));
        Point3f back = tw.point(p.g.objectP);
        CHECK(length(back - p.si.p) < 1e-4f);
    }

    SECTION("flip_normals turns the mean curvature negative, not the Gaussian") {
        Ref<IShape> f = make("sphere", {{"radius", 0.8}, {"to_world", tw}, {"flip_normals", true}});
        CHECK(checkCurvature(probe(*f, 200, 2, Point3f(4.f, -1.f, 2.f), 3.f), -0.5, 0.25, 1e-4) > 150);
    }
    SECTION("a translated sphere's object point is the hit minus the translation") {
        Ref<IShape> t = make("sphere", {{"radius", 0.5}, {"to_world", Transform::translate({3.f, 0.f, 0.f})}});
        for (const Probe& p : probe(*t, 50, 3, Point3f(3.f, 0.f, 0.f))) {
            CHECK(p.g.objectP.x == Approx(p.si.p.x - 3.f).margin(1e-5));
            CHECK(p.g.objectP.y == Approx(p.si.p.y).margin(1e-5));
            CHECK(p.g.objectP.z == Approx(p.si.p.z).margin(1e-5));
        }
    }
}

TEST_CASE("geometry queries: cylinder mean 1/(2r) and Gaussian 0 on the tube and flat caps", "[geometry]") {
    Ref<IShape> c = make("cylinder", {{"radius", 0.25}, {"p0", PointValue{{0.f, 0.f, -1.f}}}, {"p1", PointValue{{0.f, 0.f, 1.f}}},
                                      {"caps", true}, {"to_world", Transform::rotate({1.f, 0.f, 0.f}, 50.f)}});
    int tube = 0, caps = 0;
    for (const Probe& p : probe(*c, 600, 4, Point3f(0.f), 2.f)) {
        const bool onCap = std::abs(p.g.objectP.z) > 1.f - 1e-4f;
        INFO("object point " << p.g.objectP.x << ", " << p.g.objectP.y << ", " << p.g.objectP.z);
        if (onCap) {
            ++caps;
            CHECK(p.c.mean == 0.f);
            CHECK(p.c.gaussian == 0.f);
        } else {
            ++tube;
            CHECK(p.c.mean == Approx(2.0).epsilon(1e-4));  // 1 / (2 · 0.25)
            CHECK(p.c.gaussian == Approx(0.0).margin(1e-4));
            CHECK(p.c.k1 == Approx(4.0).epsilon(1e-4));
            CHECK(p.c.k2 == Approx(0.0).margin(1e-4));
            CHECK(std::hypot(p.g.objectP.x, p.g.objectP.y) == Approx(0.25).epsilon(1e-4));
        }
    }
    CHECK(tube > 50);
    CHECK(caps > 5);
}

TEST_CASE("geometry queries: a rectangle is flat and its object point lies in the unit square at z = 0", "[geometry]") {
    const Transform tw = Transform::translate({0.f, 1.f, 0.f}) * Transform::rotate({0.f, 1.f, 1.f}, 60.f) *
                         Transform::scale({3.f, 0.5f, 1.f});
    Ref<IShape> r = make("rectangle", {{"to_world", tw}});
    auto probes = probe(*r, 300, 5, Point3f(0.f, 1.f, 0.f), 2.f);
    REQUIRE(probes.size() > 30);
    for (const Probe& p : probes) {
        CHECK(p.c.mean == 0.f);
        CHECK(p.c.gaussian == 0.f);
        CHECK(p.g.objectP.z == Approx(0.f).margin(1e-5));
        CHECK(std::abs(p.g.objectP.x) <= 1.f + 1e-5f);
        CHECK(std::abs(p.g.objectP.y) <= 1.f + 1e-5f);
    }
}

TEST_CASE("geometry queries: tessellated spheres read 1/r within the tessellation error", "[geometry]") {
    // Lat-long mesh of radius 1.5 (64 × 32, no uv: barycentric parametrisation). Its
    // interpolated normals are those of the point's direction from the centre, so the
    // estimate is off only by the chord sag and the tilt of the triangle's plane to the
    // normal, both of order (π/32)² ≈ 1 %: within 1 % (seen: 0.5 % on K, less on H).
    SECTION("barycentric parametrisation") {
        LatLongSphere mesh(1.5f, 64, 32);
        CHECK(checkCurvature(probe(mesh, 300, 6), 1.0 / 1.5, 1.0 / (1.5 * 1.5), 0.01) > 250);
    }
    // revolution of a half circle of radius 1.5 (Catmull–Rom through 33 points, 128
    // segments): the mesh's uv parametrisation; the spline's own curvature departs from
    // the circle's between the points, and the chords add the error above: within 1 %.
    SECTION("uv parametrisation (revolution)") {
        std::string profile;
        const int K = 32;
        for (int k = 0; k <= K; ++k) {
            double t = std::numbers::pi * k / K;
            profile += fmt::format("{}{:.9g} {:.9g}", k ? ", " : "", k == K || k == 0 ? 0.0 : 1.5 * std::sin(t), -1.5 * std::cos(t));
        }
        Ref<IShape> rev = make("revolution", {{"profile", profile}, {"interpolation", std::string("catmullrom")},
                                              {"segments", 128}, {"rings", 4}});
        CHECK(checkCurvature(probe(*rev, 300, 7), 1.0 / 1.5, 1.0 / (1.5 * 1.5), 0.01) > 250);
    }
}

TEST_CASE("geometry queries: an instance scaled by 2 halves the curvature and answers in group space", "[geometry][instancing]") {
    Properties sp("shape", "sphere");
    sp.set("radius", 0.5);
    sp.set("center", PointValue{{0.2f, 0.f, 0.f}});
    Properties gp("shape", "shapegroup");
    gp.set("s", ComponentValue{"shape", Registry::instance().create("shape", "sphere", sp)});
    Properties ip("shape", "instance");
    const Transform tw = Transform::translate({1.f, 2.f, 3.f}) * Transform::rotate({0.f, 0.f, 1.f}, 30.f) *
                         Transform::scale(Vector3f(2.f));
    ip.set("shapegroup", ComponentValue{"shape", Registry::instance().create("shape", "shapegroup", gp)});
    ip.set("to_world", tw);
    Ref<IShape> inst = makeShape("instance", ip);
    auto probes = probe(*inst, 200, 8, tw.point(Point3f(0.2f, 0.f, 0.f)), 1.5f);
    REQUIRE(probes.size() > 100);
    for (const Probe& p : probes) {
        CHECK(p.si.instance == inst.get());
        CHECK(p.si.shape != inst.get());  // the member, with its mesh/media
        // The member sphere has no to_world: its object space is the group's.
        CHECK(length(p.g.objectP - Point3f(0.2f, 0.f, 0.f)) == Approx(0.5f).epsilon(1e-4));
        CHECK(length(tw.point(p.g.objectP) - p.si.p) < 1e-4f);
    }
    CHECK(checkCurvature(probes, 1.0, 1.0, 1e-4) > 100);  // world radius 1
}

TEST_CASE("geometry queries: a unit sphere instanced with scale (1 2 3) has an ellipsoid's curvatures", "[geometry][instancing]") {
    // Non-uniform: the normal derivatives go through the normals' matrix. For the
    // ellipsoid x²/a² + y²/b² + z²/c² = 1 with h² = x²/a⁴ + y²/b⁴ + z²/c⁴ (outward normals):
    // K = 1 / (a²b²c² h⁴), H = (a² + b² + c² − |p|²) / (2 a²b²c² h³).
    Properties gp("shape", "shapegroup");
    Properties sp("shape", "sphere");
    gp.set("s", ComponentValue{"shape", Registry::instance().create("shape", "sphere", sp)});
    Properties ip("shape", "instance");
    ip.set("shapegroup", ComponentValue{"shape", Registry::instance().create("shape", "shapegroup", gp)});
    ip.set("to_world", Transform::scale({1.f, 2.f, 3.f}));
    Ref<IShape> inst = makeShape("instance", ip);
    const double a = 1, b = 2, c = 3, abc2 = a * a * b * b * c * c;
    int n = 0;
    for (const Probe& p : probe(*inst, 300, 10, Point3f(0.f), 3.f)) {
        if (!regular(p)) continue;
        ++n;
        const Vector3d q(p.si.p);
        const double h = std::sqrt(q.x * q.x / (a * a * a * a) + q.y * q.y / (b * b * b * b) + q.z * q.z / (c * c * c * c));
        const double K = 1.0 / (abc2 * h * h * h * h), H = (a * a + b * b + c * c - glm::dot(q, q)) / (2.0 * abc2 * h * h * h);
        INFO("hit " << q.x << ", " << q.y << ", " << q.z);
        CHECK(p.c.gaussian == Approx(K).epsilon(1e-3));
        CHECK(p.c.mean == Approx(H).epsilon(1e-3));
        CHECK(length(Vector3f(p.g.objectP)) == Approx(1.f).epsilon(1e-4));
    }
    CHECK(n > 200);
}

TEST_CASE("geometry queries: the curvature texture on a sphere reads bias + scale · curvature", "[geometry][texture]") {
    Ref<IShape> s = make("sphere", {{"radius", 2.0}});
    auto texture = [](std::vector<std::pair<std::string, PropertyValue>> params) {
        Properties p("texture", "curvature");
        for (auto& [k, v] : params) p.set(k, v);
        Ref<ITexture> t = query<ITexture>(Registry::instance().create("texture", "curvature", p));
        REQUIRE(t);
        return t;
    };
    Ref<ITexture> mean = texture({{"scale", 0.8}, {"bias", 0.1}});                             // 0.1 + 0.8 / 2
    Ref<ITexture> gauss = texture({{"kind", std::string("gaussian")}, {"scale", 2.0}});         // 2 / 4
    Ref<ITexture> big = texture({{"kind", std::string("max")}, {"scale", 10.0}, {"clamp", false}});  // 10 / 2
    Ref<ITexture> clamped = texture({{"kind", std::string("min")}, {"scale", 10.0}});           // 5 → 1
    const SampledWavelengths lambda = SampledWavelengths::sampleVisible(0.4f);
    int n = 0;
    for (const Probe& p : probe(*s, 100, 9, Point3f(0.f), 3.f)) {
        if (!regular(p)) continue;
        ++n;
        CHECK(mean->evalFloat(p.si) == Approx(0.5f).epsilon(1e-4));
        CHECK(mean->eval(p.si, lambda)[0] == Approx(0.5f).epsilon(1e-4));
        CHECK(gauss->evalFloat(p.si) == Approx(0.5f).epsilon(1e-4));
        CHECK(big->evalFloat(p.si) == Approx(5.f).epsilon(1e-4));
        CHECK(clamped->evalFloat(p.si) == 1.f);
    }
    CHECK(n > 50);
    // Bad kind: one-line error naming the parameter.
    Properties bad("texture", "curvature");
    bad.set("kind", std::string("mead"));
    requireThrowsNaming([&] { Registry::instance().create("texture", "curvature", bad); }, "kind");
}

TEST_CASE("geometry queries: aov curvature and gaussian_curvature and object_position and shape_index", "[geometry][aov]") {
    auto scene = sceneWith("<integrator type=\"aov\"><string name=\"aovs\" value=\"h:curvature, k:gaussian_curvature, "
                           "o:object_position, s:shape_index, i:prim_index\"/></integrator>",
                           "<shape type=\"rectangle\"><transform name=\"to_world\"><translate z=\"-5\"/></transform></shape>" +
                               SphereAt3);
    Image img = render(*scene);
    const int h = channel(img, "h.H"), k = channel(img, "k.K"), ox = channel(img, "o.X"), oz = channel(img, "o.Z"),
              s = channel(img, "s.I");
    // The central pixels see only the sphere of radius 0.5 (box filter: each pixel is the
    // mean of its own samples): H = 2, K = 4, object point on the sphere facing the camera.
    for (int y = 6; y < 10; ++y)
        for (int x = 6; x < 10; ++x) {
            INFO("pixel " << x << ", " << y);
            CHECK(img.at(x, y, h) == Approx(2.f).epsilon(1e-3));
            CHECK(img.at(x, y, k) == Approx(4.f).epsilon(1e-3));
            CHECK(std::abs(img.at(x, y, ox)) < 0.15f);
            CHECK(img.at(x, y, oz) > 0.45f);
            CHECK(img.at(x, y, s) == 2.f);  // the second shape of the scene, 1-based
        }
}

TEST_CASE("geometry queries are lazy: a render that asks for none never calls localGeometry", "[geometry][lazy]") {
    registerCountingSphere();
    g_localGeometryCalls = 0;
    auto plain = sceneWith("<integrator type=\"path\"/><emitter type=\"constant\"/>",
                           "<shape type=\"test_counting_sphere\"/>");
    render(*plain);
    auto aovs = sceneWith("<integrator type=\"aov\"><string name=\"aovs\" value=\"d:depth, n:sh_normal, p:position\"/></integrator>",
                          "<shape type=\"test_counting_sphere\"/>");
    render(*aovs);
    CHECK(g_localGeometryCalls == 0);
    // The counter sees the queries when they are made: the curvature AOV asks once per hit.
    auto asking = sceneWith("<integrator type=\"aov\"><string name=\"aovs\" value=\"h:curvature\"/></integrator>",
                            "<shape type=\"test_counting_sphere\"/>");
    render(*asking);
    CHECK(g_localGeometryCalls > 0);
}
