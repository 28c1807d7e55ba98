// Constructive solid geometry (shape/csg): exact crossings of spheres minus spheres,
// lenses and unions against their closed forms, normals turned on the walls of holes, the
// BSDF of the part hit (and the csg's own for parts without one), closed meshes and
// capped cylinders as parts, nesting, the same hits under every accelerator, a rendered
// silhouette against its analytic area, the shape conformance suite on a configuration,
// and bad input (open parts, emitters) failing with one line naming file:line.
#include "app_runner.hpp"
#include "conform_session.hpp"
#include "conformance/conformance.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"
#include "temp_files.hpp"
#include "xml_helpers.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <numbers>
#include <string>

using namespace effigi;
using effigi::test::errorOf;

namespace {

const char* const Accelerators[] = {"embree", "bvh", "kdtree", "bruteforce"};

std::string sceneXml(const std::string& body, const std::string& accel = "embree") {
    return "<scene version=\"3.0.0\">\n<accelerator type=\"" + accel +
           "\"/>\n<sensor type=\"perspective\"><film type=\"hdrfilm\"><integer name=\"width\" value=\"4\"/>"
           "<integer name=\"height\" value=\"4\"/></film></sensor>\n" +
           body + "</scene>\n";
}
std::unique_ptr<Scene> load(const std::string& text) { return loadScene(*xml::parseString(text, "inline.xml")); }

std::string sphere(float x, float y, float z, float r, const std::string& inner = "") {
    return fmt::format("<shape type=\"sphere\"><point name=\"center\" x=\"{}\" y=\"{}\" z=\"{}\"/>"
                       "<float name=\"radius\" value=\"{}\"/>{}</shape>\n", x, y, z, r, inner);
}
std::string bsdf(const std::string& id) { return "<bsdf type=\"diffuse\" id=\"" + id + "\"/>"; }
std::string csg(const std::string& op, const std::string& parts, const std::string& extra = "") {
    return "<shape type=\"csg\"><string name=\"operation\" value=\"" + op + "\"/>\n" + parts + extra + "</shape>\n";
}

/// A = unit sphere at the origin (BSDF "a"), B = radius 0.5 at (1, 0, 0) (BSDF "b"): A − B.
const std::string Bitten = csg("difference", sphere(0, 0, 0, 1, bsdf("a")) + sphere(1, 0, 0, 0.5f, bsdf("b")));
/// Spheres of radius 1 at x = ∓0.5 (BSDFs "a", "b").
std::string pair(const std::string& op) { return csg(op, sphere(-0.5f, 0, 0, 1, bsdf("a")) + sphere(0.5f, 0, 0, 1, bsdf("b"))); }

struct Expect {
    Point3f o;
    Vector3f d;
    float t;        // < 0: a miss
    Normal3f n;
    const char* bsdf;
};

void checkHits(const Scene& scene, std::initializer_list<Expect> cases) {
    for (const Expect& e : cases) {
        INFO("ray o = (" << e.o.x << ", " << e.o.y << ", " << e.o.z << "), d = (" << e.d.x << ", " << e.d.y << ", " << e.d.z << ")");
        SurfaceInteraction si;
        bool hit = scene.intersect(Ray{e.o, e.d, Infinity}, si);
        CHECK(scene.occluded(Ray{e.o, e.d, Infinity}) == hit);
        if (e.t < 0.f) {
            CHECK_FALSE(hit);
            continue;
        }
        REQUIRE(hit);
        CHECK(si.t == Approx(e.t).epsilon(1e-5));
        CHECK(length(si.p - (e.o + e.t * e.d)) < 1e-5f);
        CHECK(length(si.n - e.n) < 1e-5f);
        CHECK(dot(si.shading.n, si.n) > 0.9999f);
        CHECK(std::abs(dot(si.shading.s, si.shading.n)) < 1e-5f);
        CHECK(length(cross(si.shading.s, si.shading.t) - si.shading.n) < 1e-5f);
        CHECK(length(si.wo + normalize(e.d)) < 1e-6f);
        REQUIRE(si.bsdf);
        CHECK(si.bsdf->id() == e.bsdf);
        // A ray stopping just short of the hit is not blocked.
        CHECK_FALSE(scene.occluded(Ray{e.o, e.d, e.t * (1.f - 1e-4f)}));
    }
}

const Vector3f X(1, 0, 0), Y(0, 1, 0), Z(0, 0, 1);

} // namespace

