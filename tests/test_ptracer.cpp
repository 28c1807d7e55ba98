// Renderer ptracer (particle tracing) and the perspective camera's ICameraImportance.
// - The camera's connection inverts generateRay and its importance integrates to 1.
// - ptracer agrees with `path` (region means, statistical tolerance) on
//   tests/data/ptracer/scene.xml, and with Mitsuba 3's ptracer on the same scene and on
//   the corpus scene tests/scenes/various_emitters/test_various_emitters_ptracer.xml.
// - max_depth 0 / 1, hide_emitters, samples_per_pass, progressive passes, crop windows,
//   bad configurations.
// References (Mitsuba 3.9.1, scalar_spectral):
//   python3 bench/mitsuba_reference.py tests/data/ptracer/scene.xml
//           tests/data/ptracer/scene-mitsuba.exr --spp 16384
//   python3 bench/mitsuba_reference.py
//           $EFFIGI_MITSUBA_CORPUS/tests/scenes/various_emitters/test_various_emitters_ptracer.xml
//           tests/data/ptracer/various_emitters-128x16-mitsuba.exr --spp 8192 -D resx=128 -D resy=16
#include "image_helpers.hpp"
#include "scene_text.hpp"
#include "skip.hpp"

#include "effigi/core/error.hpp"
#include "effigi/interfaces/icamera_importance.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/xml/loader.hpp"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace effigi;

namespace {

const std::string SceneFile = EFFIGI_SOURCE_DIR "/tests/data/ptracer/scene.xml";
/// The public Mitsuba scene corpus is not part of the project: this check runs where
/// EFFIGI_MITSUBA_CORPUS names a checkout of it (as bench/mitsuba_corpus.py's DIR).
std::string corpusScene() {
    const char* dir = std::getenv("EFFIGI_MITSUBA_CORPUS");
    return dir ? std::string(dir) + "/tests/scenes/various_emitters/test_various_emitters_ptracer.xml" : "";
}

/// A scene file with text `from` replaced by `to` (must occur).
std::unique_ptr<Scene> loadEdited(const std::string& file, const std::string& from, const std::string& to,
                                  std::map<std::string, std::string> defines = {}) {
    return test::loadEdited(file, from.empty() ? test::TextEdits{} : test::TextEdits{{from, to}}, std::move(defines));
}

/// Mean of channel c (0..2; 3 = grey) over the pixel rectangle [x0, x1) × [y0, y1).
double regionMean(const Image& img, int c, int x0, int y0, int x1, int y1) {
    double sum = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            sum += c < 3 ? img.at(x, y, c) : (img.at(x, y, 0) + img.at(x, y, 1) + img.at(x, y, 2)) / 3.0;
    return sum / (double(x1 - x0) * (y1 - y0));
}

struct Region {
    int x0, y0, x1, y1;
};

/// The four quadrants and the whole image.
std::vector<Region> quadrants(int w, int h) {
    return {{0, 0, w / 2, h / 2}, {w / 2, 0, w, h / 2}, {0, h / 2, w / 2, h}, {w / 2, h / 2, w, h}, {0, 0, w, h}};
}

/// Mean and standard error of a region's value over K independently seeded renders:
/// a light path splats into many pixels, so pixels are not independent and the error
/// is taken from the spread between renders instead.
struct SeededMean {
    double mean = 0, stderr_ = 0;
};

SeededMean seededMean(const std::vector<Image>& renders, int c, const Region& r) {
    double sum = 0, sum2 = 0;
    for (const Image& img : renders) {
        double m = regionMean(img, c, r.x0, r.y0, r.x1, r.y1);
        sum += m;
        sum2 += m * m;
    }
    double k = double(renders.size());
    double mean = sum / k, var = std::max(0.0, (sum2 / k - mean * mean) * k / (k - 1.0));
    return {mean, std::sqrt(var / k)};
}

/// K = 16 renders of the test scene with ptracer (32 spp each: 16 · 32 · 32² light paths).
const std::vector<Image>& ptracerRenders() {
    static std::vector<Image> renders = [] {
        auto scene = loadEdited(SceneFile, "", "");
        std::vector<Image> out;
        for (std::uint64_t seed = 1; seed <= 16; ++seed) {
            RenderStats stats;
            out.push_back(test::renderSeeded(*scene, seed * 7919, &stats));
            REQUIRE(stats.rejectedSamples == 0);
            REQUIRE(stats.samples == 32u * 32u * 32u);
        }
        return out;
    }();
    return renders;
}

// Student's t quantile for a two-sided false-alarm probability of 1e-4 with 15 degrees
// of freedom is 5.24; 5.5 keeps each check's false-alarm probability below 6e-5 (the
// renders are seeded, so the outcome is deterministic).
constexpr double TQuantile = 5.5;

} // namespace

