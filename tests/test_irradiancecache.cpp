// Renderer irradiancecache (components/renderer/irradiancecache.cpp): the gather's
// irradiance and Ward & Heckbert gradients against a closed form (a square emitter over a
// plane: Lambert's polygon formula, differentiated numerically), the closed diffuse
// enclosure's exact radiance, the Cornell box against `path` wall by wall, determinism,
// bad parameters and extreme ones. Every render is seeded, so each check is deterministic;
// tolerances are stated where they are set.
#include "../components/renderer/irradiance_gather.hpp"
#include "cornell_regions.hpp"
#include "printable_line.hpp"
#include "scene_text.hpp"

#include "effigi/core/error.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>

using namespace effigi;
using namespace effigi::test;
using namespace effigi::irrcache;

namespace {

// A square emitter of unit radiance, side 1, centred over (0, 0) at height 1, facing down.
constexpr float LightHalf = 0.5f, LightHeight = 1.f;

/// Exact irradiance at p with normal n from the square (Lambert's polygon formula:
/// E = L/2 Σ γ_i n·(u_i × u_i+1)/|u_i × u_i+1|, u_i the unit vectors to the corners).
double exactE(const Vector3f& p, const Vector3f& n) {
    const Vector3f c[4] = {{-LightHalf, -LightHalf, LightHeight}, {LightHalf, -LightHalf, LightHeight},
                           {LightHalf, LightHalf, LightHeight}, {-LightHalf, LightHalf, LightHeight}};
    double sum = 0.0;
    for (int i = 0; i < 4; ++i) {
        const glm::dvec3 a = glm::normalize(glm::dvec3(c[i] - p)), b = glm::normalize(glm::dvec3(c[(i + 1) % 4] - p));
        const glm::dvec3 x = glm::cross(a, b);
        sum += std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0)) * glm::dot(glm::dvec3(n), x / glm::length(x));
    }
    return 0.5 * std::abs(sum);
}

/// A record's gather at p, n against the square (every node sees radiance 1).
HemisphereGather::Result gatherAt(const Vector3f& p, const Vector3f& n, int m, std::uint64_t seed) {
    HemisphereGather g(m, 3 * m);
    PCG32 rng(seed, 7);
    g.generate(Frame(n), rng);
    for (int cell = 0; cell < g.count(); ++cell) {
        const Vector3f d = g.direction(cell);
        NodeValues L{};
        float dist = Infinity;
        if (d.z > 0.f) {
            const float t = (LightHeight - p.z) / d.z;
            const Vector3f q = p + d * t;
            if (std::abs(q.x) <= LightHalf && std::abs(q.y) <= LightHalf) L.fill(1.f), dist = t;
        }
        g.set(cell, L, dist);
    }
    return g.process();
}

std::unique_ptr<Scene> loadText(const std::string& text, const std::string& file) {
    return loadScene(*xml::parseString(text, file, {}));
}

std::unique_ptr<Scene> loadCornell(const std::string& file, std::map<std::string, std::string> defines) {
    xml::ParseOptions opt;
    opt.defines = std::move(defines);
    return loadSceneFile(std::string(EFFIGI_SOURCE_DIR) + "/scenes/cornell-box/" + file, opt);
}

Image renderImage(Scene& scene, std::uint64_t seed) {
    RenderControl control;
    control.progress = false;
    control.seed = seed;
    RenderStats stats = scene.renderer().render(scene, control);
    CHECK(stats.rejectedSamples == 0);
    return scene.camera().film().develop();
}

const std::string Enclosure = R"(<scene version="3.0.0">
  <integrator type="irradiancecache">$EXTRA</integrator>
  <sensor type="perspective"><float name="fov" value="60"/>
    <transform name="to_world"><lookat origin="0, 0, 0" target="0, 0, 1" up="0, 1, 0"/></transform>
    <sampler type="independent"><integer name="sample_count" value="8"/></sampler>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/>
      <rfilter type="box"/></film></sensor>
  <shape type="cube"><boolean name="flip_normals" value="true"/>
    <bsdf type="diffuse"><float name="reflectance" value="$RHO"/></bsdf>
    <emitter type="area"><spectrum name="radiance" value="1"/></emitter></shape>
