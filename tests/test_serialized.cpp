// The serialized shape (Mitsuba's zlib-compressed mesh format): a tiny writer in this
// file produces version 3 and 4 files (single and double precision, several meshes,
// optional normals / uvs / colours), the shape must read back exactly what was written,
// seek to any mesh through the end-of-file dictionary, and turn every kind of damage
// into one error line naming the file.
#include "shape_helpers.hpp"
#include "skip.hpp"
#include "temp_files.hpp"

#include <cstring>
#include <cstdlib>
#include <filesystem>

using namespace effigi;
using namespace effigi::test;
namespace fs = std::filesystem;

namespace {

/// Removed at exit with everything the tests wrote into it.
const ScratchDir scratch("serialized");

/// A zlib stream (RFC 1950) made of uncompressed "stored" deflate blocks (RFC 1951
/// §3.2.4): valid input for any inflater, and short enough to write here.
std::string zlibStored(const std::string& data) {
    std::string out("\x78\x01", 2);
    std::size_t pos = 0;
    do {
        std::size_t n = std::min<std::size_t>(65535, data.size() - pos);
        out += char(pos + n == data.size() ? 1 : 0);  // BFINAL, BTYPE = 00
        put(out, std::uint16_t(n));
        put(out, std::uint16_t(~n));
        out += data.substr(pos, n);
        pos += n;
    } while (pos < data.size());
    std::uint32_t a = 1, b = 0;  // Adler-32, stored big endian
    for (unsigned char c : data) {
        a = (a + c) % 65521;
        b = (b + a) % 65521;
    }
    std::uint32_t adler = (b << 16) | a;
    for (int shift = 24; shift >= 0; shift -= 8) out += char((adler >> shift) & 0xff);
    return out;
}

struct SerMesh {
    std::vector<Point3f> p;
    std::vector<Normal3f> n;
    std::vector<Point2f> uv;
    std::vector<Point3f> colors;
    std::vector<std::uint32_t> idx;
};

/// One mesh record: header + zlib stream.
std::string meshRecord(const SerMesh& m, int version, bool dp) {
    std::string s;
    std::uint32_t flags = (m.n.empty() ? 0 : 1) | (m.uv.empty() ? 0 : 2) | (m.colors.empty() ? 0 : 8) | (dp ? 0x2000 : 0x1000);
    put(s, flags);
    if (version == 4) s += std::string("mesh\0", 5);
    put(s, std::uint64_t(m.p.size()));
    put(s, std::uint64_t(m.idx.size() / 3));
    auto reals = [&](const float* f, std::size_t count) {
        for (std::size_t i = 0; i < count; ++i) dp ? put(s, double(f[i])) : put(s, f[i]);
    };
    reals(&m.p[0].x, 3 * m.p.size());
    if (!m.n.empty()) reals(&m.n[0].x, 3 * m.n.size());
    if (!m.uv.empty()) reals(&m.uv[0].x, 2 * m.uv.size());
    if (!m.colors.empty()) reals(&m.colors[0].x, 3 * m.colors.size());
    for (std::uint32_t i : m.idx) put(s, i);
    std::string out;
    put(out, std::uint16_t(0x041C));
    put(out, std::uint16_t(version));
    return out + zlibStored(s);
}

/// A whole file: records, then the dictionary of their offsets and the count.
std::string serializedFile(const std::vector<SerMesh>& meshes, int version, bool dp = false) {
    std::string out;
    std::vector<std::uint64_t> offsets;
    for (const SerMesh& m : meshes) {
        offsets.push_back(out.size());
        out += meshRecord(m, version, dp);
    }
    for (std::uint64_t o : offsets) version == 4 ? put(out, o) : put(out, std::uint32_t(o));
    put(out, std::uint32_t(meshes.size()));
    return out;
}

/// A unit quad at height z with normals +z, uvs and colours.
SerMesh quad(float z, float size = 1.f) {
    SerMesh m;
    m.p = {{0.f, 0.f, z}, {size, 0.f, z}, {size, size, z}, {0.f, size, z}};
    m.n.assign(4, Normal3f(0.f, 0.f, 1.f));
    m.uv = {{0.f, 0.f}, {1.f, 0.f}, {1.f, 1.f}, {0.f, 1.f}};
    m.idx = {0, 1, 2, 0, 2, 3};
    return m;
}

Ref<IShape> load(const fs::path& file, std::int64_t index = 0, Properties props = Properties("shape", "serialized")) {
    props.set("filename", file.string());
    props.set("shape_index", index);
    return makeShape("serialized", props);
}

} // namespace

