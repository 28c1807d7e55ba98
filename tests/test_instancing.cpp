// Instancing (shapegroup + instance): hits through an instance agree with the same shapes
// placed directly, under every accelerator; a shapegroup alone is invisible; bad input
// fails with file:line; many instances share one group; and a small scene agrees with
// Mitsuba 3 end to end.
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"
#include "image_helpers.hpp"
#include "xml_helpers.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

using namespace effigi;
using effigi::test::errorOf;

namespace {

const char* const Accelerators[] = {"embree", "bvh", "kdtree", "bruteforce"};

std::string sceneXml(const std::string& accel, const std::string& body) {
    return "<scene version=\"3.0.0\">\n"
           "<accelerator type=\"" + accel + "\"/>\n"
           "<sensor type=\"perspective\"><film type=\"hdrfilm\"><integer name=\"width\" value=\"4\"/>"
           "<integer name=\"height\" value=\"4\"/></film></sensor>\n" +
           body + "</scene>\n";
}

std::unique_ptr<Scene> load(const std::string& text) { return loadScene(*xml::parseString(text, "inline.xml")); }

/// 1-based line of the first occurrence of marker in text (where an error must point).
int lineOf(const std::string& text, const std::string& marker) {
    std::size_t at = text.find(marker);
    REQUIRE(at != std::string::npos);
    return 1 + int(std::count(text.begin(), text.begin() + std::ptrdiff_t(at), '\n'));
}

// Members with their own transforms and distinct (id-named) BSDFs, so a hit names its member.
const std::string Members = R"(
    <shape type="cube"><transform name="to_world"><scale x="0.5" y="0.3" z="0.4"/><translate x="-1"/></transform>
        <bsdf type="diffuse" id="b_cube"/></shape>
    <shape type="rectangle"><transform name="to_world"><rotate y="1" angle="-70"/><translate x="1" z="0.2"/></transform>
        <bsdf type="diffuse" id="b_rect"/></shape>
)";
const std::string SphereMember = R"(
    <shape type="sphere"><point name="center" x="0.2" y="0.5" z="0"/><float name="radius" value="0.4"/>
        <bsdf type="diffuse" id="b_sphere"/></shape>
)";

std::string group(const std::string& members) {
    return "<shape type=\"shapegroup\" id=\"g\">" + members + "</shape>\n";
}
std::string instance(const std::string& ops) {
    return "<shape type=\"instance\"><ref id=\"g\"/><transform name=\"to_world\">" + ops + "</transform></shape>\n";
}
/// The members placed directly: each member's own ops followed by the instance's.
std::string direct(const std::string& members, const std::string& ops) {
    std::string out = members;
    for (std::size_t at = 0; (at = out.find("</transform>", at)) != std::string::npos; at += ops.size() + 12)
        out.insert(at, ops);
    // The sphere has no transform of its own: give it the instance's.
    for (std::size_t at = 0; (at = out.find("<shape type=\"sphere\">", at)) != std::string::npos; ++at)
        out.insert(at + 21, "<transform name=\"to_world\">" + ops + "</transform>");
    return out;
}

/// Random rays from a sphere of radius 8 aimed at random points near the origin
/// (seeded), so most of them hit something.
std::vector<Ray> randomRays(int n, std::uint64_t seed, float scale = 1.f) {
    PCG32 rng(seed, 1);
    std::vector<Ray> rays;
    for (int i = 0; i < n; ++i) {
        Point3f o = 8.f * warp::squareToUniformSphere({rng.nextFloat(), rng.nextFloat()});
        Point3f target(3.f * rng.nextFloat() - 1.5f, 3.f * rng.nextFloat() - 1.5f, 3.f * rng.nextFloat() - 1.5f);
        rays.push_back(Ray{scale * o, normalize(target - o), Infinity});
    }
    return rays;
}