TEST_CASE("ptracer: the perspective camera's connection inverts generateRay", "[render][ptracer]") {
    auto scene = loadEdited(SceneFile, "", "", {{"res", "40"}});
    ICamera& camera = scene->camera();
    const ICameraImportance* imp = query<ICameraImportance>(&camera);
    REQUIRE(imp);
    Vector2i size = camera.film().fullSize();
    PCG32 rng(12345, 7);
    SampledWavelengths lambda = SampledWavelengths::sampleVisible(0.5f);
    for (int i = 0; i < 200; ++i) {
        Point2f pFilm(rng.nextFloat() * float(size.x), rng.nextFloat() * float(size.y));
        SampledSpectrum w;
        Ray ray = camera.generateRay({pFilm, Point2f(0.5f), 0.f}, lambda, w);
        float t = 0.5f + 5.f * rng.nextFloat();
        Point3f p = ray(t);
        CameraImportanceSample cs;
        REQUIRE(imp->sampleDirection(p, Point2f(0.5f), cs));
        INFO("film " << pFilm.x << ", " << pFilm.y);
        CHECK(cs.pFilm.x == Approx(pFilm.x).margin(2e-3));
        CHECK(cs.pFilm.y == Approx(pFilm.y).margin(2e-3));
        CHECK(dot(cs.wi, -ray.d) == Approx(1.f).margin(1e-5));
        CHECK(cs.dist == Approx(length(p - cs.pCamera)).epsilon(1e-5));
        CHECK(cs.pdf == 1.f);
    }
    // Behind the camera: no connection.
    Point3f behind = camera.toWorld().point(Point3f(0.f, 0.f, -1.f));
    CameraImportanceSample cs;
    CHECK_FALSE(imp->sampleDirection(behind, Point2f(0.5f), cs));
    CHECK(cs.pdf == 0.f);

    // The importance per solid angle, weight · dist², integrates to 1 over the sphere
    // of directions (uniform sphere samples; 200k samples, tolerance 5 standard errors).
    const Point3f origin = camera.toWorld().point(Point3f(0.f));
    const int n = 200000;
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        Vector3f d = warp::squareToUniformSphere(Point2f(rng.nextFloat(), rng.nextFloat()));
        float r = 3.f;
        double v = 0;
        if (imp->sampleDirection(origin + r * d, Point2f(0.5f), cs)) v = double(cs.weight) * r * r * 4.0 * Pi;
        sum += v;
        sum2 += v * v;
    }
    double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
    INFO("integral " << mean << " ± " << se);
    CHECK(std::abs(mean - 1.0) < 5.0 * se);
    CHECK(se < 0.02);
}

TEST_CASE("ptracer: agrees with path on the test scene", "[render][ptracer]") {
    const std::vector<Image>& pt = ptracerRenders();
    auto pathScene = loadEdited(SceneFile, "<integrator type=\"ptracer\">", "<integrator type=\"path\">",
                                {{"spp", "64"}});
    RenderControl control;
    control.progress = false;
    control.seed = 17;
    pathScene->renderer().render(*pathScene, control);
    Image path = pathScene->camera().film().develop();
    std::vector<float> variance;  // path's own per-pixel variance; box filter: independent pixels
    REQUIRE(pathScene->renderer().varianceEstimate(variance));
    for (const Region& r : quadrants(path.width, path.height))
        for (int c = 0; c < 3; ++c) {
            SeededMean a = seededMean(pt, c, r);
            double b = regionMean(path, c, r.x0, r.y0, r.x1, r.y1), var = 0;
            for (int y = r.y0; y < r.y1; ++y)
                for (int x = r.x0; x < r.x1; ++x) var += variance[(std::size_t(y) * path.width + x) * 3 + c];
            double n = double(r.x1 - r.x0) * (r.y1 - r.y0), seB = std::sqrt(var) / n;
            double se = std::sqrt(a.stderr_ * a.stderr_ + seB * seB);
            INFO("region " << r.x0 << "," << r.y0 << " channel " << c << ": ptracer " << a.mean << " ± " << a.stderr_
                           << ", path " << b << " ± " << seB);
            CHECK(std::abs(a.mean - b) < TQuantile * se);
            CHECK(se < 0.03 * b);  // sharp enough to see a missing bounce or light
        }
}

