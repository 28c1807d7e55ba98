// Shapes: the PLY reader, the OBJ loader, mesh shapes (rectangle, cube), analytic
// shapes (sphere, disk), and the sampling contracts every shape keeps (uniform area
// sampling with pdf 1/area; sampleDirection's pdf equal to pdfDirection; pdfDirection
// integrating to one over the directions that see the shape).
#include <catch2/catch.hpp>

#include "effigi/core/error.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/render/ply_reader.hpp"
#include "effigi/render/shape_base.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace effigi;
namespace fs = std::filesystem;

namespace {

// ---- helpers --------------------------------------------------------------------------

/// A per-process scratch directory, removed at exit.
fs::path tempDir() {
    struct Scratch {
        fs::path dir = fs::temp_directory_path() / fmt::format("effigi_test_shapes_{}", ::getpid());
        Scratch() { fs::create_directories(dir); }
        ~Scratch() {
            std::error_code ec;
            fs::remove_all(dir, ec);
        }
    };
    static Scratch scratch;
    return scratch.dir;
}

fs::path writeFile(const std::string& name, const std::string& bytes) {
    fs::path p = tempDir() / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
}

Ref<IShape> makeShape(const std::string& type, Properties props) {
    Ref<IShape> s = query<IShape>(Registry::instance().create("shape", type, props));
    REQUIRE(s);
    return s;
}
Ref<IShape> makeShape(const std::string& type) { return makeShape(type, Properties("shape", type)); }

/// Brute-force ray/triangle intersection (Möller & Trumbore 1997) in double, reporting
/// Embree-style barycentrics: p = (1-u-v) p0 + u p1 + v p2.
bool intersectMesh(const TriangleMesh& m, const Ray& r, Hit& hit) {
    bool found = false;
    double best = r.tMax;
    for (std::size_t i = 0; i < m.triangleCount(); ++i) {
        Vector3d p0(m.positions[m.indices[3 * i]]), p1(m.positions[m.indices[3 * i + 1]]),
            p2(m.positions[m.indices[3 * i + 2]]), o(r.o), d(r.d);
        Vector3d e1 = p1 - p0, e2 = p2 - p0, pv = glm::cross(d, e2);
        double det = glm::dot(e1, pv);
        if (std::abs(det) < 1e-300) continue;
        Vector3d tv = o - p0;
        double u = glm::dot(tv, pv) / det;
        if (u < 0.0 || u > 1.0) continue;
        Vector3d qv = glm::cross(tv, e1);
        double v = glm::dot(d, qv) / det;
        if (v < 0.0 || u + v > 1.0) continue;
        double t = glm::dot(e2, qv) / det;
        if (t > 1e-9 && t < best) {
            best = t;
            hit.t = float(t);
            hit.prim = std::uint32_t(i);
            hit.uv = Point2f(float(u), float(v));
            hit.shape = 0;
            found = true;
        }
    }
    return found;
}

/// Closest hit on one shape, whichever kind it is.
bool trace(const IShape& s, const Ray& r, Hit& hit) {
    if (s.mesh()) return intersectMesh(*s.mesh(), r, hit);
    float t;
    Point2f uv;
    if (!s.intersect(r, t, uv)) return false;
    hit.t = t;
    hit.uv = uv;
    hit.shape = 0;
    hit.prim = 0;
    return true;
}

/// Wilson–Hilferty approximation of the chi-square quantile with k degrees of freedom;
/// z is the standard normal quantile (3.090 for a significance level of 0.001).
double chi2Critical(int k, double z = 3.090) {
    double a = 2.0 / (9.0 * k);
    return k * std::pow(1.0 - a + z * std::sqrt(a), 3.0);
}

double chi2(const std::vector<double>& observed, const std::vector<double>& expected) {
    double c = 0.0;
    for (std::size_t i = 0; i < observed.size(); ++i) {
        double d = observed[i] - expected[i];
        c += d * d / expected[i];
    }
    return c;
}

/// 1-based line number of a byte offset.
int lineOf(const std::string& s, std::size_t at) { return 1 + int(std::count(s.begin(), s.begin() + long(at), '\n')); }

template <typename F> void requireThrowsNaming(F&& f, const std::string& needle) {
    try {
        f();
        FAIL("no effigi::Error thrown; expected one naming " << needle);
    } catch (const Error& e) {
        INFO("message: " << e.what());
        CHECK(std::string(e.what()).find(needle) != std::string::npos);
        CHECK(std::string(e.what()).find('\n') == std::string::npos);  // one line
    }
}

// ---- a small PLY writer, so one content can be written in all three formats ----------

struct PlyProp {
    std::string type, name;
    std::string countType;  // non-empty: a list property
};
struct PlyElem {
    std::string name;
    std::vector<PlyProp> props;
    std::vector<std::vector<std::vector<double>>> rows;  // row -> property -> values
};

void putBinary(std::string& out, const std::string& type, double v, bool bigEndian) {
    unsigned char b[8];
    std::size_t n = 0;
    auto store = [&](auto x) {
        n = sizeof(x);
        std::memcpy(b, &x, n);
    };
    if (type == "char") store(std::int8_t(v));
    else if (type == "uchar") store(std::uint8_t(v));
    else if (type == "short") store(std::int16_t(v));
    else if (type == "ushort") store(std::uint16_t(v));
    else if (type == "int") store(std::int32_t(v));
    else if (type == "uint") store(std::uint32_t(v));
    else if (type == "float") store(float(v));
    else if (type == "double") store(double(v));
    else FAIL("bad type in test " << type);
    if (bigEndian != (std::endian::native == std::endian::big))
        for (std::size_t i = 0; i < n / 2; ++i) std::swap(b[i], b[n - 1 - i]);
    out.append(reinterpret_cast<const char*>(b), n);
}

std::string writePly(const std::vector<PlyElem>& elems, const std::string& format) {
    std::string out = "ply\nformat " + format + " 1.0\ncomment written by test_shapes\n";
    for (const auto& e : elems) {
        out += fmt::format("element {} {}\n", e.name, e.rows.size());
        for (const auto& p : e.props)
            out += p.countType.empty() ? fmt::format("property {} {}\n", p.type, p.name)
                                       : fmt::format("property list {} {} {}\n", p.countType, p.type, p.name);
    }
    out += "end_header\n";
    bool ascii = format == "ascii", big = format == "binary_big_endian";
    for (const auto& e : elems)
        for (const auto& row : e.rows) {
            for (std::size_t k = 0; k < e.props.size(); ++k) {
                const auto& vals = row[k];
                if (!e.props[k].countType.empty()) {
                    if (ascii) out += fmt::format("{} ", vals.size());
                    else putBinary(out, e.props[k].countType, double(vals.size()), big);
                }
                for (double v : vals) {
                    if (ascii) out += fmt::format("{} ", v);
                    else putBinary(out, e.props[k].type, v, big);
                }
            }
            if (ascii) out += "\n";
        }
    return out;
}

/// Five vertices with normals, uvs and extra properties; a quad and a triangle with an
/// extra list and scalar; an extra element in between. Values are exact in float.
std::vector<PlyElem> sampleContent() {
    PlyElem v{"vertex",
              {{"float", "x", ""},
               {"float", "y", ""},
               {"double", "z", ""},
               {"uchar", "confidence", ""},
               {"float", "nx", ""},
               {"float", "ny", ""},
               {"float", "nz", ""},
               {"int", "junk", "uchar"},
               {"float", "u", ""},
               {"float", "v", ""}},
              {}};
    const double pos[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 1.25}};
    for (int i = 0; i < 5; ++i)
        v.rows.push_back({{pos[i][0]}, {pos[i][1]}, {pos[i][2]}, {double(200 + i)}, {0}, {0}, {1},
                          std::vector<double>(std::size_t(i), -7.0), {pos[i][0] * 0.5}, {pos[i][1] * 0.25}});
    PlyElem edge{"edge", {{"int", "vertex1", ""}, {"int", "vertex2", ""}}, {{{0}, {1}}, {{1}, {2}}}};
    PlyElem f{"face",
              {{"short", "flags", ""}, {"int", "vertex_indices", "uchar"}, {"float", "texcoord", "uchar"}},
              {{{3}, {0, 1, 2, 3}, {0.5, 0.25}}, {{-1}, {3, 2, 4}, {}}}};
    return {v, edge, f};
}

} // namespace