TEST_CASE("csg: a sphere minus a sphere has exact walls with inward normals in the bite", "[csg]") {
    auto scene = load(sceneXml(Bitten));
    const float c = std::sqrt(1.f - 0.36f);  // A's wall at x = 0.6: z = ±0.8
    checkHits(*scene, {
        // Along −x through the bite: B's wall at x = 0.5 (inside A), normal into the bite.
        {{3, 0, 0}, -X, 2.5f, X, "b"},
        // From inside the material on through A's far side.
        {{0, 0, 0}, -X, 1.f, -X, "a"},
        // Down x = 0.6: A's top, then from inside the material into the bite (leaving the
        // solid along B's wall, normal −n_B), then from the bite back into the material.
        {{0.6f, 0, 3}, -Z, 3.f - c, {0.6f, 0, c}, "a"},
        {{0.6f, 0, 0.5f}, -Z, 0.2f, {0.8f, 0, -0.6f}, "b"},
        {{0.6f, 0, 0}, -Z, 0.3f, {0.8f, 0, 0.6f}, "b"},
        // x = 0.9: B covers all of A's chord, the ray passes through the hole.
        {{0.9f, 0, 3}, -Z, -1.f, {}, ""},
        // Missing A, through B only: nothing.
        {{1.2f, 0, 3}, -Z, -1.f, {}, ""},
        // Far from the bite: A alone.
        {{0, 0, 3}, -Z, 2.f, Z, "a"},
    });
}

TEST_CASE("csg: the intersection of two spheres is a lens and their union a peanut", "[csg]") {
    auto lens = load(sceneXml(pair("intersection")));
    const float rim = std::sqrt(0.75f);
    checkHits(*lens, {
        {{3, 0, 0}, -X, 2.5f, X, "a"},         // the left sphere's cap faces +x
        {{0, 0, 0}, -X, 0.5f, -X, "b"},        // from inside: out through the right one's cap
        {{0.2f, 3, 0}, -Y, 3.f - std::sqrt(0.51f), {0.7f, std::sqrt(0.51f), 0}, "a"},
        {{0, rim + 0.01f, 3}, -Z, -1.f, {}, ""},  // just beyond the rim (x = 0, y² = 3/4): a miss
        {{0.3f, 0, 3}, -Z, 3.f - std::sqrt(1.f - 0.64f), {0.8f, 0, std::sqrt(0.36f)}, "a"},
    });
    auto peanut = load(sceneXml(pair("union")));
    checkHits(*peanut, {
        {{3, 0, 0}, -X, 1.5f, X, "b"},
        {{-3, 0, 0}, X, 1.5f, -X, "a"},
        {{0.2f, 0, 0}, Z, std::sqrt(1.f - 0.09f), {-0.3f, 0, std::sqrt(0.91f)}, "b"},  // out through b
        {{0, 0, 0}, X, 1.5f, X, "b"},          // no crossing where the two overlap
    });
}

TEST_CASE("csg: area() estimates the boundary's area", "[csg]") {
    // Closed forms from spherical caps (area 2π r h): the lens is two caps of height 1/2,
    // the peanut two spheres less those caps; the bitten sphere keeps A less its cap of
    // height 1/8 and gains B's cap of height 3/8 (the planes meet at x = 7/8).
    const double pi = std::numbers::pi;
    struct Case {
        std::string xml;
        double area;
    };
    for (const Case& c : {Case{pair("intersection"), 2.0 * pi}, Case{pair("union"), 6.0 * pi},
                          Case{Bitten, 4.0 * pi - 2.0 * pi * 0.125 + 2.0 * pi * 0.5 * 0.375}}) {
        auto scene = load(sceneXml(c.xml));
        REQUIRE(scene->shapes().size() == 1);
        INFO(c.xml);
        CHECK(scene->shapes()[0]->area() == Approx(c.area).epsilon(2e-3));
    }
}