TEST_CASE("serialized: reads back what was written, versions 3 and 4, float and double", "[shapes][serialized]") {
    SerMesh m = quad(0.f);
    m.p[2] = {1.25f, 1.5f, 0.125f};  // not planar, so the normals differ from face normals
    m.n[1] = normalize(Normal3f(0.1f, 0.2f, 1.f));
    m.uv[3] = {0.3f, 0.7f};
    for (int version : {3, 4})
        for (bool dp : {false, true}) {
            INFO("version " << version << " double " << dp);
            fs::path f = scratch.write(fmt::format("one_v{}_{}.serialized", version, dp), serializedFile({m}, version, dp));
            Ref<IShape> s = load(f);
            const TriangleMesh& r = *s->mesh();
            REQUIRE(r.vertexCount() == 4);
            REQUIRE(r.triangleCount() == 2);
            CHECK(r.positions == m.p);
            CHECK(r.indices == m.idx);
            REQUIRE(r.uvs.size() == 4);
            CHECK(r.uvs == m.uv);  // no v flip: Mitsuba stores uvs as they are used
            REQUIRE(r.normals.size() == 4);
            for (int i = 0; i < 4; ++i) CHECK(length(r.normals[i] - m.n[i]) < 1e-6f);
        }
}

TEST_CASE("serialized: shape_index seeks to each mesh and reads only that one", "[shapes][serialized]") {
    std::vector<SerMesh> meshes = {quad(0.f), quad(1.f, 2.f), quad(5.f, 0.5f)};
    meshes[1].n.clear();                                // no normals
    meshes[2].uv.clear();                               // no uvs
    meshes[2].colors.assign(4, Point3f(0.5f));          // colours are skipped
    for (int version : {3, 4}) {
        INFO("version " << version);
        std::string bytes = serializedFile(meshes, version);
        fs::path f = scratch.write(fmt::format("three_v{}.serialized", version), bytes);
        for (int i = 0; i < 3; ++i) {
            Ref<IShape> s = load(f, i);
            CHECK(s->mesh()->positions == meshes[std::size_t(i)].p);
            // A mesh stored without normals gets smooth ones computed, as in Mitsuba.
            CHECK(s->mesh()->normals.size() == meshes[std::size_t(i)].p.size());
            if (!meshes[std::size_t(i)].n.empty()) CHECK(s->mesh()->normals == meshes[std::size_t(i)].n);
            CHECK(s->mesh()->uvs.size() == meshes[std::size_t(i)].uv.size());
        }
        // Break mesh 0's stream: meshes 1 and 2 still load (they are reached by seeking),
        // mesh 0 reports a zlib error.
        std::string broken = bytes;
        broken[4] = '\x00';  // zlib header byte CMF
        fs::path fb = scratch.write(fmt::format("broken0_v{}.serialized", version), broken);
        CHECK(load(fb, 2)->mesh()->positions == meshes[2].p);
        requireThrowsNaming([&] { load(fb, 0); }, fb.string());
        requireThrowsNaming([&] { load(f, 3); }, "shape_index 3 is out of range");
    }
}

TEST_CASE("serialized: face_normals, flip_normals and to_world", "[shapes][serialized]") {
    fs::path f = scratch.write("flags.serialized", serializedFile({quad(0.f)}, 4));
    Properties p("shape", "serialized");
    p.set("face_normals", true);
    p.set("flip_normals", true);
    p.set("to_world", Transform::translate({0.f, 0.f, 2.f}) * Transform::scale({2.f, 2.f, 2.f}));
    Ref<IShape> s = load(f, 0, p);
    CHECK(s->mesh()->normals.empty());
    CHECK(s->area() == Approx(4.f));
    CHECK(s->bbox().min.z == Approx(2.f));
    // Flipped winding: the geometric normal of a hit from above points down.
    Ray ray{{0.5f, 0.5f, 5.f}, {0.f, 0.f, -1.f}};
    Hit hit;
    REQUIRE(trace(*s, ray, hit));
    CHECK(s->interaction(ray, hit).n.z == Approx(-1.f));

    Properties q("shape", "serialized");
    q.set("flip_normals", true);
    Ref<IShape> t = load(f, 0, q);
    REQUIRE(t->mesh()->normals.size() == 4);
    CHECK(t->mesh()->normals[0].z == Approx(-1.f));
}

