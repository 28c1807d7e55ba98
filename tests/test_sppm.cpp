// Renderer sppm (components/renderer/sppm.cpp, sppm_core.hpp): stochastic progressive
// photon mapping.
// - The progressive update (SppmPixel): the radius never grows and shrinks whenever
//   photons arrive, and the estimate of a uniform photon density is unbiased whatever
//   the radius does (z-test, seeded).
// - The Cornell box agrees with `path`: image and wall means (regions of
//   tests/data/cornell/regions.txt), tolerance = measured SPPM bias at this size + noise.
// - Energy: a closed diffuse enclosure (walls emit Le, reflect ρ = 0.5) shows Le/(1 − ρ).
// - Progressive: n iterations then n more (RenderControl::accumulate) give exactly the
//   image of 2n at once, and of `effigi render --spp 2n` (renderProgressive); the same
//   seed gives the same image, another seed another; max_passes; a stop request.
// - Dispersion: the caustic of a dispersive glass sphere (hero slot only on both sides)
//   is finite and as bright, channel by channel, as ptracer's.
// - Bad parameters are one-line errors naming file:line and the parameter.
#include "cornell_regions.hpp"
#include "scene_text.hpp"
#include "xml_helpers.hpp"

#include "../components/renderer/sppm_core.hpp"

#include "effigi/interfaces/ifilm.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/render/progressive.hpp"
#include "effigi/xml/loader.hpp"

#include <catch2/catch.hpp>

#include <atomic>
#include <fstream>
#include <sstream>

using namespace effigi;
using namespace effigi::test;

namespace {

/// Scene file `file` with its <integrator ...>...</integrator> replaced by `integrator`.
std::unique_ptr<Scene> withIntegrator(const std::string& file, const std::string& integrator,
                                      std::map<std::string, std::string> defines,
                                      std::pair<std::string, std::string> edit = {}) {
    return loadWithIntegrator(file, integrator, std::move(defines), edit.first.empty() ? TextEdits{} : TextEdits{edit});
}

const std::string Cornell = EFFIGI_SOURCE_DIR "/scenes/cornell-box/scene.xml";

std::string sppm(const std::string& params) {
    return R"(<integrator type="sppm"><integer name="max_depth" value="8"/>)" + params + "</integrator>";
}

} // namespace

TEST_CASE("sppm update: the radius only shrinks, and a uniform density is estimated without bias",
          "[sppm][render]") {
    // Photons of unit flux land as a Poisson process of density D per iteration; the
    // pixel sees Poisson(D π R²) of them. τ / (n π R²) is then Σ Φ_i / (π R_i²) / n, each
    // term of mean D whatever R_i was: the mean over 400 seeded pixels must be D within
    // 4 standard errors (two-sided 6e-5).
    PCG32 rng(7, 11);
    auto poisson = [&](double mean) {  // Knuth's product method; means here are < 30
        double l = std::exp(-mean), p = 1.0;
        int k = -1;
        do {
            ++k, p *= rng.nextDouble();
        } while (p > l);
        return k;
    };
    const double D = 40.0;
    double sum = 0, sum2 = 0;
    const int pixels = 400, iterations = 200;
    bool monotone = true;
    for (int i = 0; i < pixels; ++i) {
        SppmPixel px;
        px.radius = 0.4f;
        for (int k = 0; k < iterations; ++k) {
            const float before = px.radius;
            const int M = poisson(D * Pi * double(px.radius) * px.radius);
            px.update(float(M), Vector3f(float(M)), 0.7f);
            monotone = monotone && px.radius <= before && (M == 0 || px.radius < before) && px.radius > 0.f;
        }
        const double e = px.estimate(1, iterations, iterations * 1.0);  // Φp = 1, one "path" an iteration
        sum += e, sum2 += e * e;
    }
    CHECK(monotone);
    const double mean = sum / pixels, se = std::sqrt((sum2 / pixels - mean * mean) / (pixels - 1));
    INFO("estimated density " << mean << " ± " << se << ", true " << D);
    CHECK(std::abs(mean - D) < 4.0 * se);
    CHECK(se < 0.02 * D);  // sharp enough to see a 5 % error
}