TEST_CASE("ptracer: agrees with Mitsuba 3's ptracer on the test scene", "[render][ptracer]") {
    const std::vector<Image>& pt = ptracerRenders();
    test::ExrImage ref = test::readExr(EFFIGI_SOURCE_DIR "/tests/data/ptracer/scene-mitsuba.exr");
    REQUIRE(ref.spec.width == pt[0].width);
    REQUIRE(ref.spec.height == pt[0].height);
    // Tolerance: 1 % systematic (spectral upsampling and wavelength sampling differ
    // between the renderers) plus TQuantile standard errors of the difference; the
    // reference's own error is ours scaled by the path counts, √(512 / 16384).
    for (const Region& r : quadrants(ref.spec.width, ref.spec.height))
        for (int c = 0; c < 3; ++c) {
            SeededMean a = seededMean(pt, c, r);
            double b = 0;
            for (int y = r.y0; y < r.y1; ++y)
                for (int x = r.x0; x < r.x1; ++x) b += ref.at(x, y, c);
            b /= double(r.x1 - r.x0) * (r.y1 - r.y0);
            double se = a.stderr_ * std::sqrt(1.0 + 512.0 / 16384.0);
            INFO("region " << r.x0 << "," << r.y0 << " channel " << c << ": effigi " << a.mean << " ± " << a.stderr_
                           << ", mitsuba " << b);
            CHECK(std::abs(a.mean - b) < 0.01 * b + TQuantile * se);
            CHECK(se < 0.03 * b);
        }
}

TEST_CASE("ptracer: the Mitsuba corpus scene renders and agrees with Mitsuba 3", "[render][ptracer]") {
    const std::string CorpusScene = corpusScene();
    if (CorpusScene.empty() || !std::filesystem::exists(CorpusScene)) {
        return test::skipTest("EFFIGI_MITSUBA_CORPUS does not name a Mitsuba corpus checkout");
    }
    test::ExrImage ref =
        test::readExr(EFFIGI_SOURCE_DIR "/tests/data/ptracer/various_emitters-128x16-mitsuba.exr");
    xml::ParseOptions opt;
    opt.defines = {{"resx", "128"}, {"resy", "16"}, {"spp", "8"}};
    auto scene = loadSceneFile(CorpusScene, opt);
    std::vector<Image> renders;
    for (std::uint64_t seed = 1; seed <= 16; ++seed) renders.push_back(test::renderSeeded(*scene, seed * 104729));
    REQUIRE(renders[0].width == ref.spec.width);
    REQUIRE(renders[0].height == ref.spec.height);
    // Grey means of eight columns (each lit by a different emitter type) and the whole
    // image: 2 % systematic plus TQuantile standard errors of the difference (the
    // reference's error is ours scaled by √(16·8 / 8192)).
    std::vector<Region> regions;
    for (int i = 0; i < 8; ++i) regions.push_back({i * 16, 0, i * 16 + 16, 16});
    regions.push_back({0, 0, 128, 16});
    for (const Region& r : regions) {
        SeededMean a = seededMean(renders, 3, r);
        double b = 0;
        for (int y = r.y0; y < r.y1; ++y)
            for (int x = r.x0; x < r.x1; ++x) b += (ref.at(x, y, 0) + ref.at(x, y, 1) + ref.at(x, y, 2)) / 3.0;
        b /= double(r.x1 - r.x0) * (r.y1 - r.y0);
        double se = a.stderr_ * std::sqrt(1.0 + 128.0 / 8192.0);
        INFO("columns " << r.x0 << ".." << r.x1 << ": effigi " << a.mean << " ± " << a.stderr_ << ", mitsuba " << b);
        CHECK(std::abs(a.mean - b) < 0.02 * b + TQuantile * se);
        CHECK(se < 0.05 * b);
    }
}