TEST_CASE("csg: parts without a bsdf take the nearest enclosing csg's", "[csg]") {
    // Inner union: a with its own BSDF, a plain sphere; the outer csg supplies "outer".
    const std::string inner = csg("union", sphere(-0.5f, 0, 0, 0.6f, bsdf("a")) + sphere(0.5f, 0, 0, 0.6f));
    auto scene = load(sceneXml(csg("union", inner + sphere(0, 3, 0, 0.5f), bsdf("outer"))));
    checkHits(*scene, {
        {{-3, 0, 0}, X, 1.9f, -X, "a"},
        {{3, 0, 0}, -X, 1.9f, X, "outer"},
        {{0, 6, 0}, -Y, 2.5f, Y, "outer"},
    });
    // Without any <bsdf> on the csgs, a plain part keeps its default diffuse one.
    auto plain = load(sceneXml(csg("union", sphere(-0.5f, 0, 0, 0.6f, bsdf("a")) + sphere(0.5f, 0, 0, 0.6f))));
    SurfaceInteraction si;
    REQUIRE(plain->intersect(Ray{{3, 0, 0}, -X, Infinity}, si));
    REQUIRE(si.bsdf);
    CHECK(si.bsdf->id().empty());
    CHECK(si.bsdf->typeName() == "bsdf/diffuse");
}

TEST_CASE("csg: flip_normals turns the csg's normals, not its parts' insides", "[csg]") {
    const std::string flippedPart =
        csg("difference", sphere(0, 0, 0, 1, bsdf("a")) +
                              sphere(1, 0, 0, 0.5f, bsdf("b") + "<boolean name=\"flip_normals\" value=\"true\"/>"));
    checkHits(*load(sceneXml(flippedPart)), {{{3, 0, 0}, -X, 2.5f, X, "b"}, {{0, 0, 3}, -Z, 2.f, Z, "a"}});
    const std::string flipped = csg("difference", sphere(0, 0, 0, 1, bsdf("a")) + sphere(1, 0, 0, 0.5f, bsdf("b")),
                                    "<boolean name=\"flip_normals\" value=\"true\"/>");
    checkHits(*load(sceneXml(flipped)), {{{3, 0, 0}, -X, 2.5f, -X, "b"}, {{0, 0, 3}, -Z, 2.f, -Z, "a"}});
}

TEST_CASE("csg: closed meshes capped cylinders and nested csgs as parts", "[csg]") {
    // A cube pierced along z by a capped cylinder, minus it: a square tube. The same
    // box as an OBJ file (wound inward on purpose: the part's orientation is its own
    // business) gives the same hits.
    test::ScratchDir dir("csg");
    const std::string obj = dir.write("box.obj",
        "v -1 -1 -1\nv 1 -1 -1\nv 1 1 -1\nv -1 1 -1\nv -1 -1 1\nv 1 -1 1\nv 1 1 1\nv -1 1 1\n"
        "f 1 2 3\nf 1 3 4\nf 5 7 6\nf 5 8 7\nf 1 5 6\nf 1 6 2\nf 2 6 7\nf 2 7 3\nf 3 7 8\nf 3 8 4\nf 4 8 5\nf 4 5 1\n").string();
    const std::string cylinder = "<shape type=\"cylinder\"><point name=\"p0\" x=\"0\" y=\"0\" z=\"-2\"/>"
                                 "<point name=\"p1\" x=\"0\" y=\"0\" z=\"2\"/><float name=\"radius\" value=\"0.5\"/>"
                                 "<boolean name=\"caps\" value=\"true\"/>" + bsdf("hole") + "</shape>\n";
    for (const std::string& box : {std::string("<shape type=\"cube\">") + bsdf("box") + "</shape>\n",
                                   "<shape type=\"obj\"><string name=\"filename\" value=\"" + obj + "\"/>" + bsdf("box") +
                                       "<boolean name=\"face_normals\" value=\"true\"/></shape>\n"}) {
        INFO(box);
        auto scene = load(sceneXml(csg("difference", box + cylinder)));
        checkHits(*scene, {
            {{3, 0, 0}, -X, 2.f, X, "box"},
            {{0.75f, 0, 0}, -X, 0.25f, -X, "hole"},      // from the material into the hole
            {{0, 0, 0}, X, 0.5f, -X, "hole"},            // from the hole into the material
            {{0.2f, 0.1f, 3}, -Z, -1.f, {}, ""},         // down the hole: nothing
            {{0.7f, 0, 3}, -Z, 2.f, Z, "box"},
        });
    }
    // Nested: (cube ∩ sphere) − cylinder; a ray along the diagonal is cut by the sphere.
    const std::string tree = csg("difference", csg("intersection", "<shape type=\"cube\">" + bsdf("box") + "</shape>\n" +
                                                                        sphere(0, 0, 0, 1.3f, bsdf("ball"))) + cylinder);
    const Vector3f diag = normalize(Vector3f(-1, -1, -1));
    checkHits(*load(sceneXml(tree)), {
        {{3, 3, 3}, diag, std::sqrt(27.f) - 1.3f, -diag, "ball"},
        {{3, 0, 0}, -X, 2.f, X, "box"},
        {{0.2f, 0.1f, 3}, -Z, -1.f, {}, ""},
    });
}