// ---- PLY ------------------------------------------------------------------------------

TEST_CASE("PLY: ascii, binary little and big endian give identical meshes", "[shapes][ply]") {
    auto content = sampleContent();
    TriangleMesh a = readPly(writeFile("same_ascii.ply", writePly(content, "ascii")));
    TriangleMesh le = readPly(writeFile("same_le.ply", writePly(content, "binary_little_endian")));
    TriangleMesh be = readPly(writeFile("same_be.ply", writePly(content, "binary_big_endian")));

    // The quad is fan-triangulated: (0 1 2) (0 2 3), then the triangle (3 2 4).
    const std::vector<std::uint32_t> indices{0, 1, 2, 0, 2, 3, 3, 2, 4};
    for (const TriangleMesh* m : {&a, &le, &be}) {
        CHECK(m->indices == indices);
        REQUIRE(m->positions.size() == 5);
        REQUIRE(m->normals.size() == 5);
        REQUIRE(m->uvs.size() == 5);
        CHECK(m->positions[4] == Point3f(0.5f, 0.5f, 1.25f));
        CHECK(m->normals[2] == Normal3f(0.f, 0.f, 1.f));
        CHECK(m->uvs[2] == Point2f(0.5f, 0.25f));
        CHECK(m->positions == a.positions);
        CHECK(m->normals == a.normals);
        CHECK(m->uvs == a.uvs);
    }
}

TEST_CASE("PLY: alternative names and types; faces may come first", "[shapes][ply]") {
    PlyElem f{"face", {{"uint", "vertex_index", "int"}}, {{{0, 1, 2}}}};
    PlyElem v{"vertex",
              {{"double", "x", ""}, {"double", "y", ""}, {"double", "z", ""}, {"float", "s", ""}, {"float", "t", ""}},
              {{{0}, {0}, {0}, {0}, {0}}, {{2}, {0}, {0}, {1}, {0}}, {{0}, {2}, {0}, {0}, {1}}}};
    for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
        TriangleMesh m = readPlyFromMemory(writePly({f, v}, format), "mem.ply");
        CHECK(m.indices == std::vector<std::uint32_t>{0, 1, 2});
        CHECK(m.normals.empty());
        REQUIRE(m.uvs.size() == 3);
        CHECK(m.uvs[1] == Point2f(1.f, 0.f));
        CHECK(m.positions[2] == Point3f(0.f, 2.f, 0.f));
    }
    // CRLF line ends in an ascii file.
    std::string crlf = "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\n"
                       "property float z\r\nelement face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
                       "0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n";
    CHECK(readPlyFromMemory(crlf, "crlf.ply").triangleCount() == 1);
}