TEST_CASE("ptracer: max_depth, hide_emitters and progressive passes", "[render][ptracer]") {
    const std::string tag = "<integer name=\"max_depth\" value=\"$max_depth\"/>";
    auto grey = [](const Image& img) { return regionMean(img, 3, 0, 0, img.width, img.height); };

    // max_depth 0: nothing at all.
    auto none = loadEdited(SceneFile, "", "", {{"max_depth", "0"}, {"spp", "4"}});
    CHECK(grey(test::renderSeeded(*none, 1)) == 0.0);
    // max_depth 1: only what is seen directly (the area light and the environment)...
    auto direct = loadEdited(SceneFile, "", "", {{"max_depth", "1"}, {"spp", "8"}});
    double visible = grey(test::renderSeeded(*direct, 1));
    CHECK(visible > 0.0);
    // ... which hide_emitters removes.
    auto hidden = loadEdited(SceneFile, tag, tag + "<boolean name=\"hide_emitters\" value=\"true\"/>",
                             {{"max_depth", "1"}, {"spp", "8"}});
    CHECK(grey(test::renderSeeded(*hidden, 1)) == 0.0);
    // Scattered light adds to it.
    auto full = loadEdited(SceneFile, "", "", {{"spp", "8"}});
    CHECK(grey(test::renderSeeded(*full, 1)) > visible);

    // Two progressive passes of 8 samples trace the same paths as one of 16: the same
    // image up to the order of floating-point sums.
    auto once = loadEdited(SceneFile, "", "", {{"spp", "16"}});
    Image a = test::renderSeeded(*once, 3);
    RenderControl control;
    control.progress = false;
    control.seed = 3;
    control.sampleCount = 8;
    once->renderer().render(*once, control);
    control.sampleOffset = 8;
    control.accumulate = true;
    once->renderer().render(*once, control);
    Image b = once->camera().film().develop();
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        CHECK(b.pixels[i] == Approx(a.pixels[i]).epsilon(1e-4).margin(1e-6));

    // samples_per_pass splits the work, not the result.
    auto passes = loadEdited(SceneFile, tag, tag + "<integer name=\"samples_per_pass\" value=\"4\"/>", {{"spp", "16"}});
    Image c = test::renderSeeded(*passes, 3);
    for (std::size_t i = 0; i < a.pixels.size(); ++i)
        CHECK(c.pixels[i] == Approx(a.pixels[i]).epsilon(1e-4).margin(1e-6));
}

TEST_CASE("ptracer: a crop window shows the same pixels as the full film", "[render][ptracer]") {
    // Light paths are keyed by full-film pixel and sample index, so a cropped film traces
    // the same paths (as many as the full film: Mitsuba's count) and its pixels match the
    // full render's, up to the order of floating-point sums (box filter: no spill-over).
    auto full = loadEdited(SceneFile, "", "", {{"spp", "8"}});
    Image a = test::renderSeeded(*full, 5);
    const std::string box = "<rfilter type=\"box\"/>";
    auto crop = loadEdited(SceneFile, box,
                           box + "<integer name=\"crop_offset_x\" value=\"8\"/><integer name=\"crop_offset_y\" "
                                 "value=\"12\"/><integer name=\"crop_width\" value=\"20\"/><integer "
                                 "name=\"crop_height\" value=\"10\"/>",
                           {{"spp", "8"}});
    Image b = test::renderSeeded(*crop, 5);
    REQUIRE(b.width == 20);
    REQUIRE(b.height == 10);
    double sum = 0;
    for (int y = 0; y < b.height; ++y)
        for (int x = 0; x < b.width; ++x)
            for (int c = 0; c < 3; ++c) {
                sum += b.at(x, y, c);
                CHECK(b.at(x, y, c) == Approx(a.at(x + 8, y + 12, c)).epsilon(1e-4).margin(1e-6));
            }
    CHECK(sum > 0.0);
}

TEST_CASE("ptracer: bad configurations are reported", "[render][ptracer]") {
    const std::string tag = "<integer name=\"max_depth\" value=\"$max_depth\"/>";
    // samples_per_pass must divide the sample count (Mitsuba's rule).
    auto bad = loadEdited(SceneFile, tag, tag + "<integer name=\"samples_per_pass\" value=\"5\"/>", {{"spp", "16"}});
    RenderControl control;
    control.progress = false;
    CHECK_THROWS_WITH(bad->renderer().render(*bad, control), Catch::Contains("samples_per_pass"));
    CHECK_THROWS_AS(loadEdited(SceneFile, tag, tag + "<integer name=\"samples_per_pass\" value=\"0\"/>"), Error);
    CHECK_THROWS_AS(loadEdited(SceneFile, tag, "<integer name=\"max_depth\" value=\"-2\"/>"), Error);
    CHECK_THROWS_AS(loadEdited(SceneFile, tag, tag + "<integer name=\"rr_depth\" value=\"0\"/>"), Error);
    // Every camera component implements ICameraImportance now (the error for one that
    // does not stays in ptracer); orthographic, once refused, renders
    // (tests/test_camera_importance.cpp checks it against path).
    auto ortho = loadEdited(SceneFile, "<sensor type=\"perspective\">\n        <float name=\"fov\" value=\"45\"/>",
                            "<sensor type=\"orthographic\">", {{"spp", "4"}});
    CHECK_NOTHROW(ortho->renderer().render(*ortho, control));
}
