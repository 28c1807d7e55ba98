// Renderers direct, moment and aov (with nested renderers): direct against path with
// max_depth = 2 and against Mitsuba 3's `direct`; moments against the nested renderer's
// image and the renderer's own variance estimate; aov's channel layout and values;
// the 2D and 1D stratification of the multijitter and orthogonal samplers.
// Reference image: python3 bench/mitsuba_reference.py tests/data/renderers/direct.xml
//                  tests/data/renderers/direct-mitsuba.exr --spp 1024   (Mitsuba 3.9.1,
// scalar_spectral). The test scene uses a box filter, so pixels are independent.
#include "image_helpers.hpp"
#include "scene_text.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/spectral/colorspace.hpp"
#include "effigi/xml/loader.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>

using namespace effigi;

namespace {

const std::string SceneFile = EFFIGI_SOURCE_DIR "/tests/data/renderers/direct.xml";

/// The test scene with its <integrator type="direct"/> replaced by `integrator`.
std::unique_ptr<Scene> loadWith(const std::string& integrator, std::map<std::string, std::string> defines = {}) {
    return test::loadEdited(SceneFile, {{"<integrator type=\"direct\"/>", integrator}}, std::move(defines));
}

struct Rendered {
    Image image;
    std::vector<float> variance;  // per pixel R, G, B: variance of the pixel value
    RenderStats stats;
};

Rendered render(Scene& scene, std::uint64_t seed) {
    RenderControl control;
    control.progress = false;
    control.seed = seed;
    Rendered r;
    r.stats = scene.renderer().render(scene, control);
    r.image = scene.camera().film().develop();
    scene.renderer().varianceEstimate(r.variance);
    return r;
}

int channel(const Image& img, const std::string& name) {
    auto it = std::find(img.channelNames.begin(), img.channelNames.end(), name);
    INFO("channel " << name);
    REQUIRE(it != img.channelNames.end());
    return int(it - img.channelNames.begin());
}

/// Mean of channel c over a quadrant (q = 0..3) or the whole image (q = 4), and the
/// standard error of that mean from the renderer's per-pixel variance (independent pixels).
std::pair<double, double> regionMean(const Rendered& r, int c, int q) {
    const Image& img = r.image;
    int w = img.width, h = img.height;
    int x0 = q == 4 ? 0 : (q % 2) * w / 2, y0 = q == 4 ? 0 : (q / 2) * h / 2;
    int x1 = q == 4 ? w : x0 + w / 2, y1 = q == 4 ? h : y0 + h / 2;
    double sum = 0, var = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            sum += img.at(x, y, c);
            if (!r.variance.empty()) var += r.variance[(std::size_t(y) * w + x) * 3 + c];
        }
    double n = double(x1 - x0) * (y1 - y0);
    return {sum / n, std::sqrt(var) / n};
}

/// Two independent renders agree in every quadrant and channel within 4.5 standard
/// errors of the difference (two-sided false alarm 7e-6 per check, 15 checks; seeded).
void checkAgree(const Rendered& a, const Rendered& b, double sharpness = 0.02) {
    for (int q = 0; q < 5; ++q)
        for (int c = 0; c < 3; ++c) {
            auto [ma, sa] = regionMean(a, c, q);
            auto [mb, sb] = regionMean(b, c, q);
            double se = std::sqrt(sa * sa + sb * sb);
            INFO("region " << q << " channel " << c << ": " << ma << " ± " << sa << " vs " << mb << " ± " << sb);
            REQUIRE(se > 0.0);
            CHECK(std::abs(ma - mb) < 4.5 * se);
            CHECK(se < sharpness * std::max(ma, mb));  // sharp enough to see a missing light
        }
}

} // namespace

TEST_CASE("direct: equals path with max_depth 2", "[renderer][direct]") {
    auto direct = loadWith("<integrator type=\"direct\"/>", {{"spp", "32"}});
    auto path = loadWith("<integrator type=\"path\"><integer name=\"max_depth\" value=\"2\"/></integrator>",
                         {{"spp", "32"}});
    Rendered a = render(*direct, 1), b = render(*path, 2);
    CHECK(a.stats.rejectedSamples == 0);
    CHECK(a.stats.samples == 48u * 48u * 32u);
    checkAgree(a, b);
}

TEST_CASE("direct: emitter-only, BSDF-only and several shading samples agree", "[renderer][direct]") {
    // Without delta lights or mirrors both techniques see every light (MIS then only
    // changes the noise, not the mean).
    std::map<std::string, std::string> smooth{{"spp", "64"}, {"point", "0, 0, 0"}, {"mirror", "roughconductor"}};
    Rendered ref = render(*loadWith("<integrator type=\"direct\"/>", smooth), 3);
    for (const char* variant : {"<integer name=\"emitter_samples\" value=\"0\"/>",
                                "<integer name=\"bsdf_samples\" value=\"0\"/>",
                                "<integer name=\"shading_samples\" value=\"3\"/>",
                                "<integer name=\"emitter_samples\" value=\"2\"/><integer name=\"bsdf_samples\" "
                                "value=\"1\"/>"}) {
        INFO(variant);
        auto scene = loadWith(std::string("<integrator type=\"direct\">") + variant + "</integrator>", smooth);
        checkAgree(render(*scene, 4), ref, 0.04);  // one technique alone is noisy
    }
}