</scene>)";

std::string enclosure(const std::string& rho, const std::string& extra) {
    std::string s = Enclosure;
    // A coarse gather (6 × 18 rays) unless the test sets its own.
    const std::string params =
        extra.find("\"resolution\"") == std::string::npos ? extra + R"(<integer name="resolution" value="6"/>)" : extra;
    s.replace(s.find("$EXTRA"), 6, params);
    s.replace(s.find("$RHO"), 4, rho);
    return s;
}

} // namespace

TEST_CASE("irradiancecache: gather irradiance and gradients match the square emitter's closed form",
          "[irradiancecache]") {
    // 64 × 192 jittered cells: the stratified estimate of E is within 0.3 % here (seeded).
    const Vector3f p(0.3f, 0.1f, 0.f), n(0.f, 0.f, 1.f);
    const int m = 64;
    const HemisphereGather::Result r = gatherAt(p, n, m, 1);
    const double e = exactE(p, n);
    INFO("E gathered " << r.E[0] << ", exact " << e);
    CHECK(std::abs(r.E[0] - e) < 0.003 * e);
    for (int i = 1; i < Nodes; ++i) CHECK(r.E[i] == r.E[0]);

    // Translational gradient against the central difference of the exact E (h = 1e-3; its
    // own error is O(h²) ≈ 1e-6). Ward & Heckbert's estimate from the cell boundaries is
    // within 5 % of |∇E| here.
    const double h = 1e-3;
    const glm::dvec3 fd((exactE(p + Vector3f(h, 0, 0), n) - exactE(p - Vector3f(h, 0, 0), n)) / (2 * h),
                        (exactE(p + Vector3f(0, h, 0), n) - exactE(p - Vector3f(0, h, 0), n)) / (2 * h), 0.0);
    const glm::dvec3 tg(r.transGrad[0]);
    INFO("∇t gathered (" << tg.x << ", " << tg.y << ", " << tg.z << "), finite differences (" << fd.x << ", " << fd.y
                         << ")");
    CHECK(glm::length(tg - fd) < 0.05 * glm::length(fd));

    // Pairs of records 0.1 apart (128 × 384 cells each): their difference of E over the
    // distance, averaged over 16 seeds (σ of the mean ≈ 0.004 here), agrees with the gradient
    // at the midpoint within 5 % of |∇E| (the difference quotient's own error is 0.3 %).
    const float dx = 0.1f;
    double diff = 0.0;
    for (std::uint64_t seed = 2; seed < 18; ++seed)
        diff += (gatherAt(p + Vector3f(dx / 2, 0, 0), n, 128, seed).E[0] -
                 gatherAt(p - Vector3f(dx / 2, 0, 0), n, 128, seed + 100).E[0]) / (16.0 * dx);
    const double exactDiff = (exactE(p + Vector3f(dx / 2, 0, 0), n) - exactE(p - Vector3f(dx / 2, 0, 0), n)) / dx;
    INFO("records' difference " << diff << ", exact difference " << exactDiff);
    CHECK(std::abs(diff - tg.x) < 0.05 * glm::length(fd));

    // Rotational gradient: tilting n by δ about y changes E by (n × n')·∇_r (δ = 0.01 rad).
    const float delta = 0.01f;
    const Vector3f nt(std::sin(delta), 0.f, std::cos(delta));
    const double dE = exactE(p, nt) - e, predicted = dot(cross(n, nt), r.rotGrad[0]);
    INFO("rotation: exact change " << dE << ", predicted " << predicted);
    CHECK(std::abs(predicted - dE) < 0.05 * std::abs(dE));
}

