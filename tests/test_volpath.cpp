// volpath (issue 15): homogeneous media in the Cornell box against Mitsuba 3 (isotropic,
// Henyey–Greenstein g = 0.7, chromatic σt), the white furnace (an albedo-1 medium in a
// uniform environment gives back exactly the environment), attenuation seen from a
// camera inside an absorbing medium against exp(−σt d), volpath = path without media,
// and the renderers that cannot render media saying so.
#include "app_runner.hpp"
#include "cornell_regions.hpp"
#include "reference_regions.hpp"
#include "scene_text.hpp"
#include "skip.hpp"

#include "effigi/core/error.hpp"
#include "effigi/xml/parser.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>

using namespace effigi;
using namespace effigi::test;

namespace {

/// The scene text rendered with `seed`; the developed image.
Image renderText(const std::string& xml, std::uint64_t seed = 0, std::vector<float>* variance = nullptr) {
    auto scene = loadScene(*xml::parseString(xml, "volpath-test.xml", {}));
    RenderStats stats;
    Image img = renderSeeded(*scene, seed, &stats);
    CHECK(stats.rejectedSamples == 0);
    if (variance) REQUIRE(scene->renderer().varianceEstimate(*variance));
    return img;
}

/// A scene: `renderer`, a camera at z = 4 looking at the origin (fov, res, spp), and `body`.
std::string sceneXml(const std::string& renderer, const std::string& body, int res, int spp, float fov = 30.f,
                     const std::string& cameraExtra = "") {
    return R"(<scene version="3.0.0">)" + renderer + R"(
    <sensor type="perspective"><float name="fov" value=")" + std::to_string(fov) + R"("/>
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value=")" + std::to_string(spp) + R"("/></sampler>
        <film type="hdrfilm"><integer name="width" value=")" + std::to_string(res) + R"("/>
            <integer name="height" value=")" + std::to_string(res) + R"("/><rfilter type="box"/></film>)" +
           cameraExtra + R"(
    </sensor>)" + body + "</scene>";
}

const std::vector<Region> kMediumRegions = {{"image", 0.f, 0.f, 1.f, 1.f},
                                            {"medium", .36f, .58f, .64f, .84f},
                                            {"back wall above", .35f, .2f, .65f, .45f},
                                            {"red wall", 0.f, .2f, .12f, .8f},
                                            {"green wall", .88f, .2f, 1.f, .8f},
                                            {"floor", .2f, .9f, .8f, 1.f}};

} // namespace

TEST_CASE("volpath: a homogeneous medium in the Cornell box agrees with Mitsuba 3", "[volpath][render]") {
    // References: Mitsuba 3.9.1 scalar_spectral volpath, 4096 spp (commands in the scene
    // files). Per region and channel |effigi − Mitsuba| / Mitsuba < 2 % + 4 standard errors
    // of effigi's estimate (two-sided false alarm 6e-5 per comparison; seeded, so the
    // outcome is deterministic); the reference's own noise at 4096 spp is ≈ 4× smaller.
    for (const char* name : {"medium-isotropic", "medium-hg", "medium-chromatic"}) {
        INFO(name);
        compareWithReference(std::string("tests/data/media/") + name + ".xml",
                             std::string("tests/data/media/") + name + "-mitsuba.exr", {{"spp", "256"}},
                             kMediumRegions, 0.02);
    }
}

TEST_CASE("volpath: Mitsuba's participating-media test scenes agree with their references", "[volpath][render]") {
    // The homogeneous-medium scenes of the public Mitsuba corpus (tests/scenes/
    // participating_media: null, thin-dielectric and dielectric boundaries, media around
    // and inside emitters, spectral σt, a spot light behind a rough dielectric), against
    // the references shipped with them (Mitsuba 2.2.1, spectral variant). Runs where
    // EFFIGI_MITSUBA_CORPUS names a checkout of the corpus (bench/mitsuba_corpus.py's DIR).
    // Per channel, image mean within 2 % + 4 standard errors (false alarm 6e-5 each).
    const char* dir = std::getenv("EFFIGI_MITSUBA_CORPUS");
    const std::filesystem::path base = dir ? std::filesystem::path(dir) / "tests/scenes/participating_media" : "";
    if (!dir || !std::filesystem::exists(base)) return skipTest("EFFIGI_MITSUBA_CORPUS does not name a Mitsuba corpus checkout");
    for (const char* name : {"homo_area_light", "homo_dielectric_envmap", "homo_emitter_inside_medium", "homo_null_envmap",
                             "homo_obj_inside_medium", "homo_roughdielectric_spot", "surf_area_light"}) {
        INFO(name);
        compareWithReference((base / (std::string("test_") + name + "_volpath.xml")).string(),
                             (base / "refs" / (std::string("test_") + name + "_ref_spectral.exr")).string(),
                             {{"spp", "256"}}, {{"image", 0.f, 0.f, 1.f, 1.f}}, 0.02);
    }
    compareWithReference((base / "test_homo_spectral_sigmat_volpathmis.xml").string(),
                         (base / "refs/test_homo_spectral_sigmat_ref_spectral.exr").string(), {{"spp", "256"}},
                         {{"image", 0.f, 0.f, 1.f, 1.f}}, 0.02);
}