TEST_CASE("csg: rays leaving the surface do not hit it again", "[csg]") {
    // A lens is convex: a ray leaving a point of its surface outward hits nothing, one
    // leaving inward hits the far side (not the point it left), at every scale.
    PCG32 rng(5, 9);
    for (float scale : {1e-4f, 1.f, 1e4f}) {
        INFO("scale " << scale);
        auto scene = load(sceneXml(csg("intersection", sphere(-0.5f * scale, 0.2f * scale, 0, scale) +
                                                           sphere(0.5f * scale, 0.2f * scale, 0, scale))));
        const IShape& lens = *scene->shapes()[0];
        int selfHits = 0, missed = 0, tried = 0;
        for (int i = 0; i < 2000; ++i) {
            PositionSample ps = lens.samplePosition({rng.nextFloat(), rng.nextFloat()});
            if (!(ps.pdf > 0.f)) continue;
            ++tried;
            Vector3f d = warp::squareToUniformSphere({rng.nextFloat(), rng.nextFloat()});
            SurfaceInteraction si;
            si.p = ps.p;
            si.n = ps.n;
            float t;
            Point2f uv;
            bool hit = lens.intersect(si.spawnRay(d), t, uv);
            if (dot(d, ps.n) > 0.f) selfHits += hit;
            else missed += !hit || !(t * length(d) > 1e-5f * scale);
        }
        CHECK(tried > 1990);
        CHECK(selfHits == 0);
        CHECK(missed == 0);
    }
}

TEST_CASE("csg: every accelerator gives the same hits", "[csg]") {
    const std::string body = Bitten + csg("intersection", sphere(1.5f, 1.5f, 0, 0.6f) + sphere(1.9f, 1.5f, 0, 0.6f)) +
                             csg("union", "<shape type=\"cube\"><transform name=\"to_world\"><scale value=\"0.4\"/>"
                                          "<translate x=\"-1.5\" y=\"1\"/></transform></shape>" +
                                              sphere(-1.5f, 1.4f, 0.2f, 0.3f));
    auto reference = load(sceneXml(body, "bruteforce"));
    PCG32 rng(11, 3);
    std::vector<Ray> rays;
    for (int i = 0; i < 2000; ++i) {
        Point3f o = 5.f * warp::squareToUniformSphere({rng.nextFloat(), rng.nextFloat()});
        Point3f target(4.f * rng.nextFloat() - 2.f, 3.f * rng.nextFloat() - 1.f, 2.f * rng.nextFloat() - 1.f);
        rays.push_back(Ray{o, normalize(target - o), rng.nextFloat() < 0.3f ? 6.f * rng.nextFloat() : Infinity});
    }
    for (const char* accel : Accelerators) {
        INFO("accelerator " << accel);
        auto scene = load(sceneXml(body, accel));
        int hits = 0, differ = 0;
        for (const Ray& r : rays) {
            SurfaceInteraction a, b;
            bool ha = scene->intersect(r, a), hb = reference->intersect(r, b);
            if (scene->occluded(r) != hb) ++differ;
            if (ha != hb || (ha && (a.t != b.t || a.n != b.n || a.p != b.p || a.bsdf->id() != b.bsdf->id()))) ++differ;
            hits += hb;
        }
        CHECK(hits > 500);
        CHECK(differ == 0);
    }
}