TEST_CASE("PLY: malformed files throw errors naming the file (and line)", "[shapes][ply]") {
    const std::string good = writePly(sampleContent(), "ascii");
    const std::string goodBin = writePly(sampleContent(), "binary_little_endian");
    // needle ":N:" means "file:N:", anything else must appear besides the file name.
    auto check = [](const std::string& name, const std::string& bytes, const std::string& needle) {
        fs::path p = writeFile(name, bytes);
        INFO(name);
        if (needle.front() == ':') {
            requireThrowsNaming([&] { readPly(p); }, p.string() + needle);
        } else {
            requireThrowsNaming([&] { readPly(p); }, p.string());
            requireThrowsNaming([&] { readPly(p); }, needle);
        }
    };
    auto replace = [](std::string s, const std::string& from, const std::string& to) {
        auto at = s.find(from);
        REQUIRE(at != std::string::npos);
        return s.replace(at, from.size(), to);
    };
    SECTION("bad magic") { check("magic.ply", "plx\n" + good.substr(4), ":1:"); }
    SECTION("empty file") { check("empty.ply", "", ":1:"); }
    SECTION("no end_header") { check("noend.ply", "ply\nformat ascii 1.0\nelement vertex 0\n", ":"); }
    SECTION("unsupported format") {
        check("format.ply", replace(good, "format ascii", "format binary_middle_endian"), ":2:");
    }
    SECTION("unknown property type") {
        check("type.ply", replace(good, "property float y", "property flaot y"), ":6:");
    }
    SECTION("property before element") {
        check("order.ply", replace(good, "comment written by test_shapes", "property float w"), ":3:");
    }
    SECTION("bad element count") { check("count.ply", replace(good, "element vertex 5", "element vertex five"), ":4:"); }
    SECTION("missing x") { check("nox.ply", replace(good, "property float x\n", "property float w\n"), ":4:"); }
    SECTION("face without vertex_indices") {
        check("noidx.ply", replace(good, "vertex_indices", "vertex_ids"), ":");
    }
    SECTION("truncated binary") { check("trunc.ply", goodBin.substr(0, goodBin.size() - 3), "truncated"); }
    SECTION("truncated binary inside the vertices") {
        check("trunc2.ply", goodBin.substr(0, goodBin.find("end_header") + 40), "truncated");
    }
    SECTION("truncated ascii") { check("trunca.ply", good.substr(0, good.size() - 4), "truncated"); }
    SECTION("non-numeric ascii token, with its line") {
        auto at = good.find("end_header\n") + 11;
        std::string bad = good.substr(0, at) + "0 zero" + good.substr(good.find(' ', at + 2));
        check("nan.ply", bad, fmt::format(":{}:", lineOf(good, at)));
    }
    SECTION("index out of range (ascii)") {
        check("range.ply", replace(good, "3 2 4", "3 2 5"), fmt::format(":{}:", lineOf(good, good.find("3 2 4"))));
    }
    SECTION("negative index (binary)") {
        PlyElem v{"vertex", {{"float", "x", ""}, {"float", "y", ""}, {"float", "z", ""}}, {{{0}, {0}, {0}}}};
        PlyElem f{"face", {{"int", "vertex_indices", "uchar"}}, {{{0, 0, -1}}}};
        check("neg.ply", writePly({v, f}, "binary_big_endian"), "out of range");
    }
    SECTION("missing file") {
        fs::path p = tempDir() / "does_not_exist.ply";
        requireThrowsNaming([&] { readPly(p); }, p.string());
    }
}

TEST_CASE("ply shape: loads through the registry, applies to_world and face_normals", "[shapes][ply]") {
    fs::path p = writeFile("shape.ply", writePly(sampleContent(), "binary_little_endian"));
    Properties props("shape", "ply");
    props.set("filename", p.string());
    props.set("to_world", Transform::translate({0.f, 0.f, 10.f}));
    props.set("face_normals", true);
    Ref<IShape> s = makeShape("ply", props);
    REQUIRE(s->mesh());
    CHECK(s->mesh()->triangleCount() == 3);
    CHECK(s->mesh()->normals.empty());
    CHECK(s->bbox().min.z == Approx(10.f));
    CHECK(s->bbox().max.z == Approx(11.25f));

    // Errors from the component name the file too; a point cloud has no triangles.
    PlyElem v{"vertex", {{"float", "x", ""}, {"float", "y", ""}, {"float", "z", ""}}, {{{0}, {0}, {0}}}};
    fs::path cloud = writeFile("cloud.ply", writePly({v}, "ascii"));
    Properties cp("shape", "ply");
    cp.set("filename", cloud.string());
    requireThrowsNaming([&] { makeShape("ply", cp); }, cloud.string());
}

// ---- OBJ ------------------------------------------------------------------------------

TEST_CASE("obj shape: polygons, texture coordinates, normals", "[shapes][obj]") {
    fs::path p = writeFile("quad.obj", "# a quad and a triangle\nmtllib missing.mtl\n"
                                       "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n"
                                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
                                       "f 1/1/1 2/2/1 3/3/1 4/4/1\nf 4/4/1 3/3/1 5/1/1\n");
    Properties props("shape", "obj");
    props.set("filename", p.string());
    Ref<IShape> s = makeShape("obj", props);
    const TriangleMesh& m = *s->mesh();
    CHECK(m.triangleCount() == 3);
    CHECK(m.vertexCount() == 5);  // (v, vt, vn) triples are shared between faces
    REQUIRE(m.uvs.size() == 5);
    REQUIRE(m.normals.size() == 5);
    // flip_tex_coords defaults to true: vt (0 0) at vertex 1 becomes uv (0 1).
    CHECK(m.uvs[0] == Point2f(0.f, 1.f));
    CHECK(s->area() == Approx(1.f + 0.5f * std::sqrt(1.25f)).epsilon(1e-5));

    Properties noflip("shape", "obj");
    noflip.set("filename", p.string());
    noflip.set("flip_tex_coords", false);
    CHECK(makeShape("obj", noflip)->mesh()->uvs[0] == Point2f(0.f, 0.f));
}

