// The subdiv shape (OpenSubdiv): limit positions and normals of a cube cage against the
// Catmull–Clark limit masks in closed form, convergence with the level, creases (the
// creased side stays flat and keeps its normal), Loop on a tetrahedron against Loop's
// limit mask, PLY and OBJ cages with face-varying uvs, bad cages reported with file:line,
// and OpenSubdiv loaded only by a scene that uses subdiv.
#include "shape_helpers.hpp"
#include "skip.hpp"
#include "xml_helpers.hpp"

#include "effigi/render/scene.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

using namespace effigi;
using namespace effigi::test;

namespace {

const std::string Cube = "-1 -1 -1, 1 -1 -1, 1 1 -1, -1 1 -1, -1 -1 1, 1 -1 1, 1 1 1, -1 1 1";
const std::string CubeFaces = "0 3 2 1, 4 5 6 7, 0 1 5 4, 1 2 6 5, 2 3 7 6, 3 0 4 7";
const std::string Data = EFFIGI_SOURCE_DIR "/tests/data/shapes/";

bool haveSubdiv() { return Registry::instance().knows("shape", "subdiv"); }

Ref<IShape> subdiv(std::vector<std::pair<std::string, PropertyValue>> params) {
    Properties p("shape", "subdiv");
    for (auto& [k, v] : params) p.set(k, v);
    return makeShape("subdiv", p);
}

Ref<IShape> cube(int level, std::vector<std::pair<std::string, PropertyValue>> more = {}) {
    more.push_back({"positions", Cube});
    more.push_back({"faces", CubeFaces});
    more.push_back({"level", std::int64_t(level)});
    return subdiv(more);
}

/// The vertex whose direction from the origin is closest to dir.
std::size_t towards(const TriangleMesh& m, Vector3f dir) {
    std::size_t best = 0;
    for (std::size_t v = 1; v < m.vertexCount(); ++v)
        if (glm::dot(glm::normalize(m.positions[v]), glm::normalize(dir)) >
            glm::dot(glm::normalize(m.positions[best]), glm::normalize(dir)))
            best = v;
    return best;
}

bool osdMapped() {
    std::ifstream maps("/proc/self/maps");
    std::stringstream ss;
    ss << maps.rdbuf();
    return ss.str().find("libosdCPU") != std::string::npos;
}

std::string sceneError(const std::string& dir, const std::string& shape) {
    std::string text = "<scene version=\"3.0.0\">\n" + shape + "\n</scene>\n";
    return errorOf([&] { loadScene(*xml::parseString(text, dir + "/subdiv.xml")); });
}

} // namespace

// First in the file: run by hand, the later cases load OpenSubdiv into this process.
TEST_CASE("subdiv: OpenSubdiv is loaded only by a scene that uses subdiv", "[shapes][subdiv]") {
    if (!haveSubdiv()) return skipTest("shape/subdiv not built (no OpenSubdiv)");
    if (osdMapped()) return skipTest("OpenSubdiv already loaded by an earlier test case in this process");
    auto scene = loadSceneFile(EFFIGI_SOURCE_DIR "/scenes/cornell-box/scene.xml");
    CHECK_FALSE(osdMapped());
    cube(1);
    CHECK(osdMapped());
}

