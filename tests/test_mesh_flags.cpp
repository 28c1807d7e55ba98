// Mitsuba's mesh flags on every mesh file shape: face_normals (drop vertex normals),
// flip_normals (reverse winding and vertex normals) on obj, ply and serialized, and
// flip_tex_coords (v -> 1 - v) on obj (default on) and ply (default off). One quad with
// normals and uvs is written in all three formats, so the same checks apply to each.
#include "shape_helpers.hpp"
#include "temp_files.hpp"

#include <filesystem>

using namespace effigi;
using namespace effigi::test;
namespace fs = std::filesystem;

namespace {

/// Removed at exit with everything the tests wrote into it.
const ScratchDir scratch("mesh_flags");

// The quad z = 0, [0,1]², normals tilted toward +x (so they differ from the face normal
// +z), uv (x, 0.25 + 0.5 y) so that a v flip is visible.
const float P[4][2] = {{0.f, 0.f}, {1.f, 0.f}, {1.f, 1.f}, {0.f, 1.f}};
const Normal3f N = Normal3f(0.6f, 0.f, 0.8f);
float vOf(int i) { return 0.25f + 0.5f * P[i][1]; }

fs::path objFile() {
    std::string s;
    for (auto& p : P) s += fmt::format("v {} {} 0\n", p[0], p[1]);
    for (int i = 0; i < 4; ++i) s += fmt::format("vt {} {}\n", P[i][0], vOf(i));
    s += fmt::format("vn {} {} {}\n", N.x, N.y, N.z);
    s += "f 1/1/1 2/2/1 3/3/1 4/4/1\n";
    return scratch.write("quad.obj", s);
}

fs::path plyFile() {
    std::string s = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                    "property float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\n"
                    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    for (int i = 0; i < 4; ++i) s += fmt::format("{} {} 0 {} {} {} {} {}\n", P[i][0], P[i][1], N.x, N.y, N.z, P[i][0], vOf(i));
    s += "4 0 1 2 3\n";
    return scratch.write("quad.ply", s);
}

/// Version 3 serialized file with one zlib stream of stored blocks (see test_serialized).
fs::path serializedFile() {
    std::string d;
    put(d, std::uint32_t(0x1003));  // normals, uvs, single precision
    put(d, std::uint64_t(4));
    put(d, std::uint64_t(2));
    for (auto& p : P) put(d, p[0]), put(d, p[1]), put(d, 0.f);
    for (int i = 0; i < 4; ++i) put(d, N.x), put(d, N.y), put(d, N.z);
    for (int i = 0; i < 4; ++i) put(d, P[i][0]), put(d, vOf(i));
    for (std::uint32_t i : {0u, 1u, 2u, 0u, 2u, 3u}) put(d, i);
    std::string z("\x78\x01\x01", 3);
    put(z, std::uint16_t(d.size()));
    put(z, std::uint16_t(~d.size()));
    z += d;
    std::uint32_t a = 1, b = 0;
    for (unsigned char c : d) a = (a + c) % 65521, b = (b + a) % 65521;
    std::uint32_t adler = (b << 16) | a;
    for (int shift = 24; shift >= 0; shift -= 8) z += char((adler >> shift) & 0xff);
    std::string f;
    put(f, std::uint16_t(0x041C));
    put(f, std::uint16_t(3));
    f += z;
    put(f, std::uint32_t(0));
    put(f, std::uint32_t(1));
    return scratch.write("quad.serialized", f);
}

Ref<IShape> load(const std::string& type, const fs::path& file, std::vector<std::pair<std::string, bool>> flags = {}) {
    Properties p("shape", type);
    p.set("filename", file.string());
    for (auto& [k, v] : flags) p.set(k, v);
    return makeShape(type, p);
}

/// The shading normal and uv where a ray from above hits the quad at (x, y).
SurfaceInteraction hitAt(const IShape& s, float x, float y) {
    Ray ray{{x, y, 2.f}, {0.f, 0.f, -1.f}};
    Hit hit;
    REQUIRE(trace(s, ray, hit));
    return s.interaction(ray, hit);
}

} // namespace