TEST_CASE("obj shape: missing or garbled files throw errors naming the file", "[shapes][obj]") {
    auto check = [](const fs::path& p) {
        Properties props("shape", "obj");
        props.set("filename", p.string());
        INFO(p.string());
        requireThrowsNaming([&] { makeShape("obj", props); }, p.string());
    };
    check(tempDir() / "missing.obj");
    check(writeFile("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n"));         // index 0 / junk
    check(writeFile("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"));         // past the end
    check(writeFile("relative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -7\n"));   // before the start
    check(writeFile("nofaces.obj", "v 0 0 0\nv 1 0 0\n"));
    check(writeFile("binary.obj", std::string("\x7f" "ELF\x02\x01\x01\0\0\0garbage\xff\xfe", 20)));
}

// ---- rectangle and cube ---------------------------------------------------------------

TEST_CASE("rectangle: geometry, winding, transforms, flip_normals", "[shapes]") {
    Ref<IShape> r = makeShape("rectangle");
    const TriangleMesh& m = *r->mesh();
    CHECK(r->area() == Approx(4.f));
    CHECK(m.triangleCount() == 2);
    for (std::size_t i = 0; i < 2; ++i) {
        Point3f p0, p1, p2;
        m.triangle(i, p0, p1, p2);
        CHECK(normalize(cross(p1 - p0, p2 - p0)).z == Approx(1.f));
    }
    for (std::size_t v = 0; v < 4; ++v)
        CHECK(m.uvs[v] == Point2f((m.positions[v].x + 1.f) / 2.f, (m.positions[v].y + 1.f) / 2.f));

    // Hit reconstruction from barycentrics: point, normals, uv, frame along dp/du.
    Ray ray{{0.5f, -0.25f, 3.f}, {0.f, 0.f, -2.f}};
    Hit hit;
    REQUIRE(intersectMesh(m, ray, hit));
    SurfaceInteraction si = r->interaction(ray, hit);
    CHECK(si.p.x == Approx(0.5f));
    CHECK(si.p.y == Approx(-0.25f));
    CHECK(si.p.z == Approx(0.f).margin(1e-6));
    CHECK(si.t == Approx(1.5f));
    CHECK(si.n == Normal3f(0.f, 0.f, 1.f));
    CHECK(si.uv.x == Approx(0.75f));
    CHECK(si.uv.y == Approx(0.375f));
    CHECK(si.wo.z == Approx(1.f));
    CHECK(si.shading.s.x == Approx(1.f));
    CHECK(si.shading.n.z == Approx(1.f));
    CHECK(si.shape == r.get());
    CHECK(si.bsdf != nullptr);
    CHECK(si.emitter == nullptr);

    SECTION("scaled: area") {
        Properties p("shape", "rectangle");
        p.set("to_world", Transform::scale({2.f, 3.f, 1.f}));
        CHECK(makeShape("rectangle", p)->area() == Approx(24.f));
    }
    SECTION("rotated: normals follow") {
        Properties p("shape", "rectangle");
        p.set("to_world", Transform::translate({1.f, 2.f, 3.f}) * Transform::rotate({1.f, 0.f, 0.f}, 90.f));
        Ref<IShape> s = makeShape("rectangle", p);
        // +z rotated by +90° about x is −y.
        for (const Normal3f& n : s->mesh()->normals) {
            CHECK(n.y == Approx(-1.f));
            CHECK(n.z == Approx(0.f).margin(1e-6));
        }
        Ray down{{1.2f, 5.f, 3.1f}, {0.f, -1.f, 0.f}};
        Hit h;
        REQUIRE(intersectMesh(*s->mesh(), down, h));
        SurfaceInteraction rs = s->interaction(down, h);
        CHECK(rs.n.y == Approx(-1.f));
        CHECK(rs.p.y == Approx(2.f));
        CHECK(rs.t == Approx(3.f));
        CHECK(s->samplePosition({0.3f, 0.6f}).n.y == Approx(-1.f));
    }
    SECTION("flat scale still has normals") {
        Properties p("shape", "rectangle");
        p.set("to_world", Transform::scale({2.f, 2.f, 0.f}));
        Ref<IShape> s = makeShape("rectangle", p);
        CHECK(s->mesh()->normals[0] == Normal3f(0.f, 0.f, 1.f));
        CHECK(s->area() == Approx(16.f));
    }
    SECTION("flip_normals") {
        Properties p("shape", "rectangle");
        p.set("flip_normals", true);
        Ref<IShape> s = makeShape("rectangle", p);
        Hit h;
        REQUIRE(intersectMesh(*s->mesh(), ray, h));
        SurfaceInteraction fs = s->interaction(ray, h);
        CHECK(fs.n.z == Approx(-1.f));
        CHECK(fs.shading.n.z == Approx(-1.f));
        CHECK(fs.uv.x == Approx(0.75f));  // the parametrisation is unchanged
        CHECK(fs.uv.y == Approx(0.375f));
        CHECK(s->samplePosition({0.5f, 0.5f}).n.z == Approx(-1.f));
    }
}

