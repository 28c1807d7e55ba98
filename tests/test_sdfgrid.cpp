// The .vol reader and the sdfgrid shape: a grid sampled from an analytic sphere agrees
// with the sphere within the trilinear interpolation error (hits, misses, rays from inside,
// normals, area), bad files give one-line errors, and a small scene agrees with Mitsuba 3.
#include "image_helpers.hpp"
#include "reference_regions.hpp"
#include "shape_helpers.hpp"

#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/render/vol_reader.hpp"
#include "effigi/xml/loader.hpp"

#include <catch2/catch.hpp>

#include <unistd.h>

#include <fstream>
#include <functional>
#include <sstream>

using namespace effigi;
using test::makeShape;
using test::requireThrowsNaming;
namespace fs = std::filesystem;

namespace {

fs::path tempDir() {
    fs::path d = fs::temp_directory_path() / ("effigi-test-sdfgrid-" + std::to_string(getpid()));
    fs::create_directories(d);
    return d;
}

fs::path writeFile(const std::string& name, const std::string& bytes) {
    fs::path p = tempDir() / name;
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
}

/// A grid of nx·ny·nz points over [0,1]³ sampled from sdf.
VolGrid sampleGrid(int nx, int ny, int nz, const std::function<double(const Vector3d&)>& sdf) {
    VolGrid g;
    g.size[0] = std::uint32_t(nx), g.size[1] = std::uint32_t(ny), g.size[2] = std::uint32_t(nz);
    g.channels = 1;
    g.bbox = BBox3f(Point3f(0.f), Point3f(1.f));
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i)
                g.data.push_back(float(sdf(Vector3d(double(i) / (nx - 1), double(j) / (ny - 1), double(k) / (nz - 1)))));
    return g;
}

// The sphere used throughout: centre (0.5, 0.45, 0.55), radius 0.3 in the unit cube. The
// grid is deliberately not cubic, so that an axis mix-up moves the surface.
const Vector3d C(0.5, 0.45, 0.55);
constexpr double R = 0.3;
constexpr int NX = 33, NY = 29, NZ = 37;

fs::path sphereFile() {
    static fs::path p = writeFile("sphere.vol", encodeVol(sampleGrid(NX, NY, NZ, [](const Vector3d& q) {
                                      return glm::length(q - C) - R;
                                  })));
    return p;
}

Ref<IShape> sphereGrid(const Transform& toWorld, const std::string& normals = "smooth", bool flip = false) {
    Properties p("shape", "sdfgrid");
    p.set("filename", sphereFile().string());
    p.set("to_world", toWorld);
    p.set("normals", normals);
    p.set("flip_normals", flip);
    return makeShape("sdfgrid", p);
}

/// Trilinear interpolation error bound for the sphere SDF: h²/8 · Σ|∂²f| ≤ 3h²/(8ρ) near
/// the surface (ρ ≈ R), with h the largest grid spacing; doubled for margin.
const double InterpError = 2.0 * 3.0 / (8.0 * R * (NX - 1) * (NX - 1));

} // namespace

TEST_CASE("vol reader: round trip of a multi-channel grid", "[sdfgrid][vol]") {
    VolGrid g;
    g.size[0] = 3, g.size[1] = 2, g.size[2] = 4;
    g.channels = 2;
    g.bbox = BBox3f(Point3f(-1.f, 0.f, 2.f), Point3f(1.f, 0.5f, 3.f));
    for (int i = 0; i < 3 * 2 * 4 * 2; ++i) g.data.push_back(float(i) * 0.25f - 3.f);
    fs::path p = writeFile("round.vol", encodeVol(g));
    CHECK(fs::file_size(p) == 48 + 4 * g.data.size());
    VolGrid r = readVol(p);
    CHECK(r.size[0] == 3);
    CHECK(r.size[1] == 2);
    CHECK(r.size[2] == 4);
    CHECK(r.channels == 2);
    CHECK(r.bbox.min == g.bbox.min);
    CHECK(r.bbox.max == g.bbox.max);
    CHECK(r.data == g.data);
    // x fastest, then y, then z, channels innermost.
    CHECK(r.at(1, 0, 0, 0) == g.data[2]);
    CHECK(r.at(0, 1, 0, 1) == g.data[3 * 2 + 1]);
    CHECK(r.at(2, 1, 3, 1) == g.data.back());
}