TEST_CASE("serialized: damaged files give one error line naming the file and the cause", "[shapes][serialized]") {
    std::string good = serializedFile({quad(0.f), quad(1.f)}, 4);
    auto check = [](const std::string& name, const std::string& bytes, const std::string& cause, std::int64_t index = 0) {
        fs::path f = scratch.write(name, bytes);
        INFO(name);
        requireThrowsNaming([&] { load(f, index); }, f.string());
        requireThrowsNaming([&] { load(f, index); }, cause);
    };
    requireThrowsNaming([&] { load(scratch.dir() / "missing.serialized"); }, "missing.serialized");
    check("empty.serialized", "", "truncated");
    check("magic.serialized", "\x1d\x04" + good.substr(2), "magic");
    check("version.serialized", good.substr(0, 2) + std::string("\x05\x00", 2) + good.substr(4), "version 5");
    check("truncated.serialized", good.substr(0, 40), "truncated");
    check("header.serialized", good.substr(0, 3), "truncated");
    std::string zerr = good;
    zerr[5] = '\x7f';  // FCHECK no longer makes CMF·FLG a multiple of 31
    check("zlib.serialized", zerr, "zlib");
    check("index.serialized", good, "out of range", 2);
    check("dictionary.serialized", good.substr(0, good.size() - 12) + std::string("\x00\x00\x00\x40", 4), "dictionary", 1);

    SerMesh bad = quad(0.f);
    bad.idx[4] = 4;  // one past the last vertex
    check("vindex.serialized", serializedFile({bad}, 3), "out of range");
    SerMesh huge = quad(0.f);
    std::string rec = meshRecord(huge, 3, false);
    // Claim 2^40 vertices: rejected before any allocation.
    std::string payload;
    put(payload, std::uint32_t(0x1000));
    put(payload, std::uint64_t(1) << 40);
    put(payload, std::uint64_t(1));
    check("counts.serialized", rec.substr(0, 4) + zlibStored(payload), "implausible");

    Properties neg("shape", "serialized");
    neg.set("filename", scratch.write("neg.serialized", good).string());
    neg.set("shape_index", std::int64_t(-1));
    CHECK_THROWS_AS(Registry::instance().create("shape", "serialized", neg), Error);
}

TEST_CASE("serialized: the Mitsuba corpus meshes load", "[shapes][serialized]") {
    // Files written by Mitsuba itself, from the public corpus where EFFIGI_MITSUBA_CORPUS
    // names a checkout of it (as for bench/mitsuba_corpus.py).
    const char* dir = std::getenv("EFFIGI_MITSUBA_CORPUS");
    const fs::path corpus = dir ? dir : "";
    const fs::path rect = corpus / "tests/serialized/rectangle_normals_uv.serialized";
    const fs::path mat = corpus / "scenes/matpreview/matpreview.serialized";
    if (!fs::exists(rect) || !fs::exists(mat)) {
        return test::skipTest("EFFIGI_MITSUBA_CORPUS does not name a Mitsuba corpus checkout");
    }
    // Expected values: what Mitsuba 3.9.1 (scalar_rgb) reports for the same files.
    for (const char* name : {"rectangle_normals_uv", "rectangle_normals", "rectangle_uv"}) {
        Ref<IShape> s = load(corpus / "tests/serialized" / (std::string(name) + ".serialized"));
        INFO(name);
        CHECK(s->mesh()->triangleCount() == 2);
        CHECK(s->mesh()->vertexCount() == 4);
        CHECK(s->area() == Approx(46.73999f).epsilon(1e-5));
        CHECK(s->bbox().min.x == Approx(-2.85f));
        CHECK(s->bbox().min.z == Approx(-7.6f));
        CHECK(s->bbox().max.z == Approx(0.6f));
    }
    // matpreview (version 3): the plane, the interior and the exterior of the material ball.
    const std::size_t faces[3] = {512, 3936, 57152}, vertices[3] = {289, 2078, 29439};
    const float areas[3] = {4.960819f, 8.681538f, 32.166462f};
    for (int i = 0; i < 3; ++i) {
        Ref<IShape> s = load(mat, i);
        INFO("matpreview mesh " << i);
        CHECK(s->mesh()->triangleCount() == faces[i]);
        CHECK(s->mesh()->vertexCount() == vertices[i]);
        CHECK(s->mesh()->normals.size() == vertices[i]);
        CHECK(s->area() == Approx(areas[i]).epsilon(1e-4));
    }
    requireThrowsNaming([&] { load(mat, 3); }, "out of range");
}