TEST_CASE("irradiancecache: closed diffuse enclosure shows Le/(1 − ρ)", "[irradiancecache]") {
    // Every wall emits Le = 1 and reflects ρ = 0.5: L = 2 everywhere, records exact up to
    // their gather's noise. Divided by the same camera's emission-only image (max_depth 1)
    // so that the colour conversion of the flat spectrum cancels; 3 % allows the noise of
    // 16 × 16 × 8 samples and of the records (seeded: deterministic).
    auto full = loadText(enclosure("0.5", ""), "enclosure.xml");
    auto emitted = loadText(enclosure("0.5", R"(<integer name="max_depth" value="1"/>)"), "enclosure.xml");
    const Image a = renderImage(*full, 3), b = renderImage(*emitted, 3);
    const double ratio = regionMean(a, 0, 0, 1, 1) / regionMean(b, 0, 0, 1, 1);
    INFO("L / Le = " << ratio << ", exact 2");
    CHECK(std::abs(ratio - 2.0) < 0.06);
    CHECK(allFinite(a));
}

TEST_CASE("irradiancecache: Cornell box agrees with path wall by wall", "[irradiancecache]") {
    auto ic =
        loadCornell("irradiancecache.xml", {{"res", "64"}, {"spp", "8"}, {"resolution", "8"}, {"quality", "0.5"}});
    auto pt = loadCornell("scene.xml", {{"res", "64"}, {"spp", "64"}});
    const Image a = renderImage(*ic, 1), b = renderImage(*pt, 1);
    CHECK(allFinite(a));
    // Tolerances: the bias of interpolation at this coarse setting (64² pixels, 8 × 24
    // gather rays) plus the path image's noise at 64 spp (about 1 % per wall); the image
    // mean 3 %, walls 6 %.
    const std::vector<CornellRegion> regions = cornellRegions();
    CHECK(regions.size() >= 7);
    for (const CornellRegion& r : regions) {
        const double x = regionMean(a, r), y = regionMean(b, r);
        INFO(r.name << ": irradiancecache " << x << ", path " << y << ", relative " << (x - y) / y);
        CHECK(std::abs(x - y) < (r.name == "image" ? 0.03 : 0.06) * y);
    }
}

TEST_CASE("irradiancecache: the image is a deterministic function of the seed", "[irradiancecache]") {
    auto s = loadCornell("irradiancecache.xml", {{"res", "24"}, {"spp", "2"}, {"resolution", "3"}});
    const Image a = renderImage(*s, 5), b = renderImage(*s, 5), c = renderImage(*s, 6);
    CHECK(a.pixels == b.pixels);
    CHECK(a.pixels != c.pixels);
}

TEST_CASE("irradiancecache: bad parameters are one-line errors", "[irradiancecache]") {
    for (const auto& [param, want] : std::vector<std::pair<std::string, std::string>>{
             {R"(<float name="quality" value="0"/>)", "quality"},
             {R"(<integer name="resolution" value="0"/>)", "resolution"},
             {R"(<float name="quality_adjustment" value="1.5"/>)", "quality_adjustment"},
             {R"(<integer name="max_depth" value="-2"/>)", "max_depth"},
             {R"(<store type="no_such_store"/>)", "no_such_store"}}) {
        INFO(param);
        try {
            loadText(enclosure("0.5", param), "bad.xml");
            FAIL("no error");
        } catch (const Error& e) {
            const std::string msg = e.what();
            INFO(msg);
            CHECK(msg.find(want) != std::string::npos);
            CHECK(msg.find("bad.xml") != std::string::npos);
            CHECK(test::printableLine(msg));
        }
    }
}

TEST_CASE("irradiancecache: extreme parameters give finite images", "[irradiancecache]") {
    for (const std::string extra :
         {R"(<float name="quality" value="1e-4"/>)", R"(<float name="quality" value="1e4"/>)",
          R"(<integer name="resolution" value="1"/>)",
          R"(<boolean name="clamp_screen" value="false"/><boolean name="clamp_neighbor" value="false"/>)",
          R"(<boolean name="overture" value="false"/><float name="quality_adjustment" value="0.001"/>)"}) {
        INFO(extra);
        auto s = loadText(enclosure("0.9", extra), "extreme.xml");
        const Image img = renderImage(*s, 2);
        CHECK(allFinite(img));
        CHECK(regionMean(img, 0, 0, 1, 1) > 0.0);
    }
}