TEST_CASE("vol reader: malformed files give one-line errors naming the file", "[sdfgrid][vol]") {
    VolGrid g = sampleGrid(3, 3, 3, [](const Vector3d& q) { return q.x - 0.5; });
    std::string good = encodeVol(g);
    auto check = [](const std::string& name, const std::string& bytes, const std::string& cause) {
        fs::path p = writeFile(name, bytes);
        requireThrowsNaming([&] { readVol(p); }, p.string());
        requireThrowsNaming([&] { readVol(p); }, cause);
    };
    std::string s = good;
    s[0] = 'X';
    check("magic.vol", s, "not a .vol");
    s = good;
    s[3] = 2;
    check("version.vol", s, "version 2");
    s = good;
    s[4] = 2;
    check("encoding.vol", s, "encoding 2");
    check("header.vol", good.substr(0, 30), "header");
    check("truncated.vol", good.substr(0, good.size() - 4), "truncated");
    s = good;
    s[12] = 0;  // y resolution 3 -> 0
    check("dims.vol", s, "y size is 0");
    s = good;
    s[8] = 5;  // x resolution 3 -> 5: more values than the file has
    check("mismatch.vol", s, "truncated");
    g.data[7] = std::numeric_limits<float>::quiet_NaN();
    check("nan.vol", encodeVol(g), "(1, 2, 0)");
    fs::path missing = tempDir() / "missing.vol";
    requireThrowsNaming([&] { readVol(missing); }, missing.string());
}

TEST_CASE("sdfgrid: hits, misses and rays from inside agree with the sampled sphere", "[sdfgrid]") {
    // World: scale 2 and an offset; the sphere is then centre T(C), radius 2R.
    Transform toWorld = Transform::translate({1.f, -2.f, 3.f}) * Transform::scale(Vector3f(2.f));
    Ref<IShape> s = sphereGrid(toWorld);
    Vector3d c = Vector3d(toWorld.point(Point3f(C))), rw = Vector3d(2.0 * R);
    double tol = 2.0 * InterpError;  // world units: the scale doubles object-space errors
    PCG32 rng(7, 1);
    int hits = 0;
    for (int i = 0; i < 2000; ++i) {
        // Directions uniform on the sphere; origins 3 radii out, aimed with an impact
        // parameter uniform in [0, 1.3 R]: both hits and misses.
        double z = 2.0 * rng.nextFloat() - 1.0, phi = 2.0 * Pi * rng.nextFloat();
        Vector3d d(std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), z);
        Vector3d e1 = glm::normalize(glm::cross(d, std::abs(d.x) < 0.9 ? Vector3d(1, 0, 0) : Vector3d(0, 1, 0)));
        double b = 1.3 * rw.x * rng.nextFloat();
        Vector3d o = c - 3.0 * rw.x * d + b * e1;
        Ray ray{Point3f(o), Vector3f(d), Infinity};
        float t;
        Point2f uv;
        bool hit = s->intersect(ray, t, uv);
        double tSphere = 3.0 * rw.x - std::sqrt(std::max(0.0, rw.x * rw.x - b * b));
        INFO("impact parameter " << b / rw.x << " radii");
        if (b < rw.x - 0.05) {  // clearly hitting: the same first hit as the analytic sphere
            REQUIRE(hit);
            ++hits;
            // The hit lies on the sphere within the interpolation error, and t agrees
            // (the slope of |p - c| along the ray is at least sqrt(1 - (b/r)²) ≥ 0.3 here).
            double dist = glm::length(o + double(t) * d - c);
            CHECK(std::abs(dist - rw.x) < tol);
            CHECK(std::abs(double(t) - tSphere) < tol / 0.3);
        } else if (b > rw.x + 0.05) {
            CHECK_FALSE(hit);
        }
        // Pointing away: nothing.
        Ray away{Point3f(o), Vector3f(-d), Infinity};
        CHECK_FALSE(s->intersect(away, t, uv));
        // tMax before the surface: nothing.
        Ray shortRay{Point3f(o), Vector3f(d), float(0.9 * (3.0 * rw.x - rw.x))};
        CHECK_FALSE(s->intersect(shortRay, t, uv));
        // From inside (random interior point), the exit point.
        Vector3d in = c + 0.5 * rw.x * Vector3d(rng.nextFloat() - 0.5, rng.nextFloat() - 0.5, rng.nextFloat() - 0.5);
        Ray inside{Point3f(in), Vector3f(d), Infinity};
        REQUIRE(s->intersect(inside, t, uv));
        CHECK(std::abs(glm::length(in + double(t) * d - c) - rw.x) < tol);
    }
    CHECK(hits > 1000);
}