TEST_CASE("sppm: the Cornell box agrees with path, image and walls", "[sppm][render]") {
    // 48² pixels, box filters (SPPM applies no film filter), 32 iterations of 20000 photon
    // paths (initial radius 0.04) against path at 256 spp. Measured over seeds 1–5: image
    // within ±1.7 %, walls ±0.8 % but the large box (−4.5 … +0.6 %) and the ceiling
    // (−3.4 … +2.5 %; at 48² its region lies within a few radii of the surface's front
    // edge, where the gather disc finds fewer photons). Tolerance (seed 1): image 3 %,
    // ceiling 10 %, other regions 6 %; a lost bounce of indirect light is > 15 %.
    const std::map<std::string, std::string> defines{{"res", "48"}, {"spp", "256"}};
    auto ref = withIntegrator(Cornell, R"(<integrator type="path"><integer name="max_depth" value="8"/></integrator>)",
                              defines, {"<rfilter type=\"gaussian\"/>", "<rfilter type=\"box\"/>"});
    Image a = renderSeeded(*ref, 1);
    auto s = withIntegrator(Cornell,
                            sppm(R"(<integer name="photon_count" value="20000"/><float name="initial_radius" value="0.04"/>)"),
                            {{"res", "48"}, {"spp", "32"}});
    RenderStats stats;
    Image b = renderSeeded(*s, 1, &stats);
    CHECK(stats.rejectedSamples == 0);
    REQUIRE(allFinite(b));
    const std::vector<CornellRegion> regions = cornellRegions();
    CHECK(regions.size() >= 7);
    for (const CornellRegion& r : regions) {
        const double pa = regionMean(a, r), pb = regionMean(b, r);
        const double tol = r.name == "image" ? 0.03 : r.name == "ceiling" ? 0.10 : 0.06;
        INFO(r.name << ": path " << pa << ", sppm " << pb << ", relative " << (pb - pa) / pa << ", tolerance " << tol);
        CHECK(std::abs(pb - pa) / pa < tol);
    }
}

TEST_CASE("sppm: a closed diffuse enclosure shows Le / (1 - rho)", "[sppm][render]") {
    // Inside a cube whose walls emit Le and reflect ρ = 0.5 every pixel is Le/(1 − ρ) = 2 Le
    // (the conformance suite's "enclosure"); max_depth 1 shows Le alone. Half of the
    // light is the photons', so the ratio checks their energy. Measured (seed 3): ratio
    // 1.998 (radius 0.1 on a cube of side 2: within R of an edge the gather disc loses the
    // photons of the adjacent face, which turn away). Tolerance ±4 %.
    auto scene = [](int depth) {
        const std::string text = fmt::format(
            R"(<scene version="3.0.0"><integrator type="sppm"><integer name="max_depth" value="{}"/>)"
            R"(<integer name="photon_count" value="20000"/><float name="initial_radius" value="0.1"/></integrator>)"
            R"(<sensor type="perspective"><float name="fov" value="60"/><transform name="to_world">)"
            R"(<lookat origin="0, 0, 0" target="0, 0, 1" up="0, 1, 0"/></transform>)"
            R"(<sampler type="independent"><integer name="sample_count" value="16"/></sampler>)"
            R"(<film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>)"
            R"(<rfilter type="box"/></film></sensor>)"
            R"(<shape type="cube"><boolean name="flip_normals" value="true"/>)"
            R"(<bsdf type="diffuse"><float name="reflectance" value="0.5"/></bsdf>)"
            R"(<emitter type="area"><spectrum name="radiance" value="1"/></emitter></shape></scene>)",
            depth);
        return loadScene(*xml::parseString(text, "enclosure"));
    };
    auto emitted = scene(1), full = scene(-1);
    const Image le = renderSeeded(*emitted, 3), l = renderSeeded(*full, 3);
    REQUIRE(allFinite(l));
    const double ratio = regionMean(l, 0, 0, 1, 1) / regionMean(le, 0, 0, 1, 1);
    INFO("L / Le = " << ratio << " (exact 2)");
    CHECK(std::abs(ratio - 2.0) < 0.08);
}