TEST_CASE("csg: a rendered cube with a hole has the analytic silhouette", "[csg][render]") {
    // Seen along z by an orthographic camera over [-1, 1]²: a cube of half-size 0.5 minus a
    // capped cylinder of radius 0.25 along z covers 1 − π/16 of the 4 units viewed. The
    // diffuse (albedo 0.5) faces under a uniform sky of radiance 1 are 0.5; the sky and the
    // hole are 1. Pixels below 0.75 are counted: the square's edges lie on pixel borders,
    // the circle's 50 edge pixels split about evenly (a few pixels of error), so the count
    // matches the area to 1 %; a hole missing or not cut through would be 24 % off.
    const std::string xml = R"(<scene version="3.0.0">
      <integrator type="path"><integer name="max_depth" value="4"/></integrator>
      <sensor type="orthographic">
        <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
        <film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="64"/>
          <rfilter type="box"/></film>
      </sensor>
      <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
      <shape type="csg"><string name="operation" value="difference"/>
        <shape type="cube"><transform name="to_world"><scale value="0.5"/></transform></shape>
        <shape type="cylinder"><point name="p0" x="0" y="0" z="-1"/><point name="p1" x="0" y="0" z="1"/>
          <float name="radius" value="0.25"/><boolean name="caps" value="true"/></shape>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
      </shape>
    </scene>)";
    auto scene = load(xml);
    RenderControl control;
    control.progress = false;
    RenderStats stats = scene->renderer().render(*scene, control);
    CHECK(stats.rejectedSamples == 0);
    Image img = scene->camera().film().develop();
    int covered = 0;
    double body = 0.0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            double v = (img.at(x, y, 0) + img.at(x, y, 1) + img.at(x, y, 2)) / 3.0;
            REQUIRE(std::isfinite(v));
            if (v < 0.75) ++covered, body += v;
        }
    const double expected = (1.0 - std::numbers::pi / 16.0) / 4.0 * img.width * img.height;
    INFO("covered " << covered << " pixels, expected " << expected);
    CHECK(std::abs(covered - expected) < 0.01 * expected);
    CHECK(body / covered == Approx(0.5).epsilon(0.1));
}

TEST_CASE("csg: the shape conformance suite passes on a bitten sphere", "[csg][conformance]") {
    auto out = test::tempDir("conform-csg");
    conform::Options o;
    o.tag = "shape";
    o.component = "csg";
    o.quick = true;
    o.outDir = out;
    conform::Session s(o);
    std::vector<conform::Job> jobs = s.plan();
    REQUIRE(jobs.size() >= 5);
    s.runJob(jobs.front());
    s.finish();
    INFO(test::sessionTable(s));
    CHECK(s.count(conform::Verdict::Fail) == 0);
    CHECK(s.count(conform::Verdict::Pass) >= 12);
    std::filesystem::remove_all(out);
}

TEST_CASE("csg: bad input fails with one line naming file:line", "[csg]") {
    auto expect = [](const std::string& text, const std::string& marker, const std::string& needle) {
        std::string e = errorOf([&] { load(text); });
        INFO(e);
        CHECK(e.find('\n') == std::string::npos);
        std::size_t at = text.find(marker);
        REQUIRE(at != std::string::npos);
        int line = 1 + int(std::count(text.begin(), text.begin() + std::ptrdiff_t(at), '\n'));
        CHECK(e.find(fmt::format("inline.xml:{}", line)) != std::string::npos);
        CHECK(e.find(needle) != std::string::npos);
    };
    const std::string ball = sphere(0, 0, 0, 1);
    expect(sceneXml(csg("union", ball + "\n<shape type=\"rectangle\"/>")), "<shape type=\"rectangle\"", "not a closed solid");
    expect(sceneXml(csg("union", ball + "\n<shape type=\"disk\"/>")), "<shape type=\"disk\"", "not closed");
    expect(sceneXml(csg("union", ball + "\n<shape type=\"cylinder\"/>")), "<shape type=\"cylinder\"", "caps");
    expect(sceneXml(csg("union", ball + sphere(1, 0, 0, 1), "\n<emitter type=\"area\"/>")), "<emitter",
           "csg shapes cannot be emitters");
    expect(sceneXml(csg("union", ball + "\n" + sphere(1, 0, 0, 1, "<emitter type=\"area\"/>"))),
           "<shape type=\"sphere\"><point name=\"center\" x=\"1\"", "csg shapes cannot be emitters");
    expect(sceneXml("\n" + csg("union", ball)), "<shape type=\"csg\"", "two or more");
    expect(sceneXml("<shape type=\"csg\">\n<string name=\"operation\" value=\"xor\"/>" + ball + ball + "</shape>"),
           "value=\"xor\"", "operation");
}