TEST_CASE("direct: bad parameters are located errors", "[renderer][direct]") {
    CHECK_THROWS_WITH(loadWith("<integrator type=\"direct\"><integer name=\"shading_samples\" value=\"2\"/>"
                               "<integer name=\"bsdf_samples\" value=\"1\"/></integrator>"),
                      Catch::Contains("direct.xml:") && Catch::Contains("shading_samples"));
    CHECK_THROWS_WITH(loadWith("<integrator type=\"direct\"><integer name=\"shading_samples\" value=\"0\"/>"
                               "</integrator>"),
                      Catch::Contains("at least one"));
    CHECK_THROWS_WITH(loadWith("<integrator type=\"direct\"><integer name=\"bsdf_samples\" value=\"-1\"/>"
                               "</integrator>"),
                      Catch::Contains("bsdf_samples"));
}

TEST_CASE("direct: hide_emitters hides the environment seen by the camera", "[renderer][direct]") {
    Rendered shown = render(*loadWith("<integrator type=\"direct\"/>", {{"spp", "4"}}), 5);
    Rendered hidden = render(
        *loadWith("<integrator type=\"direct\"><boolean name=\"hide_emitters\" value=\"true\"/></integrator>",
                  {{"spp", "4"}}),
        5);
    // The top row sees only the sky; row 40 only the floor, lit as before (same samples).
    for (int c = 0; c < 3; ++c) {
        CHECK(shown.image.at(24, 0, c) > 0.1f);
        CHECK(hidden.image.at(24, 0, c) == 0.f);
        CHECK(hidden.image.at(24, 40, c) == Approx(shown.image.at(24, 40, c)).epsilon(1e-5));
    }
}

TEST_CASE("direct: agrees with Mitsuba 3's direct", "[renderer][direct][mitsuba]") {
    auto scene = loadWith("<integrator type=\"direct\"/>", {{"spp", "64"}});
    Rendered ours = render(*scene, 6);
    test::ExrImage ref = test::readExr(EFFIGI_SOURCE_DIR "/tests/data/renderers/direct-mitsuba.exr");
    REQUIRE(ref.spec.width == ours.image.width);
    REQUIRE(ref.spec.height == ours.image.height);
    // Tolerance: 2 % systematic (RGB upsampling and the metals' spectral data differ
    // between the renderers) plus 4 standard errors of our 64-spp estimate (two-sided
    // false alarm 6e-5 per check, seeded); the 1024-spp reference's noise is negligible.
    for (int q = 0; q < 5; ++q)
        for (int c = 0; c < 3; ++c) {
            auto [m, se] = regionMean(ours, c, q);
            const Image& img = ours.image;
            int w = img.width, h = img.height;
            int x0 = q == 4 ? 0 : (q % 2) * w / 2, y0 = q == 4 ? 0 : (q / 2) * h / 2;
            int x1 = q == 4 ? w : x0 + w / 2, y1 = q == 4 ? h : y0 + h / 2;
            double sum = 0;
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) sum += ref.at(x, y, c);
            double mref = sum / (double(x1 - x0) * (y1 - y0));
            INFO("region " << q << " channel " << c << ": effigi " << m << " ± " << se << ", mitsuba " << mref);
            CHECK(std::abs(m - mref) < 0.02 * mref + 4.0 * se);
        }
}