TEST_CASE("sppm: progressive passes continue the same iterations", "[sppm][render]") {
    auto load = [] {
        return withIntegrator(Cornell, sppm(R"(<integer name="photon_count" value="5000"/>)"),
                              {{"res", "16"}, {"spp", "8"}});
    };
    auto s = load();
    const Image whole = renderSeeded(*s, 5);
    RenderControl first;
    first.sampleOffset = 0, first.sampleCount = 4;
    renderSeeded(*s, 5, nullptr, first);
    RenderControl second;
    second.sampleOffset = 4, second.sampleCount = 4, second.accumulate = true;
    const Image twoPasses = renderSeeded(*s, 5, nullptr, second);
    CHECK(twoPasses.pixels == whole.pixels);  // bit for bit: the same iterations in the same order

    // renderProgressive (effigi render --spp 8): passes of 1, 1, 2, 4 iterations.
    auto p = load();
    RenderControl base;
    base.progress = false;
    base.seed = 5;
    ProgressiveOptions opt;
    opt.spp = 8;
    opt.progress = false;
    renderProgressive(*p, base, opt);
    CHECK(p->camera().film().develop().pixels == whole.pixels);

    const Image again = renderSeeded(*load(), 5), other = renderSeeded(*load(), 6);
    CHECK(again.pixels == whole.pixels);
    CHECK(other.pixels != whole.pixels);
    std::vector<float> variance;
    CHECK_FALSE(s->renderer().varianceEstimate(variance));  // no per-pixel variance: see sppm.cpp

    // max_passes replaces the sampler's count; a stop request (SIGINT) before the first
    // iteration ends leaves a black, finite image.
    auto capped = withIntegrator(Cornell, sppm(R"(<integer name="photon_count" value="1000"/>)"
                                               R"(<integer name="max_passes" value="3"/>)"),
                                 {{"res", "16"}, {"spp", "8"}});
    RenderStats stats;
    renderSeeded(*capped, 5, &stats);
    CHECK(stats.samples == 3u * 16u * 16u);
    std::atomic<bool> stop{true};
    RenderControl halted;
    halted.stop = &stop;
    const Image none = renderSeeded(*capped, 5, &stats, halted);
    CHECK(stats.interrupted);
    CHECK(stats.samples == 0u);
    REQUIRE(allFinite(none));
}

