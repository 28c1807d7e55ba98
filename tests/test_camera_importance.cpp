// ICameraImportance of the thin-lens and orthographic cameras (the light tracer's
// connection to the camera), as tests/test_ptracer.cpp checks it for perspective:
// - the connection inverts generateRay (film position, direction, distance, lens point);
// - the importance integrates to 1 over the film: over the sphere of directions from a
//   lens point (thinlens), over the plane across the viewing direction (orthographic);
// - thinlens with aperture 0 connects exactly as the perspective camera does;
// - points outside the clip slab or the film do not connect;
// - ptracer agrees with `path` through a thin lens (tests/data/ptracer/thinlens.xml) and
//   through a scaled orthographic camera (tests/data/ptracer/scene.xml, edited in memory).
#include "camera_helpers.hpp"
#include "image_helpers.hpp"
#include "scene_text.hpp"

#include "effigi/interfaces/icamera_importance.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/xml/loader.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

using namespace effigi;
using effigi::test::readText;

namespace {

using test::makeCamera;
using test::Params;
using test::rayAt;

const Point3f Eye(1.f, 2.f, 5.f), Target(0.f, 0.5f, 0.f);
const Vector3f Up(0.f, 1.f, 0.f);

const ICameraImportance& importanceOf(ICamera& cam) {
    const ICameraImportance* imp = query<ICameraImportance>(&cam);
    REQUIRE(imp);
    return *imp;
}

/// Mean and standard error of n samples of f(rng).
template <typename F> std::pair<double, double> monteCarlo(int n, PCG32& rng, F f) {
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        double v = f(rng);
        sum += v;
        sum2 += v * v;
    }
    double mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n)};
}

Params thinLensParams(double aperture) {
    return {{"to_world", Transform::lookAt(Eye, Target, Up)}, {"fov", 40.0}, {"near_clip", 0.05},
            {"far_clip", 30.0}, {"aperture_radius", aperture}, {"focus_distance", 4.0}};
}

Params orthoParams() {
    // Scaled non-uniformly: the film rectangle is 6 x 4/1.5 world units (60 x 40 film).
    return {{"to_world", Transform::lookAt(Eye, Target, Up) * Transform::scale({3.f, 2.f, 1.f})},
            {"near_clip", 0.5}, {"far_clip", 20.0}};
}

} // namespace

TEST_CASE("thinlens: the connection inverts generateRay", "[camera][importance]") {
    auto cam = makeCamera("thinlens", 40, 30, thinLensParams(0.3));
    const ICameraImportance& imp = importanceOf(*cam);
    PCG32 rng(4242, 3);
    for (int i = 0; i < 300; ++i) {
        Point2f film(40.f * rng.nextFloat(), 30.f * rng.nextFloat()), u(rng.nextFloat(), rng.nextFloat());
        Ray ray = rayAt(*cam, film, u);
        Point3f p = ray(0.3f + 8.f * rng.nextFloat());
        CameraImportanceSample cs;
        REQUIRE(imp.sampleDirection(p, u, cs));  // the same lens sample: the same lens point
        INFO("film " << film.x << ", " << film.y << " lens " << u.x << ", " << u.y);
        CHECK(cs.pFilm.x == Approx(film.x).margin(2e-3));
        CHECK(cs.pFilm.y == Approx(film.y).margin(2e-3));
        CHECK(dot(cs.wi, -ray.d) == Approx(1.f).margin(1e-5));
        CHECK(cs.dist == Approx(length(p - cs.pCamera)).epsilon(1e-5));
        // The lens point lies on the ray's line, in the lens plane through the eye.
        CHECK(length(cross(cs.pCamera - ray.o, ray.d)) < 1e-4f);
        CHECK(std::abs(dot(cs.pCamera - Eye, normalize(Target - Eye))) < 1e-4f);
        CHECK(length(cs.pCamera - Eye) <= 0.3f + 1e-5f);
        CHECK(cs.pdf == 1.f);
        CHECK_FALSE(cs.deltaDirection);
    }
    // Behind the lens and beyond the far plane: no connection.
    CameraImportanceSample cs;
    CHECK_FALSE(imp.sampleDirection(cam->toWorld().point(Point3f(0.f, 0.f, -1.f)), Point2f(0.5f), cs));
    CHECK(cs.pdf == 0.f);
    CHECK_FALSE(imp.sampleDirection(cam->toWorld().point(Point3f(0.f, 0.f, 31.f)), Point2f(0.5f), cs));
}