/// Compare two scenes hit by hit. A ray may hit in one and graze past an edge in the
/// other (the two sides use different triangle tests): at most 0.5 % such rays.
/// `scale`: the scenes' size (rays and distances scale with it).
void compareHits(const Scene& a, const Scene& b, float tol, float scale = 1.f) {
    std::vector<Ray> rays = randomRays(3000, 7, scale);
    int hits = 0, disagree = 0;
    for (const Ray& r : rays) {
        SurfaceInteraction sa, sb;
        bool ha = a.intersect(r, sa), hb = b.intersect(r, sb);
        CHECK(a.occluded(r) == ha);
        if (ha != hb) {
            ++disagree;
            continue;
        }
        if (!ha) continue;
        ++hits;
        INFO("ray o=(" << r.o.x << "," << r.o.y << "," << r.o.z << ") d=(" << r.d.x << "," << r.d.y << "," << r.d.z
                       << ") t " << sa.t << " vs " << sb.t);
        REQUIRE(sa.bsdf);
        REQUIRE(sb.bsdf);
        CHECK(sa.bsdf->id() == sb.bsdf->id());
        CHECK(std::abs(sa.t - sb.t) <= tol * std::max(scale, sb.t));
        CHECK(length(sa.p - sb.p) <= tol * 8.f * scale);
        CHECK(dot(sa.n, sb.n) > 1.f - tol);
        CHECK(dot(sa.shading.n, sb.shading.n) > 1.f - tol);
        CHECK(std::abs(dot(sa.shading.s, sa.shading.n)) < 1e-4f);
        CHECK(length(sa.uv - sb.uv) <= 10.f * tol);
        CHECK(length(sa.dpdu - sb.dpdu) <= 10.f * tol * std::max(scale, length(sb.dpdu)));
        CHECK(length(sa.wo + r.d) < 1e-5f);
    }
    CHECK(hits > 200);  // enough hits for the comparison to mean something
    CHECK(disagree <= int(rays.size()) / 200);
}

} // namespace

TEST_CASE("instancing: an identity instance hits exactly like its members", "[instancing]") {
    const std::string members = Members + SphereMember;
    for (const char* accel : Accelerators) {
        INFO("accelerator " << accel);
        auto inst = load(sceneXml(accel, group(members) + instance("")));
        auto flat = load(sceneXml(accel, members));
        REQUIRE(inst->shapes().size() == 1);
        REQUIRE(flat->shapes().size() == 3);
        compareHits(*inst, *flat, 1e-5f);
    }
}

TEST_CASE("instancing: a transformed instance hits where its transformed members are", "[instancing]") {
    // Meshes take any affine transform (non-uniform scale, shear-free rotation, translation)...
    const std::string affine = "<scale x=\"1.3\" y=\"0.7\" z=\"1.1\"/><rotate x=\"1\" y=\"2\" z=\"0.5\" angle=\"37\"/>"
                               "<translate x=\"0.3\" y=\"-0.2\" z=\"0.4\"/>";
    // ...a sphere only a similarity; a mirror is included (negative scale).
    const std::string similar = "<scale x=\"-1.2\" y=\"1.2\" z=\"1.2\"/><rotate y=\"1\" angle=\"-50\"/>"
                                "<translate x=\"-0.3\" z=\"0.5\"/>";
    for (const char* accel : Accelerators) {
        INFO("accelerator " << accel);
        auto inst = load(sceneXml(accel, group(Members) + instance(affine)));
        auto flat = load(sceneXml(accel, direct(Members, affine)));
        compareHits(*inst, *flat, 2e-4f);
        auto instS = load(sceneXml(accel, group(SphereMember) + instance(similar)));
        auto flatS = load(sceneXml(accel, direct(SphereMember, similar)));
        compareHits(*instS, *flatS, 2e-4f);
    }
}

TEST_CASE("instancing: tiny and huge instance scales", "[instancing]") {
    // The group-space ray has a tiny or huge direction; t must still carry over unchanged.
    for (float scale : {1e-3f, 1e3f}) {
        INFO("scale " << scale);
        std::string ops = fmt::format("<scale value=\"{}\"/><rotate z=\"1\" angle=\"20\"/>", scale);
        auto inst = load(sceneXml("embree", group(Members + SphereMember) + instance(ops)));
        auto flat = load(sceneXml("embree", direct(Members + SphereMember, ops)));
        compareHits(*inst, *flat, 2e-4f, scale);
    }
}

TEST_CASE("instancing: a shapegroup on its own is not part of the scene", "[instancing]") {
    auto scene = load(sceneXml("embree", group(Members + SphereMember)));
    CHECK(scene->shapes().empty());
    SurfaceInteraction si;
    for (const Ray& r : randomRays(200, 3)) CHECK_FALSE(scene->intersect(r, si));
}