TEST_CASE("moment: first moment is the nested renderer's image, second moment bounds it", "[renderer][moment]") {
    Rendered alone = render(*loadWith("<integrator type=\"direct\"/>", {{"spp", "8"}}), 7);
    // Mitsuba's spelling: a nested <integrator> that names a renderer is one.
    auto scene = loadWith("<integrator type=\"moment\"><integrator type=\"direct\"/>"
                          "<renderer type=\"direct\" name=\"two\"><integer name=\"bsdf_samples\" value=\"0\"/>"
                          "</renderer></integrator>",
                          {{"spp", "8"}});
    Rendered m = render(*scene, 7);
    const Image& img = m.image;
    std::vector<std::string> expected{"R",       "G",        "B",        "_arg_0.X",  "_arg_0.Y",      "_arg_0.Z",
                                      "two.X",   "two.Y",    "two.Z",    "m2__arg_0.X", "m2__arg_0.Y", "m2__arg_0.Z",
                                      "m2_two.X", "m2_two.Y", "m2_two.Z"};
    CHECK(img.channelNames == expected);
    int x1 = channel(img, "_arg_0.X"), x2 = channel(img, "m2__arg_0.X");
    std::size_t darker = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            // The same seed draws the same samples: the colour image is the nested one's.
            for (int c = 0; c < 3; ++c) CHECK(img.at(x, y, c) == Approx(alone.image.at(x, y, c)).margin(1e-5));
            Vector3f xyz = linearSRGBToXYZ(Vector3f(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)));
            for (int c = 0; c < 3; ++c) {
                float m1 = img.at(x, y, x1 + c), m2 = img.at(x, y, x2 + c);
                CHECK(m1 == Approx(xyz[c]).margin(1e-4).epsilon(1e-3));
                CHECK(m2 >= m1 * m1 * (1.f - 1e-4f) - 1e-9f);  // float rounding of equal samples
            }
            // Without BSDF samples the mirror sphere and the sky reflected in it go dark.
            darker += img.at(x, y, channel(img, "two.Y")) < img.at(x, y, x1 + 1) - 1e-3f;
        }
    CHECK(darker > 20);
}

TEST_CASE("moment: variance from moments matches the renderer's variance estimate", "[renderer][moment]") {
    // moment(aov(direct)): the aov wrapper writes each sample's linear sRGB as img.R/G/B,
    // the quantity whose variance the integrator estimates. Box filter: a pixel's value is
    // the plain mean of its n samples, so Var(mean) = (m2 − m1²) · n / (n − 1) / n.
    const int n = 16;
    auto scene = loadWith("<integrator type=\"moment\"><renderer type=\"aov\" name=\"a\">"
                          "<string name=\"aovs\" value=\"dd.y:depth\"/><renderer type=\"direct\" name=\"img\"/>"
                          "</renderer></integrator>",
                          {{"spp", std::to_string(n)}});
    Rendered r = render(*scene, 8);
    REQUIRE(r.variance.size() == std::size_t(48 * 48 * 3));
    int m1 = channel(r.image, "a.img.R"), m2 = channel(r.image, "m2_a.img.R");
    CHECK(channel(r.image, "a.dd.y.T") < m2);
    double sumMoments = 0, sumEstimate = 0;
    for (int y = 0; y < 48; ++y)
        for (int x = 0; x < 48; ++x)
            for (int c = 0; c < 3; ++c) {
                double a = r.image.at(x, y, m1 + c), b = r.image.at(x, y, m2 + c);
                double fromMoments = std::max(0.0, b - a * a) / (n - 1);
                double estimate = r.variance[(std::size_t(y) * 48 + x) * 3 + c];
                CHECK(fromMoments == Approx(estimate).margin(1e-6).epsilon(0.01));
                sumMoments += fromMoments, sumEstimate += estimate;
            }
    CHECK(sumEstimate > 0.0);
    CHECK(sumMoments == Approx(sumEstimate).epsilon(0.001));
}

TEST_CASE("aov: nested renderer first, then Mitsuba-named AOVs", "[renderer][aov]") {
    Rendered alone = render(*loadWith("<integrator type=\"direct\"/>", {{"spp", "4"}}), 9);
    auto scene = loadWith("<integrator type=\"aov\"><string name=\"aovs\" value=\"dd.y:depth, nn:sh_normal, "
                          "p:position, t:uv, i:prim_index\"/><renderer type=\"direct\" name=\"image\"/></integrator>",
                          {{"spp", "4"}});
    Rendered r = render(*scene, 9);
    const Image& img = r.image;
    std::vector<std::string> expected{"R",    "G",    "B",    "image.R", "image.G", "image.B", "image.A", "dd.y.T",
                                      "nn.X", "nn.Y", "nn.Z", "p.X",     "p.Y",     "p.Z",     "t.U",     "t.V",
                                      "i.I"};
    CHECK(img.channelNames == expected);
    for (int y = 0; y < 48; y += 7)
        for (int x = 0; x < 48; x += 5) {
            for (int c = 0; c < 3; ++c) {
                CHECK(img.at(x, y, c) == Approx(alone.image.at(x, y, c)).margin(1e-5));
                CHECK(img.at(x, y, 3 + c) == Approx(img.at(x, y, c)).margin(1e-4).epsilon(1e-3));
            }
            CHECK(img.at(x, y, 6) == Approx(1.f));  // the environment is everywhere
        }
    // Pixel (24, 40) sees only the floor: depth = distance to the camera at (0, 2, 6), normal +y.
    float px = img.at(24, 40, 11), py = img.at(24, 40, 12), pz = img.at(24, 40, 13);
    CHECK(py == Approx(0.f).margin(1e-4));
    CHECK(img.at(24, 40, 7) == Approx(std::sqrt(px * px + (py - 2) * (py - 2) + (pz - 6) * (pz - 6))).epsilon(0.02));
    CHECK(img.at(24, 40, 9) == Approx(1.f).margin(1e-4));
    // The top row sees only the sky: no AOVs there.
    CHECK(img.at(24, 0, 7) == 0.f);
    CHECK(img.at(24, 0, 9) == 0.f);
}