TEST_CASE("volpath: white furnace, an albedo-1 medium in a uniform environment is invisible", "[volpath][render]") {
    // Every path that scatters only in the medium (albedo 1, grey σt) keeps throughput 1
    // and ends in the environment: without light sampling from the medium and without
    // Russian roulette (rr_depth 1000) each sample returns exactly the environment's
    // radiance, so the image equals the empty scene's, sample for sample (same seed, same
    // wavelengths).
    const std::string env = R"(<emitter type="constant"><rgb name="radiance" value="0.7, 0.5, 0.3"/></emitter>)";
    const std::string renderer = R"(<integrator type="volpath"><integer name="rr_depth" value="1000"/></integrator>)";
    auto sphere = [](const std::string& medium) {
        return R"(<shape type="sphere"><float name="radius" value="1"/><bsdf type="null"/>)" + medium + "</shape>";
    };
    const Image empty = renderText(sceneXml(renderer, env, 16, 8), 3);
    const Image exact = renderText(sceneXml(renderer, env + sphere(R"(<medium type="homogeneous" name="interior">
        <float name="sigma_t" value="3"/><float name="albedo" value="1"/>
        <boolean name="sample_emitters" value="false"/><phase type="hg"><float name="g" value="0.5"/></phase></medium>)"),
                                              16, 8),
                                    3);
    for (std::size_t i = 0; i < empty.pixels.size(); ++i) CHECK(exact.pixels[i] == Approx(empty.pixels[i]).epsilon(1e-4));

    // With light sampling (MIS) and a chromatic σt the estimate is noisy but unbiased:
    // the image mean within 4 standard errors (from the per-pixel variances) of the
    // environment's (two-sided false alarm 6e-5).
    std::vector<float> var;
    const Image noisy = renderText(sceneXml(R"(<integrator type="volpath"/>)", env + sphere(R"(
        <medium type="homogeneous" name="interior"><rgb name="sigma_t" value="0.2, 0.5, 1"/>
            <float name="scale" value="4"/><float name="albedo" value="1"/></medium>)"),
                                            16, 64),
                                   5, &var);
    const Image envOnly = renderText(sceneXml(renderer, env, 16, 64), 5);
    for (int c = 0; c < 3; ++c) {
        double sum = 0, ref = 0, v = 0;
        const std::size_t n = std::size_t(noisy.width) * noisy.height;
        for (std::size_t i = 0; i < n; ++i) sum += noisy.pixels[3 * i + c], ref += envOnly.pixels[3 * i + c], v += var[3 * i + c];
        const double se = std::sqrt(v) / double(n);
        INFO("channel " << c << ": " << sum / n << " ± " << se << " against " << ref / n);
        CHECK(std::abs(sum / n - ref / n) < 4.0 * se + 1e-4 * ref / n);
    }
}

TEST_CASE("volpath: a camera inside an absorbing medium sees exp(-sigma_t d)", "[volpath][render]") {
    // A light facing the camera 2 units away, seen through a purely absorbing grey medium
    // of σt = 0.5 around the camera: every pixel of a 4° field of view sees
    // Le·exp(−σt·d) with d = 2/cos θ ≤ 2.0012. Delta tracking gives each sample 0 or
    // Le: the image over the light's is a binomial proportion, checked against
    // exp(−1.0003) within 4 standard errors √(p(1−p)/n) (false alarm 6e-5).
    const std::string light = R"(<shape type="rectangle"><transform name="to_world">
        <scale value="2"/><translate value="0, 0, 2"/></transform>
        <emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>)";
    const std::string renderer = R"(<integrator type="volpath"><integer name="max_depth" value="1"/></integrator>)";
    const std::string medium = R"(<medium type="homogeneous"><float name="sigma_t" value="0.5"/>
        <float name="albedo" value="0"/></medium>)";
    // The camera of sceneXml sits at z = 4 looking at −z; the light at z = 2 faces it (+z).
    const int res = 16, spp = 256;
    const Image clear = renderText(sceneXml(renderer, light, res, spp, 4.f), 9);
    const Image foggy = renderText(sceneXml(renderer, light, res, spp, 4.f, medium), 9);
    double a = 0, b = 0;
    for (std::size_t i = 0; i < clear.pixels.size(); ++i) a += foggy.pixels[i], b += clear.pixels[i];
    REQUIRE(b > 0.0);
    const double p = std::exp(-0.5 * 2.0006), n = double(res) * res * spp;
    INFO("transmittance " << a / b << ", expected " << p);
    CHECK(std::abs(a / b - p) < 4.0 * std::sqrt(p * (1 - p) / n));
}

