// Renderer photonmap (components/renderer/photonmap.cpp), its photon tracing
// (photon_map.hpp) and the `lighttracer` alias of ptracer (the same light-path walk).
// - The Cornell box agrees with Mitsuba 3's 2048-spp path-traced reference
//   (tests/data/cornell, which effigi's path matches within 0.2 % per wall), region by
//   region: photon mapping is biased (density estimation blurs light over the lookup
//   radius) and the renders are small, so the tolerances are the measured bias plus
//   noise, stated at each check.
// - The caustic map fills for a glass sphere and stays empty without delta surfaces; the
//   photons of a seed are the same whatever the thread count.
// - Bad parameters are one-line errors naming file:line; extreme parameters render
//   finite images.
#include "cornell_regions.hpp"
#include "scene_text.hpp"
#include "xml_helpers.hpp"

#include "../components/renderer/photon_map.hpp"

#include "effigi/interfaces/ifilm.hpp"
#include "effigi/xml/loader.hpp"

#include <OpenImageIO/imageio.h>
#include <catch2/catch.hpp>
#include <tbb/global_control.h>

#include <fstream>
#include <sstream>

using namespace effigi;
using namespace effigi::test;

namespace {

const std::string Cornell = EFFIGI_SOURCE_DIR "/scenes/cornell-box/scene.xml";

/// The Cornell box with its integrator replaced by `integrator` (XML) and `extra`
/// inserted before the geometry.
std::unique_ptr<Scene> cornell(const std::string& integrator, std::map<std::string, std::string> defines,
                               const std::string& extra = "") {
    return loadWithIntegrator(Cornell, integrator, std::move(defines),
                              extra.empty() ? TextEdits{} : TextEdits{{"<include", extra + "<include"}});
}

std::string photonmap(const std::string& params) {
    return "<integrator type=\"photonmap\"><integer name=\"max_depth\" value=\"$max_depth\"/>" + params +
           "</integrator>";
}

const std::string GlassSphere = R"(<shape type="sphere"><point name="center" x="0" y="-0.3" z="0.3"/>
    <float name="radius" value="0.3"/><bsdf type="dielectric"/></shape>)";

Image render(Scene& scene, std::uint64_t seed = 1) {
    RenderControl c;
    c.progress = false;
    c.seed = seed;
    RenderStats stats = scene.renderer().render(scene, c);
    CHECK(stats.rejectedSamples == 0);
    return scene.camera().film().develop();
}


} // namespace

TEST_CASE("photonmap: the Cornell box agrees with the path-traced reference", "[render][photonmap]") {
    // 64², 16 spp, the default 250k global photons, one gather ray per sample, seed 1.
    // Over seeds 1–6 (bench/RESULTS.md, "Photon mapping") the image mean was −1.0 …
    // −2.7 %, the ceiling (lit only indirectly, 128 px) −0.5 … −7.7 % and every other wall
    // −3.7 … +0.2 % off: the method's bias (negative, from the lookup disc reaching past
    // surface edges; −0.8 % / −3.3 % at 256², 64 spp) plus the noise of one photon map,
    // which is shared by all pixels. Tolerances: bias + ~3 seed-to-seed standard
    // deviations, 4 % for the image, 12 % for the ceiling, 6 % for the other walls.
    auto scene = cornell(photonmap(""), {{"res", "64"}, {"spp", "16"}});
    Image ours = render(*scene), ref = cornellReference(64);
    const std::vector<CornellRegion> regions = cornellRegions();
    CHECK(regions.size() >= 7);
    for (const CornellRegion& r : regions) {
        double a = regionMean(ours, r), b = regionMean(ref, r);
        INFO(r.name << ": photonmap " << a << ", reference " << b << ", relative " << (a - b) / b);
        CHECK(std::abs(a - b) <= (r.name == "image" ? 0.04 : r.name == "ceiling" ? 0.12 : 0.06) * b);
    }
    CHECK(allFinite(ours));
}