TEST_CASE("cube: 24 vertices, outward winding and normals, face_normals", "[shapes]") {
    Ref<IShape> c = makeShape("cube");
    const TriangleMesh& m = *c->mesh();
    CHECK(m.vertexCount() == 24);
    CHECK(m.triangleCount() == 12);
    CHECK(c->area() == Approx(24.f));
    for (std::size_t i = 0; i < 12; ++i) {
        Point3f p0, p1, p2;
        m.triangle(i, p0, p1, p2);
        Vector3f n = normalize(cross(p1 - p0, p2 - p0));
        Point3f centroid = (p0 + p1 + p2) / 3.f;
        CHECK(maxAbsComponent(n) == Approx(1.f));
        CHECK(dot(n, centroid) > 0.5f);  // outward
        for (int k = 0; k < 3; ++k) CHECK(dot(m.normals[m.indices[3 * i + k]], n) == Approx(1.f));
    }
    Properties p("shape", "cube");
    p.set("face_normals", true);
    p.set("to_world", Transform::scale({1.f, 2.f, 3.f}));
    Ref<IShape> fc = makeShape("cube", p);
    CHECK(fc->mesh()->normals.empty());
    CHECK(fc->area() == Approx(8.f * (2.f + 6.f + 3.f)));
}

TEST_CASE("mesh validation: errors name the source", "[shapes]") {
    TriangleMesh m;
    m.positions = {{0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}};
    m.indices = {0, 1, 3};
    requireThrowsNaming([&] { m.validate("bad.mesh"); }, "bad.mesh");
    m.indices = {0, 1, 2};
    m.positions[1].x = std::numeric_limits<float>::quiet_NaN();
    requireThrowsNaming([&] { m.validate("nan.mesh"); }, "nan.mesh");
    m.positions[1].x = 1.f;
    m.uvs.resize(2);
    requireThrowsNaming([&] { m.validate("uv.mesh"); }, "uv.mesh");
}

// ---- sphere and disk ------------------------------------------------------------------

TEST_CASE("sphere: intersection against analytic answers", "[shapes][sphere]") {
    for (float radius : {1e-4f, 1.f, 1e4f}) {
        INFO("radius " << radius);
        Properties p("shape", "sphere");
        p.set("radius", double(radius));
        p.set("center", PointValue{{0.f, 0.f, 0.f}});
        Ref<IShape> s = makeShape("sphere", p);
        CHECK(s->area() == Approx(4.f * Pi * radius * radius));
        float t;
        Point2f uv;
        const float R = radius;

        // From outside, head on; unnormalised direction halves t.
        REQUIRE(s->intersect(Ray{{0.f, 0.f, -5.f * R}, {0.f, 0.f, 1.f}}, t, uv));
        CHECK(t == Approx(4.f * R).epsilon(1e-6));
        REQUIRE(s->intersect(Ray{{0.f, 0.f, -5.f * R}, {0.f, 0.f, 2.f}}, t, uv));
        CHECK(t == Approx(2.f * R).epsilon(1e-6));
        // Off-axis: t = 5R − sqrt(R² − x0²).
        REQUIRE(s->intersect(Ray{{0.6f * R, 0.f, -5.f * R}, {0.f, 0.f, 1.f}}, t, uv));
        CHECK(t == Approx(4.2f * R).epsilon(1e-6));
        // From inside: the far side.
        REQUIRE(s->intersect(Ray{{0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}}, t, uv));
        CHECK(t == Approx(R).epsilon(1e-6));
        REQUIRE(s->intersect(Ray{{0.f, 0.5f * R, 0.f}, {0.f, 1.f, 0.f}}, t, uv));
        CHECK(t == Approx(0.5f * R).epsilon(1e-6));
        // Misses: pointing away, beyond tMax, passing by.
        CHECK_FALSE(s->intersect(Ray{{0.f, 0.f, -5.f * R}, {0.f, 0.f, -1.f}}, t, uv));
        CHECK_FALSE(s->intersect(Ray{{0.f, 0.f, -5.f * R}, {0.f, 0.f, 1.f}, 3.9f * R}, t, uv));
        CHECK_FALSE(s->intersect(Ray{{1.001f * R, 0.f, -5.f * R}, {0.f, 0.f, 1.f}}, t, uv));
        // Grazing: just inside the silhouette hits near the tangent point, just outside misses.
        REQUIRE(s->intersect(Ray{{0.9999f * R, 0.f, -5.f * R}, {0.f, 0.f, 1.f}}, t, uv));
        CHECK(t == Approx(5.f * R).epsilon(0.02));
        // Tangent exactly: if reported, the hit is the tangent point.
        if (s->intersect(Ray{{R, 0.f, -5.f * R}, {0.f, 0.f, 1.f}}, t, uv)) CHECK(t == Approx(5.f * R).epsilon(1e-3));

        // Interaction: on the surface, outward normal, uv in range.
        Ray ray{{0.3f * R, -0.2f * R, -5.f * R}, {0.f, 0.f, 1.f}};
        REQUIRE(s->intersect(ray, t, uv));
        SurfaceInteraction si = s->interaction(ray, Hit{t, 0, 0, uv});
        CHECK(length(si.p) == Approx(R).epsilon(1e-6));
        CHECK(dot(si.n, si.p / R) == Approx(1.f));
        CHECK(si.uv.x >= 0.f);
        CHECK(si.uv.x < 1.f);
        CHECK(si.uv.y == Approx(safeAcos(si.p.z / R) * InvPi).epsilon(1e-4));
        CHECK(dot(si.shading.s, si.shading.n) == Approx(0.f).margin(1e-5));
        CHECK(length(cross(si.shading.s, Vector3f(-si.p.y, si.p.x, 0.f))) == Approx(0.f).margin(1e-3 * R));
    }
}