TEST_CASE("sppm: dispersive glass gives a finite caustic as bright as light tracing's", "[sppm][render]") {
    // A sphere of N-SF11 (strongly dispersive: every photon and camera path through it
    // keeps only its hero wavelength, with the factor 4 once) on a white floor, lit from
    // the side by a small light, seen from above: its caustic lies on the floor beside it.
    // Reference: ptracer (unbiased, good at caustics) at 512 spp. Measured over seeds 1–5
    // on the caustic region: sppm's grey +3 … +12 % above ptracer's (against 8192-spp
    // ptracer: +6 %, SPPM's density-estimation bias at the caustic's sharp edge, where
    // neighbouring pixels' radii differ; a non-dispersive sphere shows the same), channel
    // ratios R/G and B/G within ±13 %. Tolerance (seed 4): grey 20 %, ratios 20 %; a
    // factor 4 lost or doubled would be −75 % / +300 %, a slot mixed up a colour cast.
    const std::string scene = R"(<scene version="3.0.0"><default name="spp" value="32"/>
        <default name="integrator" value="path"/>
        <integrator type="$integrator"><integer name="max_depth" value="8"/></integrator>
        <sensor type="perspective"><float name="fov" value="45"/>
          <transform name="to_world"><lookat origin="0, 3, 0" target="0, 0, 0" up="0, 0, -1"/></transform>
          <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
          <film type="hdrfilm"><integer name="width" value="48"/><integer name="height" value="48"/>
            <rfilter type="box"/></film></sensor>
        <shape type="rectangle"><transform name="to_world"><scale value="2, 2, 1"/><rotate x="1" angle="-90"/></transform>
          <bsdf type="diffuse"><rgb name="reflectance" value="0.8, 0.8, 0.8"/></bsdf></shape>
        <shape type="sphere"><point name="center" value="0, 0.4, 0"/><float name="radius" value="0.4"/>
          <bsdf type="dielectric"><string name="int_ior" value="sf11"/></bsdf></shape>
        <shape type="rectangle"><transform name="to_world"><scale value="0.3, 0.3, 1"/><rotate x="1" angle="90"/>
          <rotate z="1" angle="35"/><translate value="-1.6, 2.0, 0"/></transform>
          <emitter type="area"><rgb name="radiance" value="20, 20, 20"/></emitter></shape></scene>)";
    auto load = [&](const std::string& integrator, const std::string& spp) {
        std::string text = scene;
        if (integrator == "sppm")
            text.replace(text.find(R"(<integrator type="$integrator">)"), 31,
                         R"(<integrator type="sppm"><integer name="photon_count" value="30000"/>)"
                         R"(<float name="initial_radius" value="0.05"/>)");
        xml::ParseOptions opt;
        opt.defines = {{"spp", spp}};
        if (integrator != "sppm") opt.defines["integrator"] = integrator;
        return loadScene(*xml::parseString(text, "dispersive caustic", opt));
    };
    auto ref = load("ptracer", "512");
    Image a = renderSeeded(*ref, 4);
    auto s = load("sppm", "32");
    RenderStats stats;
    Image b = renderSeeded(*s, 4, &stats);
    CHECK(stats.rejectedSamples == 0);
    REQUIRE(allFinite(b));
    // The caustic and the sphere's shadow (fractions of the image).
    const float x0 = 28 / 48.f, x1 = 44 / 48.f, y0 = 14 / 48.f, y1 = 34 / 48.f;
    const double pa = regionMean(a, x0, y0, x1, y1), pb = regionMean(b, x0, y0, x1, y1);
    INFO("caustic grey: ptracer " << pa << ", sppm " << pb << ", relative " << (pb - pa) / pa);
    CHECK(std::abs(pb - pa) / pa < 0.20);
    for (int c : {0, 2}) {
        const double ra = regionMean(a, x0, y0, x1, y1, c) / regionMean(a, x0, y0, x1, y1, 1);
        const double rb = regionMean(b, x0, y0, x1, y1, c) / regionMean(b, x0, y0, x1, y1, 1);
        INFO("channel " << c << " / G: ptracer " << ra << ", sppm " << rb);
        CHECK(std::abs(rb - ra) / ra < 0.20);
    }
}

TEST_CASE("sppm: bad parameters are one-line errors naming file:line", "[sppm][errors]") {
    for (const std::string param :
         {R"(<float name="alpha" value="1"/>)", R"(<float name="alpha" value="0"/>)",
          R"(<float name="alpha" value="-0.5"/>)", R"(<integer name="photon_count" value="-5"/>)",
          R"(<integer name="photon_count" value="0"/>)", R"(<float name="initial_radius" value="-1"/>)"}) {
        const std::string msg = errorOf([&] { withIntegrator(Cornell, sppm(param), {{"res", "8"}}); });
        INFO(param << " -> " << msg);
        CHECK(msg.find('\n') == std::string::npos);
        CHECK(msg.find("scene.xml:") != std::string::npos);
        const bool names = msg.find("alpha") != std::string::npos || msg.find("photon_count") != std::string::npos ||
                           msg.find("initial_radius") != std::string::npos;
        CHECK(names);
    }
}