TEST_CASE("subdiv: a cube's limit points and normals match the Catmull-Clark limit masks", "[shapes][subdiv]") {
    if (!haveSubdiv()) return skipTest("shape/subdiv not built (no OpenSubdiv)");
    // Limit mask (n² v + 4 Σ edge neighbours + Σ diagonal neighbours) / (n (n + 5)):
    // a corner (n = 3) goes to (0.5, 0.5, 0.5); a face centre, regular after one step,
    // to z = (16 + 4·3 + 4·5/9) / 36 = 68/81.
    Ref<IShape> s = cube(3);
    const TriangleMesh& m = *s->mesh();
    std::size_t corner = towards(m, {1.f, 1.f, 1.f}), centre = towards(m, {0.f, 0.f, 1.f});
    CHECK(m.positions[corner].x == Approx(0.5f).margin(1e-6));
    CHECK(m.positions[corner].y == Approx(0.5f).margin(1e-6));
    CHECK(m.positions[corner].z == Approx(0.5f).margin(1e-6));
    CHECK(m.positions[centre].z == Approx(68.f / 81.f).margin(1e-6));
    CHECK(glm::length(m.positions[centre] - Point3f(0.f, 0.f, m.positions[centre].z)) < 1e-6f);
    // Limit normals by symmetry: along the diagonal, and +z at the face centre.
    CHECK(glm::dot(m.normals[corner], glm::normalize(Vector3f(1.f))) == Approx(1.f).margin(1e-5));
    CHECK(m.normals[centre].z == Approx(1.f).margin(1e-6));
    // Sphere-like: every limit point between the face centres' and the corners' radii.
    for (const Point3f& p : m.positions) {
        CHECK(glm::length(p) >= 68.f / 81.f - 1e-5f);
        CHECK(glm::length(p) <= std::sqrt(0.75f) + 1e-5f);
    }
    // Every vertex normal faces out and agrees with the triangles around it.
    for (std::size_t i = 0; i < m.triangleCount(); ++i) {
        Point3f p0, p1, p2;
        m.triangle(i, p0, p1, p2);
        Vector3f ng = glm::normalize(glm::cross(p1 - p0, p2 - p0));
        CHECK(glm::dot(ng, glm::normalize(p0 + p1 + p2)) > 0.9f);
        for (int k = 0; k < 3; ++k) CHECK(glm::dot(ng, m.normals[m.indices[3 * i + std::size_t(k)]]) > 0.95f);
    }
}

TEST_CASE("subdiv: the area converges with the level and the vertex count grows fourfold", "[shapes][subdiv]") {
    if (!haveSubdiv()) return skipTest("shape/subdiv not built (no OpenSubdiv)");
    std::vector<double> area;
    std::vector<std::size_t> verts;
    for (int level = 1; level <= 6; ++level) {
        Ref<IShape> s = cube(level);
        area.push_back(s->area());
        verts.push_back(s->mesh()->vertexCount());
        CHECK(s->mesh()->triangleCount() == 12u * (std::size_t(1) << (2 * level)));
    }
    // Inscribed in the limit surface: the area grows, by second-order steps (each about a
    // quarter of the one before), towards a value between the spheres of radius 68/81
    // and sqrt(3)/2.
    for (std::size_t l = 1; l < area.size(); ++l) {
        INFO("level " << l + 1 << ": " << area[l]);
        CHECK(area[l] > area[l - 1]);
        if (l >= 2) CHECK(area[l] - area[l - 1] < 0.35 * (area[l - 1] - area[l - 2]));
    }
    CHECK(area.back() > 4.0 * 3.14159265 * (68.0 / 81.0) * (68.0 / 81.0));
    CHECK(area.back() < 4.0 * 3.14159265 * 0.75);
    CHECK(verts.back() == 6u * 64u * 64u + 2u);  // a closed quad mesh: V = F + 2
}