TEST_CASE("sphere: center, to_world, flip_normals, errors", "[shapes][sphere]") {
    Properties p("shape", "sphere");
    p.set("center", PointValue{{1.f, 0.f, 0.f}});
    p.set("radius", 0.5);
    p.set("to_world", Transform::translate({0.f, 2.f, 0.f}) * Transform::scale(Vector3f(3.f)));
    p.set("flip_normals", true);
    Ref<IShape> s = makeShape("sphere", p);
    // Center (3, 2, 0), radius 1.5.
    CHECK(s->bbox().min.x == Approx(1.5f));
    CHECK(s->bbox().max.y == Approx(3.5f));
    CHECK(s->area() == Approx(4.f * Pi * 2.25f));
    float t;
    Point2f uv;
    Ray ray{{3.f, 2.f, -10.f}, {0.f, 0.f, 1.f}};
    REQUIRE(s->intersect(ray, t, uv));
    CHECK(t == Approx(8.5f));
    SurfaceInteraction si = s->interaction(ray, Hit{t, 0, 0, uv});
    CHECK(si.n.z == Approx(1.f));  // flipped: inward at the bottom of the sphere
    CHECK(si.shading.n.z == Approx(1.f));

    Properties bad("shape", "sphere");
    bad.set("to_world", Transform::scale({1.f, 2.f, 1.f}));
    requireThrowsNaming([&] { makeShape("sphere", bad); }, "to_world");
    Properties zero("shape", "sphere");
    zero.set("radius", 0.0);
    requireThrowsNaming([&] { makeShape("sphere", zero); }, "radius");
}

TEST_CASE("disk: intersection against analytic answers", "[shapes][disk]") {
    for (float scale : {1e-4f, 1.f, 1e4f}) {
        INFO("scale " << scale);
        Properties p("shape", "disk");
        p.set("to_world", Transform::translate({0.f, 0.f, scale}) * Transform::scale(Vector3f(scale)));
        Ref<IShape> d = makeShape("disk", p);
        const float S = scale;
        CHECK(d->area() == Approx(Pi * S * S));
        float t;
        Point2f uv;
        // From above and from below (both sides are hit).
        REQUIRE(d->intersect(Ray{{0.5f * S, 0.f, 3.f * S}, {0.f, 0.f, -1.f}}, t, uv));
        CHECK(t == Approx(2.f * S).epsilon(1e-6));
        CHECK(uv.x == Approx(0.5f));
        REQUIRE(d->intersect(Ray{{0.f, -0.5f * S, -S}, {0.f, 0.f, 1.f}}, t, uv));
        CHECK(t == Approx(2.f * S).epsilon(1e-6));
        CHECK(uv.y == Approx(0.75f));
        // Outside the radius, parallel, pointing away, beyond tMax.
        CHECK_FALSE(d->intersect(Ray{{0.8f * S, 0.8f * S, 3.f * S}, {0.f, 0.f, -1.f}}, t, uv));
        CHECK_FALSE(d->intersect(Ray{{-3.f * S, 0.f, S}, {1.f, 0.f, 0.f}}, t, uv));
        CHECK_FALSE(d->intersect(Ray{{0.f, 0.f, 3.f * S}, {0.f, 0.f, 1.f}}, t, uv));
        CHECK_FALSE(d->intersect(Ray{{0.f, 0.f, 3.f * S}, {0.f, 0.f, -1.f}, 1.9f * S}, t, uv));
        // Oblique.
        Ray ob{{-S, 0.f, 2.f * S}, {1.f, 0.f, -1.f}};
        REQUIRE(d->intersect(ob, t, uv));
        CHECK(t == Approx(S).epsilon(1e-6));
        SurfaceInteraction si = d->interaction(ob, Hit{t, 0, 0, uv});
        CHECK(si.p.z == Approx(S).epsilon(1e-6));
        CHECK(si.p.x == Approx(0.f).margin(1e-6 * S));
        CHECK(si.n.z == Approx(1.f));
        CHECK(si.wo.x == Approx(-std::sqrt(0.5f)));
    }
    Properties e("shape", "disk");
    e.set("to_world", Transform::rotate({0.f, 1.f, 0.f}, 90.f) * Transform::scale({2.f, 0.5f, 1.f}));
    e.set("flip_normals", true);
    Ref<IShape> ellipse = makeShape("disk", e);
    CHECK(ellipse->area() == Approx(Pi));
    CHECK(ellipse->samplePosition({0.2f, 0.7f}).n.x == Approx(-1.f));  // +z -> +x, flipped
    CHECK(ellipse->bbox().max.z == Approx(2.f));
    CHECK(ellipse->bbox().max.y == Approx(0.5f));
}

// ---- sampling contracts -----------------------------------------------------------------