TEST_CASE("thinlens: the importance integrates to 1 from every lens point", "[camera][importance]") {
    // For a fixed lens sample, weight · dist² is the importance per solid angle over the
    // lens density; over the directions from that lens point it integrates to 1 (the film
    // is covered once). Directions uniform in a 40° cone about the viewing axis, which
    // holds the whole field of view (diagonal half-angle 24°, plus the lens offset);
    // 200k per lens point, checked to 5 standard errors (false alarm < 6e-7; seeded).
    auto cam = makeCamera("thinlens", 40, 30, thinLensParams(0.3));
    const ICameraImportance& imp = importanceOf(*cam);
    PCG32 rng(77, 5);
    for (Point2f u : {Point2f(0.5f), Point2f(0.9f, 0.2f), Point2f(0.05f, 0.99f)}) {
        CameraImportanceSample axis;  // a point on the axis in focus: learn the lens point
        REQUIRE(imp.sampleDirection(cam->toWorld().point(Point3f(0.f, 0.f, 4.f)), u, axis));
        const Point3f lens = axis.pCamera;
        const float cosMax = std::cos(degToRad(40.f));
        auto [mean, se] = monteCarlo(200000, rng, [&](PCG32& r) {
            Vector3f local = warp::squareToUniformCone(Point2f(r.nextFloat(), r.nextFloat()), cosMax);
            Vector3f d = normalize(cam->toWorld().vector(local));
            const float dist = 3.f;
            CameraImportanceSample cs;
            if (!imp.sampleDirection(lens + dist * d, u, cs)) return 0.0;
            return double(cs.weight) * dist * dist / double(warp::squareToUniformConePdf(local, cosMax));
        });
        INFO("lens sample " << u.x << ", " << u.y << ": integral " << mean << " ± " << se);
        CHECK(std::abs(mean - 1.0) < 5.0 * se);
        CHECK(se < 0.005);
    }
}

TEST_CASE("thinlens: aperture 0 connects as the pinhole camera", "[camera][importance]") {
    Params pinhole = {{"to_world", Transform::lookAt(Eye, Target, Up)}, {"fov", 40.0}, {"near_clip", 0.05},
                      {"far_clip", 30.0}};
    auto pin = makeCamera("perspective", 40, 30, pinhole);
    auto lens = makeCamera("thinlens", 40, 30, thinLensParams(0.0));
    PCG32 rng(9, 1);
    for (int i = 0; i < 200; ++i) {
        Point3f p = Target + Vector3f(rng.nextFloat() - 0.5f, rng.nextFloat() - 0.5f, rng.nextFloat() - 0.5f) * 6.f;
        CameraImportanceSample a, b;
        bool okA = importanceOf(*pin).sampleDirection(p, Point2f(0.5f), a);
        bool okB = importanceOf(*lens).sampleDirection(p, Point2f(rng.nextFloat(), rng.nextFloat()), b);
        REQUIRE(okA == okB);
        if (!okA) continue;
        CHECK(b.pFilm.x == Approx(a.pFilm.x).margin(1e-3));
        CHECK(b.pFilm.y == Approx(a.pFilm.y).margin(1e-3));
        CHECK(b.weight == Approx(a.weight).epsilon(1e-4));
        CHECK(length(b.pCamera - a.pCamera) < 1e-5f);
    }
}