TEST_CASE("instancing: many instances share one group's geometry", "[instancing]") {
    std::string body = group(Members);
    for (int i = 0; i < 1000; ++i)
        body += instance(fmt::format("<translate x=\"{}\" y=\"{}\"/>", 4 * (i % 40), 4 * (i / 40)));
    auto scene = load(sceneXml("embree", body));
    REQUIRE(scene->shapes().size() == 1000);
    // Rays straight down -z onto the cube of several instances: every hit reports the one
    // member shape object (one copy of its triangles), at its instance's place.
    const IShape* member = nullptr;
    for (int i : {0, 1, 41, 999}) {
        Point3f c(-1.f + 4.f * float(i % 40), 4.f * float(i / 40), 0.f);
        SurfaceInteraction si;
        REQUIRE(scene->intersect(Ray{c + Vector3f(0.f, 0.f, 5.f), Vector3f(0.f, 0.f, -1.f), Infinity}, si));
        CHECK(si.t == Approx(4.6f).epsilon(1e-5));
        CHECK(si.n.z == Approx(1.f));
        if (!member) member = si.shape;
        CHECK(si.shape == member);
    }
}

TEST_CASE("instancing: bad input fails with one line naming file:line", "[instancing]") {
    auto expect = [](const std::string& text, const std::string& marker, const std::string& needle) {
        std::string e = errorOf([&] { load(text); });
        INFO(e);
        CHECK(e.find('\n') == std::string::npos);
        CHECK(e.find(fmt::format("inline.xml:{}", lineOf(text, marker))) != std::string::npos);
        CHECK(e.find(needle) != std::string::npos);
    };
    const std::string g = group(Members);
    expect(sceneXml("embree", g + "<shape type=\"instance\">\n<ref id=\"nope\"/></shape>"), "<ref id=\"nope\"",
           "unknown id");
    expect(sceneXml("embree", "<shape type=\"sphere\" id=\"s\"/>\n<shape type=\"instance\">\n<ref id=\"s\"/></shape>"),
           "<ref id=\"s\"", "must be a shapegroup");
    expect(sceneXml("embree", g + "\n<shape type=\"instance\"/>"), "<shape type=\"instance\"", "shapegroup");
    expect(sceneXml("embree", "<shape type=\"shapegroup\" id=\"g\">\n<shape type=\"sphere\">"
                              "<emitter type=\"area\"/></shape></shape>"),
           "<shape type=\"sphere\"", "emitter");
    expect(sceneXml("embree", g + "<shape type=\"shapegroup\" id=\"h\">\n<ref id=\"g\"/></shape>"),
           "<ref id=\"g\"", "another shapegroup");
    // A projective matrix (the parser itself refuses singular ones).
    expect(sceneXml("embree", g + "<shape type=\"instance\"><ref id=\"g\"/>\n<transform name=\"to_world\">"
                                  "<matrix value=\"1 0 0 0 0 1 0 0 0 0 1 0 0 0.5 0 1\"/></transform></shape>"),
           "<transform name=\"to_world\"><matrix", "'to_world' must be a finite, invertible affine");
}