TEST_CASE("samplePosition is uniform by area with pdf 1/area", "[shapes][sampling]") {
    // Chi-square tests at significance level 0.001 on equal-expectation cells.
    PCG32 rng(7, 11);
    const int N = 96000;

    SECTION("scaled cube (faces of different areas)") {
        Properties p("shape", "cube");
        p.set("to_world", Transform::scale({1.f, 2.f, 3.f}));
        Ref<IShape> c = makeShape("cube", p);
        const Vector3f ext(1.f, 2.f, 3.f);
        // 6 faces x 4 x 4 cells, expected count ∝ cell area.
        std::vector<double> obs(96, 0.0), exp(96, 0.0);
        for (int axis = 0; axis < 3; ++axis) {
            float faceArea = 4.f * ext[(axis + 1) % 3] * ext[(axis + 2) % 3];
            for (int side = 0; side < 2; ++side)
                for (int k = 0; k < 16; ++k) exp[std::size_t((axis * 2 + side) * 16 + k)] = N * faceArea / 16.f / c->area();
        }
        for (int i = 0; i < N; ++i) {
            PositionSample ps = c->samplePosition({rng.nextFloat(), rng.nextFloat()});
            REQUIRE(ps.pdf == Approx(1.f / c->area()));
            Vector3f q = ps.p / ext;  // back to [-1,1]³
            int axis = std::abs(ps.n.x) > 0.5f ? 0 : std::abs(ps.n.y) > 0.5f ? 1 : 2;
            REQUIRE(q[axis] * ps.n[axis] == Approx(1.f));
            int side = ps.n[axis] > 0.f;
            auto cell = [](float x) { return std::clamp(int((x + 1.f) * 2.f), 0, 3); };
            int a = cell(q[(axis + 1) % 3]), b = cell(q[(axis + 2) % 3]);
            obs[std::size_t((axis * 2 + side) * 16 + a * 4 + b)] += 1.0;
        }
        CHECK(chi2(obs, exp) < chi2Critical(95));
    }
    SECTION("sphere and disk") {
        for (const char* type : {"sphere", "disk"}) {
            INFO(type);
            Ref<IShape> s = makeShape(type);
            // Equal-area cells: (z, φ) on the sphere (Archimedes), (r², φ) on the disk.
            std::vector<double> obs(64, 0.0), exp(64, N / 64.0);
            for (int i = 0; i < N; ++i) {
                PositionSample ps = s->samplePosition({rng.nextFloat(), rng.nextFloat()});
                REQUIRE(ps.pdf == Approx(1.f / s->area()));
                float a = std::string(type) == "sphere" ? (ps.p.z + 1.f) / 2.f : dot(ps.p, ps.p);
                float phi = std::atan2(ps.p.y, ps.p.x) * Inv2Pi + 0.5f;
                obs[std::size_t(std::clamp(int(a * 8.f), 0, 7) * 8 + std::clamp(int(phi * 8.f), 0, 7))] += 1.0;
            }
            CHECK(chi2(obs, exp) < chi2Critical(63));
        }
    }
}

namespace {

/// sampleDirection's pdf must equal pdfDirection at the point found by tracing the
/// sampled direction (so MIS weights computed either way agree).
void checkDirectionPdfs(const IShape& s, const Point3f& ref, bool expectFirstHit, int minChecked = 1500) {
    PCG32 rng(3, 5);
    int checked = 0;
    for (int i = 0; i < 2000; ++i) {
        DirectionSample ds = s.sampleDirection(ref, {rng.nextFloat(), rng.nextFloat()});
        if (!(ds.pdf > 0.f)) continue;
        CHECK(length(ds.wi) == Approx(1.f));
        CHECK(length(ds.p - ref) == Approx(ds.dist).epsilon(1e-4));
        Ray ray{ref, ds.wi};
        Hit hit;
        if (!trace(s, ray, hit)) continue;  // grazing directions may round past the edge
        if (expectFirstHit) CHECK(hit.t == Approx(ds.dist).epsilon(1e-3));
        if (std::abs(hit.t - ds.dist) > 1e-3f * ds.dist) continue;
        SurfaceInteraction si = s.interaction(ray, hit);
        // On an edge of the cube the trace may report the neighbouring face.
        if (dot(si.n, ds.n) < 0.99f) continue;
        INFO(s.typeName() << " p " << ds.p.x << " " << ds.p.y << " " << ds.p.z);
        CHECK(s.pdfDirection(ref, si) == Approx(ds.pdf).epsilon(2e-3));
        ++checked;
    }
    CHECK(checked > minChecked);
}

/// Monte Carlo estimate of ∫ pdfDirection dω over the directions from ref that hit s:
/// uniform directions, 4π·pdf where they hit. Must be `expected` within 4 standard errors
/// (two-sided significance about 6e-5), seeded. That is 1 when every sampled point is
/// visible from ref; for area sampling of a shape that hides part of itself, the
/// visible fraction of its area.
void checkPdfIntegral(const IShape& s, const Point3f& ref, double expected = 1.0) {
    PCG32 rng(17, 19);
    const int N = 200000;
    double sum = 0.0, sum2 = 0.0;
    for (int i = 0; i < N; ++i) {
        Vector3f d = warp::squareToUniformSphere({rng.nextFloat(), rng.nextFloat()});
        Ray ray{ref, d};
        Hit hit;
        double x = 0.0;
        if (trace(s, ray, hit)) x = 4.0 * double(Pi) * double(s.pdfDirection(ref, s.interaction(ray, hit)));
        sum += x;
        sum2 += x * x;
    }
    double mean = sum / N, var = (sum2 / N - mean * mean) / (N - 1);
    INFO("integral " << mean << " ± " << std::sqrt(var));
    CHECK(std::abs(mean - expected) < 4.0 * std::sqrt(var));
    CHECK(std::sqrt(var) < 0.05);  // the test has power
}

} // namespace