TEST_CASE("photonmap: caustic photons come from delta surfaces only", "[render][photonmap]") {
    RenderControl quiet;
    quiet.progress = false;
    const LightPathLimits limits{-1, 5};
    auto plain = cornell(photonmap(""), {{"res", "16"}, {"spp", "1"}});
    PhotonTraceResult none = tracePhotons(*plain, PhotonPass::Caustic, 2000, limits, 7, quiet);
    CHECK(none.photons.empty());
    CHECK(none.emittedPaths == 0);  // no surface has a delta lobe: nothing is traced
    // A delta surface the light cannot reach through one: paths are tried, none stored.
    auto hidden = cornell(photonmap(""), {{"res", "16"}, {"spp", "1"}},
                          R"(<shape type="sphere"><point name="center" x="0" y="0" z="-5"/><bsdf type="conductor"/></shape>)");
    PhotonTraceResult tried = tracePhotons(*hidden, PhotonPass::Caustic, 2000, limits, 7, quiet);
    CHECK(tried.photons.empty());
    CHECK(tried.emittedPaths >= 2000);  // it gave up after `target` paths stored nothing

    auto glass = cornell(photonmap(""), {{"res", "16"}, {"spp", "1"}}, GlassSphere);
    PhotonTraceResult caustic = tracePhotons(*glass, PhotonPass::Caustic, 2000, limits, 7, quiet);
    REQUIRE(caustic.photons.size() >= 2000);
    for (const Photon& p : caustic.photons) {
        CHECK(p.depth >= 2);
        CHECK(p.flags == PhotonCaustic);
        CHECK(p.power.isFinite());
    }
    // The global map holds direct photons (depth 1, not caustic) and caustic ones.
    PhotonTraceResult global = tracePhotons(*glass, PhotonPass::Global, 5000, limits, 7, quiet);
    std::size_t direct = 0, flagged = 0;
    for (const Photon& p : global.photons) {
        direct += p.depth == 1;
        flagged += (p.flags & PhotonCaustic) != 0;
        if (p.depth == 1) CHECK(p.flags == 0);
    }
    CHECK(direct > 0);
    CHECK(flagged > 0);

    // Deterministic for a seed, whatever the thread count.
    PhotonTraceResult again;
    {
        tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
        again = tracePhotons(*glass, PhotonPass::Caustic, 2000, limits, 7, quiet);
    }
    REQUIRE(again.photons.size() == caustic.photons.size());
    CHECK(again.emittedPaths == caustic.emittedPaths);
    for (std::size_t i = 0; i < again.photons.size(); ++i) {
        CHECK(again.photons[i].p == caustic.photons[i].p);
        CHECK(again.photons[i].power[0] == caustic.photons[i].power[0]);
    }
}

TEST_CASE("photonmap: a glass sphere's caustic renders finite and brighter than without it", "[render][photonmap]") {
    // The caustic under the sphere (floor, around x = 0, z = 0.3) is lit only through
    // the glass: with caustic_photons = 0 it is darker.
    const std::string p = "<integer name=\"global_photons\" value=\"20000\"/>";
    auto with = cornell(photonmap(p + "<integer name=\"caustic_photons\" value=\"50000\"/>"),
                        {{"res", "32"}, {"spp", "4"}}, GlassSphere);
    auto without = cornell(photonmap(p + "<integer name=\"caustic_photons\" value=\"0\"/>"),
                           {{"res", "32"}, {"spp", "4"}}, GlassSphere);
    Image a = render(*with), b = render(*without);
    CHECK(allFinite(a));
    double sa = 0, sb = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) sa += a.pixels[i], sb += b.pixels[i];
    CHECK(sa > sb);
}