TEST_CASE("subdiv: infinitely sharp creases keep the side flat and its normal", "[shapes][subdiv]") {
    if (!haveSubdiv()) return skipTest("shape/subdiv not built (no OpenSubdiv)");
    // The OBJ cage's four top edges are creased (t crease ... 10): the top loop becomes
    // the cubic B-spline of the square, the top face stays in the plane z = 1. The
    // B-spline midpoint of edge (4, 5): (P3 + 23 P4 + 23 P5 + P6) / 48 = (0, -11/12, 1).
    Ref<IShape> s = subdiv({{"filename", Data + "cube_creased.obj"}, {"level", std::int64_t(4)}});
    const TriangleMesh& m = *s->mesh();
    int onEdge = 0, flat = 0, side = 0;
    for (std::size_t v = 0; v < m.vertexCount(); ++v) {
        if (m.positions[v].z > 1.f - 1e-6f) CHECK(m.positions[v].z == Approx(1.f).margin(1e-6));
        if (glm::length(m.positions[v] - Point3f(0.f, -11.f / 12.f, 1.f)) > 1e-5f) continue;
        ++onEdge;  // split per side of the crease: the top keeps exactly +z
        if (glm::length(m.normals[v] - Normal3f(0.f, 0.f, 1.f)) < 1e-6f) ++flat;
        if (m.normals[v].z < 0.8f && m.normals[v].y < -0.5f) ++side;
    }
    CHECK(onEdge >= 2);
    CHECK(flat >= 1);
    CHECK(side >= 1);
    for (std::size_t v = 0; v < m.vertexCount(); ++v)
        if (m.positions[v].z == 1.f && std::abs(m.positions[v].x) < 0.5f && std::abs(m.positions[v].y) < 0.5f)
            CHECK(m.normals[v].z == Approx(1.f).margin(1e-6));
    // uvs are face-varying: every face keeps its own [0,1]² square.
    REQUIRE(m.uvs.size() == m.vertexCount());
    for (const Point2f& uv : m.uvs) {
        CHECK(uv.x >= -1e-6f);
        CHECK(uv.x <= 1.f + 1e-6f);
        CHECK(uv.y >= -1e-6f);
        CHECK(uv.y <= 1.f + 1e-6f);
    }
    // All twelve edges creased with the inline parameter: the limit surface is the cube.
    Ref<IShape> box = cube(3, {{"crease", std::string("0 1 10, 1 2 10, 2 3 10, 3 0 10, 4 5 10, 5 6 10, 6 7 10, 7 4 10, "
                                                      "0 4 10, 1 5 10, 2 6 10, 3 7 10")}});
    CHECK(box->area() == Approx(24.0).epsilon(1e-6));
    std::size_t centre = towards(*box->mesh(), {0.f, 0.f, 1.f});
    CHECK(box->mesh()->positions[centre].z == Approx(1.f).margin(1e-6));
    // A semi-sharp crease (sharpness 2) lies between the smooth and the sharp surface.
    double smooth = cube(4)->area(), semi = cube(4, {{"crease", std::string("4 5 2")}})->area();
    CHECK(semi > smooth);
}

TEST_CASE("subdiv: Loop on a tetrahedron matches Loop's limit mask", "[shapes][subdiv]") {
    if (!haveSubdiv()) return skipTest("shape/subdiv not built (no OpenSubdiv)");
    // Valence 3, β = 3/16: the limit of a vertex is (1 - nχ) v + χ Σ neighbours with
    // χ = 1 / (3 / (8 β) + n) = 1/5: (1,1,1) goes to 0.4 (1,1,1) - 0.2 (1,1,1).
    Ref<IShape> s = subdiv({{"filename", Data + "tetrahedron.ply"}, {"scheme", std::string("loop")}, {"level", std::int64_t(4)}});
    const TriangleMesh& m = *s->mesh();
    CHECK(m.triangleCount() == 4u * 256u);
    std::size_t v = towards(m, {1.f, 1.f, 1.f});
    CHECK(m.positions[v].x == Approx(0.2f).margin(1e-6));
    CHECK(m.positions[v].y == Approx(0.2f).margin(1e-6));
    CHECK(m.positions[v].z == Approx(0.2f).margin(1e-6));
    CHECK(glm::dot(m.normals[v], glm::normalize(Vector3f(1.f))) == Approx(1.f).margin(1e-5));
    for (std::size_t i = 0; i < m.vertexCount(); ++i) CHECK(glm::dot(m.normals[i], m.positions[i]) > 0.f);
    // The same cube from a PLY cage (quads rebuilt from the reader's fans) as inline.
    Ref<IShape> ply = subdiv({{"filename", Data + "cube_cage.ply"}, {"level", std::int64_t(2)}});
    CHECK(ply->mesh()->vertexCount() == cube(2)->mesh()->vertexCount());
    CHECK(ply->area() == Approx(cube(2)->area()).epsilon(1e-6));
}