TEST_CASE("sampleDirection pdf equals pdfDirection", "[shapes][sampling]") {
    Properties rp("shape", "rectangle");
    rp.set("to_world", Transform::rotate({0.70710678f, 0.70710678f, 0.f}, 30.f) * Transform::scale({1.f, 0.5f, 1.f}));
    checkDirectionPdfs(*makeShape("rectangle", rp), {0.4f, -0.7f, 1.3f}, true);
    // From here only the +z face of the cube is visible: 1/6 of the samples are first hits.
    checkDirectionPdfs(*makeShape("cube"), {0.4f, -0.7f, 3.f}, false, 250);
    checkDirectionPdfs(*makeShape("disk"), {0.4f, -0.7f, -0.5f}, true);

    Properties sp("shape", "sphere");
    sp.set("center", PointValue{{0.f, 0.f, 1.f}});
    sp.set("radius", 0.5);
    Ref<IShape> sphere = makeShape("sphere", sp);
    checkDirectionPdfs(*sphere, {0.3f, 0.2f, -3.f}, true);   // outside: cone sampling
    checkDirectionPdfs(*sphere, {0.1f, 0.f, 0.8f}, true);     // inside: area sampling

    // Cone sampling is uniform in the cone: (1 − cos θ)/(1 − cos θmax) and φ uniform
    // (chi-square at significance level 0.001 on 10 x 10 cells).
    Point3f ref(0.3f, 0.2f, -3.f);
    Vector3f axis = normalize(Point3f(0.f, 0.f, 1.f) - ref);
    float d = length(Point3f(0.f, 0.f, 1.f) - ref);
    float cosMax = std::sqrt(1.f - 0.25f / (d * d));
    Vector3f s, t;
    coordinateSystem(axis, s, t);
    PCG32 rng(23, 29);
    const int N = 50000;
    std::vector<double> obs(100, 0.0), exp(100, N / 100.0);
    for (int i = 0; i < N; ++i) {
        DirectionSample ds = sphere->sampleDirection(ref, {rng.nextFloat(), rng.nextFloat()});
        REQUIRE(ds.pdf == Approx(1.f / (2.f * Pi * (1.f - cosMax))).epsilon(1e-3));
        double c = (1.0 - double(dot(ds.wi, axis))) / (1.0 - double(cosMax));
        double phi = std::atan2(dot(ds.wi, t), dot(ds.wi, s)) * Inv2Pi + 0.5;
        obs[std::size_t(std::clamp(int(c * 10), 0, 9) * 10 + std::clamp(int(phi * 10), 0, 9))] += 1.0;
    }
    CHECK(chi2(obs, exp) < chi2Critical(99));
}

TEST_CASE("pdfDirection integrates to one over the shape's directions", "[shapes][sampling]") {
    checkPdfIntegral(*makeShape("rectangle"), {0.3f, -0.2f, 1.5f});
    checkPdfIntegral(*makeShape("disk"), {0.5f, 0.5f, -0.7f});
    checkPdfIntegral(*makeShape("cube"), {2.f, 1.5f, 3.f}, 0.5);  // the +x, +y, +z faces are visible
    Properties sp("shape", "sphere");
    sp.set("center", PointValue{{0.f, 0.f, 1.f}});
    Ref<IShape> sphere = makeShape("sphere", sp);
    checkPdfIntegral(*sphere, {0.5f, 0.5f, -2.f});  // outside: cone sampling
    checkPdfIntegral(*sphere, {0.2f, 0.f, 1.3f});   // inside: area sampling
}

TEST_CASE("shapes carry their nested emitter; attach errors point at the scene", "[shapes]") {
    Properties ep("emitter", "area");
    Ref<IComponent> area = Registry::instance().create("emitter", "area", ep);
    Properties p("shape", "sphere");
    p.set("emitter", ComponentValue{"emitter", area});
    Ref<IShape> s = makeShape("sphere", p);
    REQUIRE(s->emitter() != nullptr);
    CHECK(s->emitter() == query<IEmitter>(area).get());
    Ray ray{{0.f, 0.f, -3.f}, {0.f, 0.f, 1.f}};
    Hit hit;
    REQUIRE(trace(*s, ray, hit));
    CHECK(s->interaction(ray, hit).emitter == s->emitter());

    // A point light cannot be nested in a shape: the error names where it was written.
    Properties pp("emitter", "point");
    Ref<IComponent> point = Registry::instance().create("emitter", "point", pp);
    Properties q("shape", "rectangle");
    q.set("emitter", ComponentValue{"emitter", point}, SourceLocation{"scene.xml", 12});
    requireThrowsNaming([&] { makeShape("rectangle", q); }, "scene.xml:12");
}

TEST_CASE("analytic shapes: rays leaving the surface do not hit it again", "[shapes][sphere][disk]") {
    PCG32 rng(31, 37);
    for (float scale : {1e-4f, 1.f, 1e4f}) {
        INFO("scale " << scale);
        Properties sp("shape", "sphere");
        sp.set("radius", double(scale));
        sp.set("center", PointValue{{0.3f * scale, -0.2f * scale, 0.1f * scale}});
        Properties dp("shape", "disk");
        dp.set("to_world", Transform::translate(Vector3f(0.5f * scale)) * Transform::scale(Vector3f(scale)));
        for (bool isSphere : {true, false}) {
            Ref<IShape> s = isSphere ? makeShape("sphere", sp) : makeShape("disk", dp);
            int selfHits = 0, wrongFar = 0;
            std::string detail;
            for (int i = 0; i < 2000; ++i) {
                PositionSample ps = s->samplePosition({rng.nextFloat(), rng.nextFloat()});
                Vector3f d = warp::squareToUniformSphere({rng.nextFloat(), rng.nextFloat()});
                SurfaceInteraction si;
                si.p = ps.p;
                si.n = ps.n;
                Ray ray = si.spawnRay(d);
                float t;
                Point2f uv;
                bool hit = s->intersect(ray, t, uv);
                if (dot(d, ps.n) > 0.f || !isSphere) {
                    // Outward from a convex surface (or off a plane): nothing to hit.
                    selfHits += hit;
                } else {
                    // Inward through a sphere: the far side, from the (offset) ray origin.
                    Vector3d oc = Vector3d(ray.o) - Vector3d(0.3, -0.2, 0.1) * double(scale), dd(d);
                    double b = glm::dot(oc, dd), c = glm::dot(oc, oc) - double(scale) * double(scale);
                    double far = -b + std::sqrt(std::max(0.0, b * b - c));
                    if (!hit || std::abs(double(t) - far) > 1e-5 * double(scale)) {
                        ++wrongFar;
                        detail += fmt::format(" [hit {} t {} expected {}]", hit, t, far);
                    }
                }
            }
            INFO(detail);
            CHECK(selfHits == 0);
            CHECK(wrongFar == 0);
        }
    }
}