// End to end against Mitsuba 3 (scalar_spectral, 1024 spp; the command is in the scene
// file's header): tests/data/instancing/scene.xml places one group three times, one of
// them non-uniformly scaled. Means over the image and over each instance's third of the
// image agree within 2 % plus 4 standard errors of our 64-spp estimate (two-sided false
// alarm 6e-5 per region; the render is seeded, so the outcome is deterministic).
TEST_CASE("instancing: a small instanced scene agrees with Mitsuba 3", "[instancing][render]") {
    auto scene = loadSceneFile(EFFIGI_SOURCE_DIR "/tests/data/instancing/scene.xml");
    RenderControl control;
    control.progress = false;
    RenderStats stats = scene->renderer().render(*scene, control);
    CHECK(stats.rejectedSamples == 0);
    Image img = scene->camera().film().develop();
    auto ref = test::readExr(EFFIGI_SOURCE_DIR "/tests/data/instancing/mitsuba-reference.exr");
    REQUIRE(ref.spec.width == img.width);
    REQUIRE(ref.spec.height == img.height);
    auto grey = [](auto&& at, int x, int y) { return (at(x, y, 0) + at(x, y, 1) + at(x, y, 2)) / 3.0; };
    auto ours = [&](int x, int y, int c) { return double(img.at(x, y, c)); };
    auto theirs = [&](int x, int y, int c) { return double(ref.at(x, y, c)); };
    struct Region {
        const char* name;
        int x0, x1, y0, y1;
    };
    const int w = img.width, h = img.height;
    for (Region r : {Region{"image", 0, w, 0, h}, Region{"left instance", 0, w / 3, h / 4, 3 * h / 4},
                     Region{"middle instance", w / 3, 2 * w / 3, h / 4, 3 * h / 4},
                     Region{"right instance", 2 * w / 3, w, h / 4, 3 * h / 4}}) {
        double sum = 0, refSum = 0, diff2 = 0;
        int n = 0, nd = 0;
        for (int y = r.y0; y < r.y1; ++y)
            for (int x = r.x0; x < r.x1; ++x, ++n) {
                sum += grey(ours, x, y);
                refSum += grey(theirs, x, y);
                if (x + 1 < r.x1) {
                    double d = grey(ours, x, y) - grey(ours, x + 1, y);
                    diff2 += d * d;
                    ++nd;
                }
            }
        double mean = sum / n, refMean = refSum / n;
        // Pixel noise from neighbour differences, σ² ≈ ⟨(p(x) − p(x+1))²⟩ / 2: the box filter
        // keeps pixels independent, and the smooth image mostly cancels (what remains only
        // widens the error bar).
        double stderr_ = std::sqrt(diff2 / (2.0 * nd) / n);
        double rel = (mean - refMean) / refMean, tol = 0.02 + 4.0 * stderr_ / refMean;
        INFO(r.name << ": effigi " << mean << ", mitsuba " << refMean << ", relative " << rel << ", tolerance " << tol);
        CHECK(std::abs(rel) < tol);
        CHECK(tol < 0.08);  // sharp enough to catch a misplaced or missing instance
    }
}

TEST_CASE("instancing: instances nest (groups of instances of groups)", "[instancing]") {
    // A leaf group (a sphere of radius 0.5), a pair group of two leaf instances at x = ±1,
    // and the pair placed twice as large one unit up: spheres of radius 1 at (±2, 1, 0).
    const std::string body =
        "<shape type=\"shapegroup\" id=\"leaf\"><shape type=\"sphere\"><float name=\"radius\" value=\"0.5\"/>"
        "</shape></shape>"
        "<shape type=\"shapegroup\" id=\"pair\">"
        "<shape type=\"instance\"><ref id=\"leaf\"/><transform name=\"to_world\"><translate x=\"-1\"/></transform></shape>"
        "<shape type=\"instance\"><ref id=\"leaf\"/><transform name=\"to_world\"><translate x=\"1\"/></transform></shape>"
        "</shape>"
        "<shape type=\"instance\"><ref id=\"pair\"/><transform name=\"to_world\"><scale value=\"2\"/>"
        "<translate y=\"1\"/></transform></shape>";
    for (const char* accel : Accelerators) {
        INFO(accel);
        auto scene = load(sceneXml(accel, body));
        REQUIRE(scene->shapes().size() == 1);
        for (float x : {-2.f, 2.f}) {
            SurfaceInteraction si;
            REQUIRE(scene->intersect(Ray{Point3f(x, 1.3f, 5.f), Vector3f(0.f, 0.f, -1.f)}, si));
            const float z = std::sqrt(1.f - 0.09f);
            CHECK(si.t == Approx(5.f - z).epsilon(1e-5));
            CHECK(si.n.z == Approx(z).epsilon(1e-4));
            CHECK(si.n.y == Approx(0.3f).epsilon(1e-3));
            // The curvature through both placements: radius 0.5 scaled by 2.
            const Curvature c = curvature(si, localGeometry(si));
            CHECK(c.mean == Approx(1.f).epsilon(1e-3));
            CHECK(c.gaussian == Approx(1.f).epsilon(1e-3));
        }
        SurfaceInteraction miss;
        CHECK_FALSE(scene->intersect(Ray{Point3f(0.f, 1.f, 5.f), Vector3f(0.f, 0.f, -1.f)}, miss));
    }
}
