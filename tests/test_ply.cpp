// Mesh file readers: the PLY reader (ascii and both binary byte orders, alternative
// property names, one test per class of malformed file) and the ply and obj shapes.
#include "shape_helpers.hpp"
#include "temp_files.hpp"

#include "effigi/render/ply_reader.hpp"

#include <algorithm>
#include <bit>
#include <cstring>
#include <filesystem>

using namespace effigi;
using namespace effigi::test;
namespace fs = std::filesystem;

namespace {

/// Removed at exit with everything the tests wrote into it.
const ScratchDir scratch("ply");

/// 1-based line number of a byte offset.
int lineOf(const std::string& s, std::size_t at) { return 1 + int(std::count(s.begin(), s.begin() + long(at), '\n')); }

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
    TriangleMesh a = readPly(scratch.write("same_ascii.ply", writePly(content, "ascii")));
    TriangleMesh le = readPly(scratch.write("same_le.ply", writePly(content, "binary_little_endian")));
    TriangleMesh be = readPly(scratch.write("same_be.ply", writePly(content, "binary_big_endian")));

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

TEST_CASE("PLY: alternative names and types, faces may come first", "[shapes][ply]") {
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
        fs::path p = scratch.write(name, bytes);
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
        fs::path p = scratch.dir() / "does_not_exist.ply";
        requireThrowsNaming([&] { readPly(p); }, p.string());
    }
}

TEST_CASE("ply shape: loads through the registry, applies to_world and face_normals", "[shapes][ply]") {
    fs::path p = scratch.write("shape.ply", writePly(sampleContent(), "binary_little_endian"));
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
    fs::path cloud = scratch.write("cloud.ply", writePly({v}, "ascii"));
    Properties cp("shape", "ply");
    cp.set("filename", cloud.string());
    requireThrowsNaming([&] { makeShape("ply", cp); }, cloud.string());
}

// ---- OBJ ------------------------------------------------------------------------------

TEST_CASE("obj shape: polygons, texture coordinates, normals", "[shapes][obj]") {
    fs::path p = scratch.write("quad.obj", "# a quad and a triangle\nmtllib missing.mtl\n"
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
    check(scratch.dir() / "missing.obj");
    check(scratch.write("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n"));         // index 0 / junk
    check(scratch.write("range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"));         // past the end
    check(scratch.write("relative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -7\n"));   // before the start
    check(scratch.write("nofaces.obj", "v 0 0 0\nv 1 0 0\n"));
    check(scratch.write("binary.obj", std::string("\x7f" "ELF\x02\x01\x01\0\0\0garbage\xff\xfe", 20)));
}