TEST_CASE("subdiv: boundary interpolation keeps or rounds the corners of an open cage", "[shapes][subdiv]") {
    if (!haveSubdiv()) return skipTest("shape/subdiv not built (no OpenSubdiv)");
    // A 2×2 quad patch with a raised centre: boundary edges are B-spline curves of the
    // boundary vertices; edge_and_corner keeps the valence-2 corners in place.
    auto patch = [](const std::string& boundary) {
        return subdiv({{"positions", std::string("0 0 0, 1 0 0, 2 0 0, 0 1 0, 1 1 0.5, 2 1 0, 0 2 0, 1 2 0, 2 2 0")},
                       {"faces", std::string("0 1 4 3, 1 2 5 4, 3 4 7 6, 4 5 8 7")}, {"boundary", boundary}});
    };
    auto nearest = [](const TriangleMesh& m, Point3f q) {
        float d = 1e30f;
        for (const Point3f& p : m.positions) d = std::min(d, glm::length(p - q));
        return d;
    };
    Ref<IShape> kept = patch("edge_and_corner"), rounded = patch("edge_only");
    CHECK(nearest(*kept->mesh(), {0.f, 0.f, 0.f}) < 1e-6f);
    CHECK(nearest(*kept->mesh(), {2.f, 2.f, 0.f}) < 1e-6f);
    CHECK(nearest(*rounded->mesh(), {0.f, 0.f, 0.f}) > 0.1f);
    CHECK(kept->area() > rounded->area());
    // Boundary edges lie on the boundary line (the cage's boundary is straight and flat).
    for (const Point3f& p : kept->mesh()->positions)
        if (p.y == 0.f) CHECK(p.z == Approx(0.f).margin(1e-6));
}

TEST_CASE("subdiv: bad cages give one line naming file:line and the parameter", "[shapes][subdiv]") {
    if (!haveSubdiv()) return skipTest("shape/subdiv not built (no OpenSubdiv)");
    auto dir = std::filesystem::temp_directory_path() / ("effigi-subdiv-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    auto write = [&](const std::string& name, const std::string& text) { std::ofstream(dir / name) << text; };
    write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    write("nocrease.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\nt crease 2/1/0 0 3 10\n");
    write("quads.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 4 3\n");
    write("cage.stl", "solid\n");
    write("bad.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\nx\n");
    auto check = [&](const std::string& shape, std::vector<std::string> needles) {
        std::string msg = sceneError(dir.string(), shape);
        INFO(msg);
        CHECK(msg.find("subdiv.xml:2") != std::string::npos);
        for (const std::string& n : needles) CHECK(msg.find(n) != std::string::npos);
        CHECK(msg.find('\n') == std::string::npos);
    };
    check(R"(<shape type="subdiv"><string name="filename" value="missing.obj"/></shape>)", {"missing.obj"});
    check(R"(<shape type="subdiv"><string name="filename" value="range.obj"/></shape>)", {"range.obj", "face 1 uses vertex 8"});
    check(R"(<shape type="subdiv"><string name="filename" value="nocrease.obj"/></shape>)", {"nocrease.obj", "not an edge"});
    check(R"(<shape type="subdiv"><string name="filename" value="quads.obj"/><string name="scheme" value="loop"/></shape>)",
          {"scheme=loop needs a triangle cage"});
    check(R"(<shape type="subdiv"><string name="filename" value="cage.stl"/></shape>)", {"cage.stl", ".obj or .ply"});
    check(R"(<shape type="subdiv"><string name="filename" value="bad.ply"/></shape>)", {"bad.ply"});
    check(R"(<shape type="subdiv"><string name="positions" value="0 0 0, 1 0 0, 0 1 0"/><string name="faces" value="0 1 3"/></shape>)",
          {"'faces'", "face 1 uses vertex 3"});
    check(R"(<shape type="subdiv"><string name="positions" value="0 0 0, 1 0 0, 0 1 0"/></shape>)", {"positions and faces"});
    check(R"(<shape type="subdiv"><string name="positions" value="0 0 0, 1 0 0, 0 1 0"/>)"
          R"(<string name="faces" value="0 1 2"/><string name="crease" value="0 1"/></shape>)",
          {"'crease'", "3"});
    check(std::string(R"(<shape type="subdiv"><string name="positions" value=")") + Cube + R"("/><string name="faces" value=")" +
              CubeFaces + R"("/><integer name="level" value="10"/></shape>)",
          {"level 10", "triangles"});
    std::filesystem::remove_all(dir);
}