TEST_CASE("sdfgrid: axis-aligned rays and rays along grid lines, at tiny and huge scales", "[sdfgrid]") {
    for (float scale : {1e-3f, 1.f, 1e3f}) {
        Transform toWorld = Transform::translate(Vector3f(5.f * scale)) * Transform::scale(Vector3f(scale));
        Ref<IShape> s = sphereGrid(toWorld);
        Vector3d c = Vector3d(toWorld.point(Point3f(C)));
        double r = R * scale;
        for (int a = 0; a < 3; ++a)
            for (double sign : {1.0, -1.0})
                // Through the centre, and along the grid line nearest to it (a ray with two
                // zero direction components lying exactly on cell faces).
                for (bool onGridLine : {false, true}) {
                    Vector3d o = c, d(0.0);
                    d[a] = sign;
                    o[a] -= sign * 3.0 * r;
                    if (onGridLine)
                        for (int b = 0; b < 3; ++b) {
                            if (b == a) continue;
                            int n = b == 0 ? NX : (b == 1 ? NY : NZ);
                            double g = std::round(C[b] * (n - 1)) / (n - 1);  // grid coordinate
                            o[b] = double(toWorld.point(Point3f(Vector3f(float(g)))) [b]);
                        }
                    Ray ray{Point3f(o), Vector3f(d), Infinity};
                    float t;
                    Point2f uv;
                    INFO("scale " << scale << ", axis " << a << ", sign " << sign << ", grid line " << onGridLine);
                    REQUIRE(s->intersect(ray, t, uv));
                    double dist = glm::length(Vector3d(ray.o) + double(t) * d - c);
                    CHECK(std::abs(dist - r) < 2.0 * InterpError * scale);
                }
    }
}

TEST_CASE("sdfgrid: normals follow the gradient under a non-uniform to_world", "[sdfgrid]") {
    // An ellipsoid: object sphere through a non-uniform scale; its exact normal at the
    // world point p is M⁻ᵀ (p_obj - C), normalised.
    Transform toWorld = Transform::translate({0.f, 1.f, 0.f}) * Transform::scale({1.f, 3.f, 0.5f});
    for (std::string mode : {"analytic", "smooth"})
        for (bool flip : {false, true}) {
            Ref<IShape> s = sphereGrid(toWorld, mode, flip);
            PCG32 rng(11, 1);
            double worstGeo = 1.0, worstShade = 1.0;
            for (int i = 0; i < 500; ++i) {
                // Rays from far outside through random interior points.
                Vector3d target = C + 0.5 * R * Vector3d(rng.nextFloat() - 0.5, rng.nextFloat() - 0.5, rng.nextFloat() - 0.5);
                double z = 2.0 * rng.nextFloat() - 1.0, phi = 2.0 * Pi * rng.nextFloat();
                Vector3d dir(std::sqrt(1 - z * z) * std::cos(phi), std::sqrt(1 - z * z) * std::sin(phi), z);
                Point3f tw = toWorld.point(Point3f(target));
                Ray ray{tw - 10.f * Vector3f(dir), Vector3f(dir), Infinity};
                Hit h;
                REQUIRE(test::trace(*s, ray, h));
                SurfaceInteraction si = s->interaction(ray, h);
                Vector3d pObj = Vector3d(toWorld.inverse().point(si.p)) - C;
                Vector3d exact = glm::normalize(Vector3d(toWorld.normal(Normal3f(pObj))));
                if (flip) exact = -exact;
                worstGeo = std::min(worstGeo, glm::dot(Vector3d(si.n), exact));
                worstShade = std::min(worstShade, glm::dot(Vector3d(si.shading.n), exact));
                CHECK(std::abs(glm::length(si.n) - 1.f) < 1e-5f);
                CHECK(std::abs(glm::length(si.shading.n) - 1.f) < 1e-5f);
                CHECK(si.uv == Point2f(0.f));
            }
            INFO(mode << (flip ? " flipped" : "") << ": worst cosine geometric " << worstGeo << ", shading "
                      << worstShade);
            // The gradient of a trilinear interpolant is off by O(h / R): a few degrees
            // at 32 cells, more where the scale stretches the cells 6:1.
            CHECK(worstGeo > 0.97);
            CHECK(worstShade > 0.97);
        }
}