TEST_CASE("mesh flags: face_normals and flip_normals on obj, ply and serialized", "[shapes][obj][ply][serialized]") {
    const std::pair<std::string, fs::path> files[] = {{"obj", objFile()}, {"ply", plyFile()}, {"serialized", serializedFile()}};
    for (const auto& [type, file] : files) {
        INFO(type);
        SurfaceInteraction plain = hitAt(*load(type, file), 0.3f, 0.6f);
        CHECK(plain.n.z == Approx(1.f));
        CHECK(length(plain.shading.n - N) < 1e-5f);  // interpolated vertex normal

        SurfaceInteraction flat = hitAt(*load(type, file, {{"face_normals", true}}), 0.3f, 0.6f);
        CHECK(flat.shading.n.z == Approx(1.f));

        SurfaceInteraction flipped = hitAt(*load(type, file, {{"flip_normals", true}}), 0.3f, 0.6f);
        CHECK(flipped.n.z == Approx(-1.f));
        CHECK(length(flipped.shading.n + N) < 1e-5f);

        SurfaceInteraction both = hitAt(*load(type, file, {{"flip_normals", true}, {"face_normals", true}}), 0.3f, 0.6f);
        CHECK(both.shading.n.z == Approx(-1.f));
    }
}

TEST_CASE("mesh flags: flip_tex_coords (obj default on, ply default off)", "[shapes][obj][ply]") {
    const float x = 0.3f, y = 0.6f, v = 0.25f + 0.5f * y;
    struct Case {
        std::string type;
        fs::path file;
        bool defaultFlips;
    };
    for (const Case& c : {Case{"obj", objFile(), true}, Case{"ply", plyFile(), false}}) {
        INFO(c.type);
        SurfaceInteraction d = hitAt(*load(c.type, c.file), x, y);
        CHECK(d.uv.x == Approx(x));
        CHECK(d.uv.y == Approx(c.defaultFlips ? 1.f - v : v));
        SurfaceInteraction on = hitAt(*load(c.type, c.file, {{"flip_tex_coords", true}}), x, y);
        CHECK(on.uv.y == Approx(1.f - v));
        SurfaceInteraction off = hitAt(*load(c.type, c.file, {{"flip_tex_coords", false}}), x, y);
        CHECK(off.uv.y == Approx(v));
    }
}

TEST_CASE("mesh flags: a mesh without normals gets angle-weighted smooth normals", "[shapes][normals]") {
    // A square pyramid: apex (0,0,1) over the base corners (±1, ±1, 0), four side faces and
    // no base. By symmetry the apex normal is +z; a base corner's normal is the
    // angle-weighted mean of its two faces' normals (Thürmer & Wüthrich 1998), computed
    // here independently from the face geometry.
    std::string s = "v 0 0 1\nv 1 1 0\nv -1 1 0\nv -1 -1 0\nv 1 -1 0\nf 1 2 3\nf 1 3 4\nf 1 4 5\nf 1 5 2\n";
    fs::path f = scratch.write("pyramid.obj", s);
    Ref<IShape> smooth = load("obj", f);
    const TriangleMesh& m = *smooth->mesh();
    REQUIRE(m.normals.size() == m.positions.size());
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
        const Point3f& p = m.positions[v];
        Vector3d expect(0.0);
        for (std::size_t t = 0; t < m.triangleCount(); ++t) {
            Point3f q[3];
            m.triangle(t, q[0], q[1], q[2]);
            for (int k = 0; k < 3; ++k) {
                if (q[k] != p) continue;
                Vector3d a = Vector3d(q[(k + 1) % 3] - q[k]), b = Vector3d(q[(k + 2) % 3] - q[k]);
                double angle = std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
                expect += angle * glm::normalize(glm::cross(a, b));
            }
        }
        expect = glm::normalize(expect);
        INFO("vertex " << v);
        CHECK(double(m.normals[v].x) == Approx(expect.x).margin(1e-5));
        CHECK(double(m.normals[v].y) == Approx(expect.y).margin(1e-5));
        CHECK(double(m.normals[v].z) == Approx(expect.z).margin(1e-5));
        CHECK(double(glm::length(m.normals[v])) == Approx(1.0).epsilon(1e-5));
    }
    CHECK(m.normals[0].z == Approx(1.f));  // the apex, by symmetry
    // face_normals keeps the facets flat.
    CHECK(load("obj", f, {{"face_normals", true}})->mesh()->normals.empty());
}