TEST_CASE("nesting: errors name the wrapper and the child", "[renderer][moment][aov]") {
    CHECK_THROWS_WITH(loadWith("<integrator type=\"moment\"><renderer type=\"radiosity\"/></integrator>"),
                      Catch::Contains("moment") && Catch::Contains("radiosity") && Catch::Contains("direct.xml:"));
    CHECK_THROWS_WITH(loadWith("<integrator type=\"moment\"/>"), Catch::Contains("at least one"));
    CHECK_THROWS_WITH(loadWith("<integrator type=\"aov\"><string name=\"aovs\" value=\"x:duv_dx\"/></integrator>"),
                      Catch::Contains("duv_dx") && Catch::Contains("direct.xml:"));
    CHECK_THROWS_WITH(loadWith("<integrator type=\"aov\"><string name=\"aovs\" value=\"x\"/></integrator>"),
                      Catch::Contains("name:type"));
    CHECK_THROWS_WITH(loadWith("<integrator type=\"moment\"><integrator type=\"nope\"/></integrator>"),
                      Catch::Contains("nope") && Catch::Contains("moment"));
}

namespace {

Ref<ISampler> makeSampler(const std::string& type, std::int64_t count, std::int64_t strength = 0) {
    Properties p("sampler", type);
    p.set("sample_count", count);
    if (strength) p.set("strength", strength);
    Ref<ISampler> s = query<ISampler>(Registry::instance().create("sampler", type, p));
    REQUIRE(s);
    return s;
}

/// Whether `cells` holds every index 0..n−1 exactly once.
bool onePerCell(std::vector<int> cells, int n) {
    std::sort(cells.begin(), cells.end());
    for (int i = 0; i < n; ++i)
        if (int(cells.size()) != n || cells[std::size_t(i)] != i) return false;
    return true;
}

/// For `pixels` pixels and the first four 2D dimensions: one point per cell of the
/// cols × rows grid, and each coordinate a Latin hypercube of n strata.
void checkStratified2D(ISampler& s, int cols, int rows, int pixels) {
    const int n = s.samplesPerPixel();
    REQUIRE(n == cols * rows);
    for (int p = 0; p < pixels; ++p) {
        s.startPixel(Point2i(p, 3 * p - 7));
        std::vector<std::vector<Point2f>> pts(4);
        for (int i = 0; i < n; ++i) {
            s.startSample(std::uint64_t(i));
            for (auto& d : pts) d.push_back(s.get2D());
        }
        for (const auto& d : pts) {
            std::vector<int> cell, xs, ys;
            for (Point2f q : d) {
                cell.push_back(int(q.y * float(rows)) * cols + int(q.x * float(cols)));
                xs.push_back(int(q.x * float(n)));
                ys.push_back(int(q.y * float(n)));
            }
            CHECK(onePerCell(cell, n));
            CHECK(onePerCell(xs, n));
            CHECK(onePerCell(ys, n));
        }
    }
}

} // namespace

TEST_CASE("multijitter: 2D cells and both 1D projections stratified, non-square counts", "[sampler][multijitter]") {
    Ref<ISampler> s = makeSampler("multijitter", 12);  // 4 columns × 3 rows
    checkStratified2D(*s, 4, 3, 6);
    CHECK(makeSampler("multijitter", 10)->samplesPerPixel() == 12);  // rounded up, as Mitsuba does
}

TEST_CASE("orthogonal: every pair of consecutive dimensions is a p x p jittered grid", "[sampler][orthogonal]") {
    checkStratified2D(*makeSampler("orthogonal", 25), 5, 5, 6);
    checkStratified2D(*makeSampler("orthogonal", 49), 7, 7, 2);
    // Strength 3 (p = 3, n = 27): any three 1D dimensions hold every 3 × 3 × 3 cell once.
    Ref<ISampler> s = makeSampler("orthogonal", 27, 3);
    REQUIRE(s->samplesPerPixel() == 27);
    s->startPixel(Point2i(4, 5));
    std::vector<int> cells;
    for (int i = 0; i < 27; ++i) {
        s->startSample(std::uint64_t(i));
        float a = s->get1D(), b = s->get1D(), c = s->get1D();
        cells.push_back(int(a * 3) * 9 + int(b * 3) * 3 + int(c * 3));
    }
    CHECK(onePerCell(cells, 27));
    CHECK(makeSampler("orthogonal", 30)->samplesPerPixel() == 49);  // next prime squared
}