TEST_CASE("sdfgrid: area estimate, bounds and position samples", "[sdfgrid]") {
    Transform toWorld = Transform::scale(Vector3f(2.f));
    Ref<IShape> s = sphereGrid(toWorld);
    double exact = 4.0 * Pi * (2 * R) * (2 * R);
    INFO("area " << s->area() << ", exact " << exact);
    CHECK(std::abs(s->area() - exact) < 0.02 * exact);  // the edge-count estimate, a few % at this grid
    BBox3f b = s->bbox();
    for (int a = 0; a < 3; ++a) {
        CHECK(b.min[a] <= float(2 * (C[a] - R)));
        CHECK(b.max[a] >= float(2 * (C[a] + R)));
        CHECK(b.max[a] - b.min[a] < float(2 * (2 * R + 0.2)));  // tight: occupied cells only
    }
    PCG32 rng(3, 1);
    for (int i = 0; i < 100; ++i) {
        PositionSample ps = s->samplePosition(Point2f(rng.nextFloat(), rng.nextFloat()));
        Vector3d q = Vector3d(ps.p) / 2.0 - C;
        CHECK(std::abs(glm::length(q) - R) < InterpError);
        CHECK(glm::dot(Vector3d(ps.n), glm::normalize(q)) > 0.97);
        CHECK(ps.pdf == Approx(1.f / s->area()));
    }
}

TEST_CASE("sdfgrid: bad input is a one-line error", "[sdfgrid]") {
    auto make = [](const fs::path& file) {
        Properties p("shape", "sdfgrid");
        p.set("filename", file.string());
        return makeShape("sdfgrid", p);
    };
    VolGrid two = sampleGrid(4, 4, 4, [](const Vector3d& q) { return q.x - 0.5; });
    two.channels = 2;
    two.data.insert(two.data.end(), two.data.begin(), two.data.end());
    fs::path p2 = writeFile("two.vol", encodeVol(two));
    requireThrowsNaming([&] { make(p2); }, "2 channels");
    fs::path flat = writeFile("flat.vol", encodeVol(sampleGrid(4, 1, 4, [](const Vector3d& q) { return q.x - 0.5; })));
    requireThrowsNaming([&] { make(flat); }, "at least 2");
    fs::path empty = writeFile("empty.vol", encodeVol(sampleGrid(4, 4, 4, [](const Vector3d&) { return 1.0; })));
    requireThrowsNaming([&] { make(empty); }, "no surface");
    fs::path missing = tempDir() / "nope.vol";
    requireThrowsNaming([&] { make(missing); }, missing.string());
    fs::path bad = writeFile("bad.vol", "VOX");
    requireThrowsNaming([&] { make(bad); }, "not a .vol");
    Properties wrongMode("shape", "sdfgrid");
    wrongMode.set("filename", sphereFile().string());
    wrongMode.set("normals", std::string("flat"));
    requireThrowsNaming([&] { makeShape("sdfgrid", wrongMode); }, "normals");

    // An area emitter is refused (as in Mitsuba), with the scene file and line.
    fs::path grid = writeFile("plane.vol", encodeVol(sampleGrid(4, 4, 4, [](const Vector3d& q) { return q.x - 0.5; })));
    fs::path scene = writeFile("emitter.xml", "<scene version=\"3.0.0\">\n<shape type=\"sdfgrid\">\n"
                                              "<string name=\"filename\" value=\"" + grid.string() + "\"/>\n"
                                              "<emitter type=\"area\"/>\n</shape>\n</scene>\n");
    requireThrowsNaming([&] { loadSceneFile(scene); }, "cannot be an area emitter");
    requireThrowsNaming([&] { loadSceneFile(scene); }, "emitter.xml:");
}

