// End to end with the path renderer: delta BSDFs and its MIS. After a specular bounce the
// emitter the next ray hits must count with weight 1 (light sampling cannot reach it), so
// a gold mirror reflecting an area light shows the light's radiance × F_gold(45°), and a
// window pane or a glass slab in front of the light passes (1 − F)/(1 + F) of it. The
// lights are black (reflectance 0): a diffuse light would also reflect what the glass
// sends back to it.
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/render/fresnel.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/named.hpp"
#include "effigi/xml/loader.hpp"

#include <catch2/catch.hpp>

#include <fmt/format.h>

using namespace effigi;

namespace {

constexpr float Radiance = 2.f;

/// A 16×16 luminance image of a narrow (4°) camera at (0, 0, 20) looking down −z at
/// `objects`; seeded, so the outcome is fixed.
Image render(const std::string& objects, int spp) {
    std::string xml = fmt::format(R"(<scene version="3.0.0">
  <integrator type="path"/>
  <sensor type="perspective">
    <float name="fov" value="4"/>
    <transform name="to_world"><lookat origin="0, 0, 20" target="0, 0, 0" up="0, 1, 0"/></transform>
    <sampler type="independent"><integer name="sample_count" value="{}"/></sampler>
    <film type="hdrfilm">
      <integer name="width" value="16"/><integer name="height" value="16"/>
      <string name="pixel_format" value="luminance"/>
      <rfilter type="box"/>
    </film>
  </sensor>
  {}
</scene>)",
                                  spp, objects);
    auto root = xml::parseString(xml, "mirror-test.xml");
    auto scene = loadScene(*root);
    RenderControl control;
    control.progress = false;
    RenderStats stats = scene->renderer().render(*scene, control);
    CHECK(stats.rejectedSamples == 0);
    return scene->camera().film().develop();
}

struct Stats {
    double mean, se;
};

/// Mean over the central 8×8 pixels and its standard error from their spread (pixels are
/// independent with a box filter).
Stats central(const Image& img) {
    REQUIRE(img.channels() == 1);
    double s = 0, s2 = 0;
    int n = 0;
    for (int y = 4; y < 12; ++y)
        for (int x = 4; x < 12; ++x) {
            double v = img.at(x, y, 0);
            s += v, s2 += v * v, ++n;
        }
    double m = s / n;
    return {m, std::sqrt(std::max(0.0, s2 / n - m * m) / (n - 1))};
}

const std::string LightFacingMinusX = fmt::format(R"(
  <shape type="rectangle">
    <transform name="to_world"><scale value="30"/><rotate y="1" angle="-90"/><translate value="10, 0, 0"/></transform>
    <emitter type="area"><spectrum name="radiance" value="{}"/></emitter>
    <bsdf type="diffuse"><float name="reflectance" value="0"/></bsdf>
  </shape>)", Radiance);

const std::string LightFacingCamera = fmt::format(R"(
  <shape type="rectangle">
    <transform name="to_world"><scale value="30"/><translate value="0, 0, -10"/></transform>
    <emitter type="area"><spectrum name="radiance" value="{}"/></emitter>
    <bsdf type="diffuse"><float name="reflectance" value="0"/></bsdf>
  </shape>)", Radiance);

} // namespace

TEST_CASE("mirror render: a gold mirror shows the light's radiance times its reflectance", "[render][conductor]") {
    // The mirror at the origin faces (1, 0, 1)/√2: camera rays turn to +x and meet the
    // light at x = 10, which the camera cannot see directly.
    Image img = render(LightFacingMinusX + R"(
  <shape type="rectangle">
    <transform name="to_world"><scale value="2"/><rotate y="1" angle="45"/></transform>
    <bsdf type="conductor"><string name="material" value="Au"/></bsdf>
  </shape>)",
                       64);
    Spectrum eta = namedSpectrum("Au-eta"), k = namedSpectrum("Au-k");
    auto expected = [&](float deg) {
        float c = std::cos(deg * Pi / 180.f);
        return Radiance * cie::luminance([&](float l) { return fresnelConductor(c, eta(l), k(l)); });
    };
    Stats s = central(img);
    // The central pixels see the mirror within ±1° of 45°; F_gold changes by |F(44°) −
    // F(46°)| over that, taken as the systematic part of the tolerance, plus 4 standard
    // errors of the wavelength and pixel noise (two-sided false alarm 6e-5).
    double ref = expected(45.f), sys = std::abs(expected(44.f) - expected(46.f));
    INFO("mirror: " << s.mean << " ± " << s.se << ", expected " << ref << " (±" << sys << ")");
    CHECK(std::abs(s.mean - ref) < sys + 4 * s.se);
    CHECK(s.se < 0.01 * ref);
    // A missing or halved MIS weight would show as a darker mirror; a perfect mirror
    // ("none") returns the radiance itself.
    Image none = render(LightFacingMinusX + R"(
  <shape type="rectangle">
    <transform name="to_world"><scale value="2"/><rotate y="1" angle="45"/></transform>
    <bsdf type="conductor"/>
  </shape>)",
                        4);
    Stats p = central(none);
    INFO("perfect mirror: " << p.mean << " ± " << p.se);
    CHECK(p.mean == Approx(Radiance * cie::luminance([](float) { return 1.f; })).epsilon(1e-4));
}

TEST_CASE("mirror render: a window pane and a glass slab pass (1 - F)/(1 + F) of the light", "[render][dielectric]") {
    // Normal incidence (within 2°, where F changes by < 1e-5): F = 0.04, (1 − F)/(1 + F) = 0.923077.
    const double expect = Radiance * (1 - 0.04) / (1 + 0.04);
    const double white = cie::luminance([](float) { return 1.f; });  // Y of a flat spectrum of 1
    Image pane = render(LightFacingCamera + R"(
  <shape type="rectangle">
    <transform name="to_world"><scale value="5"/></transform>
    <bsdf type="thindielectric"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>
  </shape>)",
                        1024);
    Image slab = render(LightFacingCamera + R"(
  <shape type="cube">
    <transform name="to_world"><scale value="5, 5, 0.2"/></transform>
    <bsdf type="dielectric"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf>
  </shape>)",
                        1024);
    for (auto [name, img] : {std::pair<const char*, const Image*>{"pane", &pane}, {"slab", &slab}}) {
        Stats s = central(*img);
        // Each camera sample passes (value 2) or is reflected away (0): binomial noise with
        // p = 0.92; 4 standard errors (false alarm 6e-5, about 0.4 %), nothing systematic.
        INFO(name << ": " << s.mean << " ± " << s.se << ", expected " << expect * white);
        CHECK(std::abs(s.mean - expect * white) < 4 * s.se + 1e-4);
        CHECK(s.se < 0.002 * expect);
    }
}