TEST_CASE("orthographic: the connection inverts generateRay", "[camera][importance]") {
    auto cam = makeCamera("orthographic", 60, 40, orthoParams());
    const ICameraImportance& imp = importanceOf(*cam);
    PCG32 rng(31337, 2);
    for (int i = 0; i < 300; ++i) {
        Point2f film(60.f * rng.nextFloat(), 40.f * rng.nextFloat());
        Ray ray = rayAt(*cam, film);
        float t = ray.tMax * rng.nextFloat();
        Point3f p = ray(t);
        CameraImportanceSample cs;
        REQUIRE(imp.sampleDirection(p, Point2f(rng.nextFloat(), rng.nextFloat()), cs));
        INFO("film " << film.x << ", " << film.y);
        CHECK(cs.pFilm.x == Approx(film.x).margin(2e-3));
        CHECK(cs.pFilm.y == Approx(film.y).margin(2e-3));
        CHECK(dot(cs.wi, -ray.d) == Approx(1.f).margin(1e-6));
        CHECK(length(cs.pCamera - ray.o) < 1e-4f);  // the ray's origin on the near plane
        CHECK(cs.dist == Approx(t).margin(1e-4));
        CHECK(cs.pdf == 1.f);
        CHECK(cs.deltaDirection);
    }
    // In front of the near plane, past the far plane, or beside the film: no connection.
    const Vector3f fwd = normalize(Target - Eye);
    CameraImportanceSample cs;
    CHECK_FALSE(imp.sampleDirection(Eye + 0.4f * fwd, Point2f(0.5f), cs));
    CHECK(cs.pdf == 0.f);
    CHECK_FALSE(imp.sampleDirection(Eye + 20.1f * fwd, Point2f(0.5f), cs));
    CHECK(imp.sampleDirection(Eye + 19.9f * fwd, Point2f(0.5f), cs));
    Vector3f side = normalize(cross(fwd, Up));
    CHECK(imp.sampleDirection(Eye + 5.f * fwd + 2.9f * side, Point2f(0.5f), cs));
    CHECK_FALSE(imp.sampleDirection(Eye + 5.f * fwd + 3.1f * side, Point2f(0.5f), cs));
}

TEST_CASE("orthographic: the importance integrates to 1 across the view", "[camera][importance]") {
    // The importance is a delta in direction, spread over area: weight (per unit area
    // across the viewing direction) integrates to 1 over a plane perpendicular to it.
    // Uniform samples on a 10 x 10 square covering the 6 x 2.67 view; 200k samples,
    // 5 standard errors (false alarm < 6e-7; seeded).
    auto cam = makeCamera("orthographic", 60, 40, orthoParams());
    const ICameraImportance& imp = importanceOf(*cam);
    const Vector3f fwd = normalize(Target - Eye), side = normalize(cross(fwd, Up)), up = cross(side, fwd);
    PCG32 rng(555, 8);
    auto [mean, se] = monteCarlo(200000, rng, [&](PCG32& r) {
        Point3f p = Eye + 7.f * fwd + (10.f * r.nextFloat() - 5.f) * side + (10.f * r.nextFloat() - 5.f) * up;
        CameraImportanceSample cs;
        return imp.sampleDirection(p, Point2f(0.5f), cs) ? double(cs.weight) * 100.0 : 0.0;
    });
    INFO("integral " << mean << " ± " << se);
    CHECK(std::abs(mean - 1.0) < 5.0 * se);
    CHECK(se < 0.02);
}

namespace {

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    auto at = text.find(from);
    REQUIRE(at != std::string::npos);
    return text.replace(at, from.size(), to);
}