TEST_CASE("sdfgrid: hit distances and normals agree with Mitsuba's, ray by ray", "[sdfgrid]") {
    // tests/data/sdfgrid/mitsuba-rays.txt: Mitsuba 3.9.1's answers for 400 seeded rays
    // against shape.vol (made by mitsuba_rays.py there). Mitsuba stops its root search at
    // 1e-5 in t and works in float; measured: t within 2.4e-7, normals within 1 - cos = 1.2e-7.
    const std::string dir = EFFIGI_SOURCE_DIR "/tests/data/sdfgrid/";
    std::ifstream in(dir + "mitsuba-rays.txt");
    REQUIRE(in);
    Ref<IShape> smooth, analytic;
    for (const char* mode : {"smooth", "analytic"}) {
        Properties p("shape", "sdfgrid");
        p.set("filename", dir + "shape.vol");
        p.set("normals", std::string(mode));
        (std::string(mode) == "smooth" ? smooth : analytic) = makeShape("sdfgrid", p);
    }
    std::string line;
    int rays = 0, hits = 0;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream ss(line);
        float v[16];
        std::string tok;
        for (float& x : v) {
            REQUIRE(ss >> tok);
            x = std::strtof(tok.c_str(), nullptr);  // also reads "inf", unlike operator>>
        }
        ++rays;
        Ray ray{Point3f(v[0], v[1], v[2]), Vector3f(v[3], v[4], v[5]), Infinity};
        Hit h;
        bool hit = test::trace(*smooth, ray, h);
        INFO("ray " << rays << ": " << line);
        REQUIRE(hit == std::isfinite(v[6]));
        if (!hit) continue;
        ++hits;
        CHECK(std::abs(h.t - v[6]) < 2e-5f);
        SurfaceInteraction s = smooth->interaction(ray, h), a = analytic->interaction(ray, h);
        CHECK(dot(s.n, Vector3f(v[7], v[8], v[9])) > 0.99999f);
        CHECK(dot(s.shading.n, Vector3f(v[10], v[11], v[12])) > 0.99999f);
        CHECK(dot(a.shading.n, Vector3f(v[13], v[14], v[15])) > 0.99999f);
    }
    CHECK(rays == 400);
    CHECK(hits > 100);
}

// End to end: tests/data/sdfgrid/sdfgrid.xml (two grids, smooth and analytic normals, one
// non-uniformly scaled) at 64 spp against Mitsuba 3.9.1 scalar_spectral at 4096 spp.
// Tolerance per box mean and channel: 2 % systematic (RGB upsampling differences) plus
// 4 standard errors of effigi's mean from its own per-pixel variance (two-sided false
// alarm about 6e-5 per check); the reference's noise is 8x smaller.
TEST_CASE("sdfgrid: a small scene agrees with Mitsuba 3", "[sdfgrid][e2e]") {
    // Boxes in image fractions: the near (analytic) grid on the left, the far (smooth) one, the
    // floor with their shadows, and the whole image. The tolerance must stay below 7 % (4
    // standard errors below 5 %) to catch real errors.
    test::compareWithReference("tests/data/sdfgrid/sdfgrid.xml", "tests/data/sdfgrid/sdfgrid-mitsuba.exr", {{"spp", "64"}},
                         {{"analytic grid (near)", 0.05f, 0.30f, 0.40f, 0.62f},
                          {"smooth grid (far)", 0.62f, 0.28f, 0.95f, 0.62f},
                          {"shadows", 0.05f, 0.62f, 0.95f, 0.85f},
                          {"all", 0.f, 0.f, 1.f, 1.f}},
                         0.02, 0.07, 5);
}