TEST_CASE("photonmap: bad parameters are one-line errors", "[render][photonmap]") {
    const std::map<std::string, std::string> d{{"res", "8"}, {"spp", "1"}};
    for (std::string bad : {"<float name=\"spectral_bandwidth\" value=\"0\"/>",
                            "<float name=\"global_lookup_radius\" value=\"-1\"/>",
                            "<float name=\"caustic_lookup_radius\" value=\"0\"/>",
                            "<string name=\"kernel\" value=\"gauss\"/>",
                            "<string name=\"store\" value=\"nosuchstore\"/>",
                            "<integer name=\"lookup_size\" value=\"0\"/>",
                            "<integer name=\"global_photons\" value=\"-5\"/>"}) {
        std::string msg = errorOf([&] { cornell(photonmap(bad), d); });
        INFO(bad << " -> " << msg);
        CHECK(msg.find('\n') == std::string::npos);
        CHECK(msg.find("scene.xml:") != std::string::npos);
    }
}

TEST_CASE("photonmap: extreme parameters give finite images", "[render][photonmap]") {
    const std::map<std::string, std::string> d{{"res", "12"}, {"spp", "2"}};
    const std::string few = "<integer name=\"global_photons\" value=\"2000\"/>"
                            "<integer name=\"caustic_photons\" value=\"2000\"/>";
    for (std::string params : {std::string("<integer name=\"lookup_size\" value=\"1\"/>"),
                               std::string("<float name=\"global_lookup_radius\" value=\"1e-6\"/>"
                                           "<float name=\"caustic_lookup_radius\" value=\"1e-6\"/>"),
                               std::string("<float name=\"global_lookup_radius\" value=\"100\"/>"),
                               std::string("<float name=\"spectral_bandwidth\" value=\"0.001\"/>"),
                               std::string("<float name=\"spectral_bandwidth\" value=\"470\"/>"),
                               std::string("<boolean name=\"final_gather\" value=\"false\"/>"),
                               std::string("<string name=\"kernel\" value=\"cone\"/>"),
                               std::string("<integer name=\"rr_depth\" value=\"1\"/>")}) {
        auto scene = cornell(photonmap(few + params), d, GlassSphere);
        INFO(params);
        CHECK(allFinite(render(*scene)));
    }
    for (const char* depth : {"0", "1", "2", "3"}) {
        std::map<std::string, std::string> dd = d;
        dd["max_depth"] = depth;
        auto scene = cornell(photonmap(few), dd, GlassSphere);
        Image img = render(*scene);
        CHECK(allFinite(img));
        if (std::string(depth) == "0")
            for (float v : img.pixels) CHECK(v == 0.f);
    }
}

TEST_CASE("photonmap: Mitsuba 0.6's camelCase names load", "[render][photonmap]") {
    std::string text = readText(Cornell);
    text.replace(text.find("version=\"3.0.0\""), 15, "version=\"0.6.0\"");
    auto a = text.find("<integrator type=\"path\">"), b = text.find("</integrator>");
    text.replace(a, b + 13 - a,
                 "<integrator type=\"photonmap\"><integer name=\"globalPhotons\" value=\"2000\"/>"
                 "<integer name=\"causticPhotons\" value=\"100\"/><integer name=\"glossySamples\" value=\"2\"/>"
                 "<integer name=\"directSamples\" value=\"2\"/><integer name=\"lookupSize\" value=\"20\"/>"
                 "<float name=\"globalLookupRadius\" value=\"0.1\"/><integer name=\"granularity\" value=\"0\"/>"
                 "</integrator>");
    xml::ParseOptions opt;
    opt.defines = {{"res", "8"}, {"spp", "1"}};
    auto scene = loadScene(*xml::parseString(text, Cornell, opt));
    CHECK(scene->renderer().typeName() == "renderer/photonmap");
    CHECK(allFinite(render(*scene)));
}

TEST_CASE("lighttracer: read as ptracer", "[render][photonmap][ptracer]") {
    auto scene = cornell("<integrator type=\"lighttracer\"><integer name=\"max_depth\" value=\"3\"/></integrator>",
                         {{"res", "8"}, {"spp", "1"}});
    CHECK(scene->renderer().typeName() == "renderer/ptracer");
    CHECK(allFinite(render(*scene)));
}