/// ptracer renders of the scene text `xmlText` (integrator ptracer, 32 x 32, box filter)
/// against a `path` render of it: region means of the four quadrants and the whole image.
/// K = 16 seeded ptracer renders (32 spp); their spread gives the standard error (a light
/// path splats into several pixels). Each region/channel check allows 5.5 standard errors
/// of the difference: Student's t with 15 degrees of freedom exceeds it with two-sided
/// probability < 6e-5.
void checkPtracerAgreesWithPath(const std::string& xmlText, const std::string& file) {
    auto load = [&](const std::string& integrator, const std::string& spp) {
        xml::ParseOptions opt;
        opt.defines = {{"spp", spp}};
        std::string text = replaced(xmlText, "<integrator type=\"ptracer\">", "<integrator type=\"" + integrator + "\">");
        return loadScene(*xml::parseString(text, file, opt));
    };
    struct Region {
        int x0, y0, x1, y1;
    };
    const std::vector<Region> regions = {{0, 0, 16, 16}, {16, 0, 32, 16}, {0, 16, 16, 32}, {16, 16, 32, 32},
                                         {0, 0, 32, 32}};
    auto regionMean = [](const Image& img, const Region& r, int c) {
        double s = 0;
        for (int y = r.y0; y < r.y1; ++y)
            for (int x = r.x0; x < r.x1; ++x) s += img.at(x, y, c);
        return s / (double(r.x1 - r.x0) * (r.y1 - r.y0));
    };
    auto render = [](Scene& scene, std::uint64_t seed) {
        RenderControl control;
        control.progress = false;
        control.seed = seed;
        scene.renderer().render(scene, control);
        return scene.camera().film().develop();
    };

    const int K = 16;
    auto pt = load("ptracer", "32");
    std::vector<double> sum(regions.size() * 3, 0.0), sum2(regions.size() * 3, 0.0);
    for (int k = 1; k <= K; ++k) {
        Image img = render(*pt, std::uint64_t(k) * 104729);
        REQUIRE(img.width == 32);
        REQUIRE(img.height == 32);
        for (std::size_t r = 0; r < regions.size(); ++r)
            for (int c = 0; c < 3; ++c) {
                double m = regionMean(img, regions[r], c);
                sum[r * 3 + c] += m;
                sum2[r * 3 + c] += m * m;
            }
    }
    auto path = load("path", "256");
    Image ref = render(*path, 17);
    std::vector<float> variance;  // path's per-pixel variance; box filter: independent pixels
    REQUIRE(path->renderer().varianceEstimate(variance));
    for (std::size_t r = 0; r < regions.size(); ++r)
        for (int c = 0; c < 3; ++c) {
            const Region& g = regions[r];
            double a = sum[r * 3 + c] / K;
            double seA = std::sqrt(std::max(0.0, (sum2[r * 3 + c] / K - a * a) * K / (K - 1.0)) / K);
            double b = regionMean(ref, g, c), var = 0;
            for (int y = g.y0; y < g.y1; ++y)
                for (int x = g.x0; x < g.x1; ++x) var += variance[(std::size_t(y) * ref.width + x) * 3 + c];
            double n = double(g.x1 - g.x0) * (g.y1 - g.y0), seB = std::sqrt(var) / n;
            double se = std::sqrt(seA * seA + seB * seB);
            INFO("region " << g.x0 << "," << g.y0 << " channel " << c << ": ptracer " << a << " ± " << seA << ", path "
                           << b << " ± " << seB);
            CHECK(std::abs(a - b) < 5.5 * se);
            CHECK(se < 0.03 * b);  // sharp enough to see a missing bounce or a wrong camera weight
        }
}

} // namespace

TEST_CASE("ptracer: agrees with path through a thin lens", "[render][ptracer][importance]") {
    const std::string file = EFFIGI_SOURCE_DIR "/tests/data/ptracer/thinlens.xml";
    checkPtracerAgreesWithPath(readText(file), file);
}

TEST_CASE("ptracer: agrees with path through an orthographic camera", "[render][ptracer][importance]") {
    // tests/data/ptracer/scene.xml seen by a scaled orthographic camera. Emitters seen
    // directly are hidden in both renders: the environment seen along the viewing
    // direction is a delta that a light tracer cannot reach (ICameraImportance).
    const std::string file = EFFIGI_SOURCE_DIR "/tests/data/ptracer/scene.xml";
    std::string text = replaced(readText(file), "<sensor type=\"perspective\">\n        <float name=\"fov\" value=\"45\"/>",
                                "<sensor type=\"orthographic\">");
    text = replaced(text, "<lookat origin=\"0, 1.5, 5\" target=\"0, 0.6, 0\" up=\"0, 1, 0\"/>",
                    "<lookat origin=\"0, 1.5, 5\" target=\"0, 0.6, 0\" up=\"0, 1, 0\"/><scale x=\"2\" y=\"2\"/>");
    text = replaced(text, "<integrator type=\"ptracer\">",
                    "<integrator type=\"ptracer\"><boolean name=\"hide_emitters\" value=\"true\"/>");
    checkPtracerAgreesWithPath(text, file);
}