TEST_CASE("volpath: a glowing absorbing medium shows Le (1 - exp(-sigma_a d))", "[volpath][render]") {
    // An emitting, purely absorbing cube (side 2, face towards the camera) seen head-on
    // through a 4° field of view: each camera ray crosses d = 2 (to 0.1 % at the border),
    // and the radiance is Le·(1 − exp(−σa d)) in expectation. Against the same emission
    // spectrum seen on an area light (same seed, same wavelengths): the ratio of the image
    // sums, within 4 standard errors of the per-pixel estimates (false alarm 6e-5).
    const std::string renderer = R"(<integrator type="volpath"/>)";
    const std::string cube = R"(<shape type="cube"><bsdf type="null"/>
        <medium type="homogeneous" name="interior"><float name="sigma_t" value="0.4"/><float name="albedo" value="0"/>
            <rgb name="emission" value="2, 1, 0.5"/></medium></shape>)";
    const std::string light = R"(<shape type="rectangle"><transform name="to_world"><translate value="0, 0, 1"/></transform>
        <emitter type="area"><rgb name="radiance" value="2, 1, 0.5"/></emitter></shape>)";
    std::vector<float> var;
    const Image glow = renderText(sceneXml(renderer, cube, 16, 256, 4.f), 11, &var);
    const Image plain = renderText(sceneXml(renderer, light, 16, 256, 4.f), 11);
    const double expected = 1.0 - std::exp(-0.4 * 2.0);
    for (int c = 0; c < 3; ++c) {
        double a = 0, b = 0, v = 0;
        for (std::size_t i = 0; i < std::size_t(glow.width) * glow.height; ++i)
            a += glow.pixels[3 * i + c], b += plain.pixels[3 * i + c], v += var[3 * i + c];
        REQUIRE(b > 0.0);
        INFO("channel " << c << ": ratio " << a / b << ", expected " << expected);
        CHECK(std::abs(a / b - expected) < 4.0 * std::sqrt(v) / b + 2e-3 * expected);
    }
}

TEST_CASE("volpath: without media it renders what path renders", "[volpath][render]") {
    // Cornell box at 32², 256 spp each: image and region means within 2 % (at this spp
    // the regions' relative standard error is below 0.5 %).
    const std::string file = EFFIGI_SOURCE_DIR "/scenes/cornell-box/scene.xml";
    auto render = [&](const std::string& integrator) {
        auto s = loadWithIntegrator(file, integrator, {{"res", "32"}, {"spp", "256"}});
        return renderSeeded(*s, 0);
    };
    const Image vol = render(R"(<integrator type="volpath"><integer name="max_depth" value="8"/></integrator>)");
    const Image path = render(R"(<integrator type="path"><integer name="max_depth" value="8"/></integrator>)");
    for (const CornellRegion& r : cornellRegions()) {
        INFO(r.name);
        CHECK(regionMean(vol, r) == Approx(regionMean(path, r)).epsilon(0.02));
    }
}

TEST_CASE("volpath: renderers without media support refuse such scenes in one line", "[volpath][xml]") {
    const std::string body = R"(<shape type="sphere"><bsdf type="null"/>
        <medium type="homogeneous" name="interior"/></shape>)";
    for (const char* r : {"bdpt", "ptracer", "photonmap", "whitted"}) {
        INFO(r);
        const std::string xml = sceneXml(std::string("<integrator type=\"") + r + "\"/>", body, 4, 1);
        try {
            loadScene(*xml::parseString(xml, "media.xml", {}));
            FAIL("loaded");
        } catch (const Error& e) {
            CHECK_THAT(e.what(), Catch::Contains("media.xml:1") && Catch::Contains("participating media") &&
                                     Catch::Contains("volpath"));
        }
    }
    // path ignores media as Mitsuba's does: it loads (and warns).
    CHECK_NOTHROW(loadScene(*xml::parseString(sceneXml("<integrator type=\"path\"/>", body, 4, 1), "media.xml", {})));
    CHECK_NOTHROW(loadScene(*xml::parseString(sceneXml("<integrator type=\"volpath\"/>", body, 4, 1), "media.xml", {})));
}
