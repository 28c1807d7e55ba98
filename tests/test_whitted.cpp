// The `whitted` renderer (components/renderer/whitted.cpp) against closed forms and
// against `direct`:
//  - a diffuse plane under a point light and a directional light: every pixel is
//    ρ/π · E with E = I cos θ / d² + E_dir cos θ_dir; also seen through a `null` sheet
//    with a mask of opacity 0.5 across the directional light's shadow rays (E_dir halved);
//  - a diffuse receiver seen in a mirror, lit directly by a point light: the pixel is
//    R · ρ/π · I cos θ / d² (the camera → mirror → receiver → light path, E S D L; light
//    reaching a receiver through a mirror, L S D E, is a caustic: Whitted's shadow rays
//    are not reflected, so it is absent by design, as in whitted.cpp's doc block);
//  - a window pane and a glass slab in front of an area light pass (1 − F)/(1 + F) of
//    it: the branches of the glass, chosen per sample, carry the right weights;
//  - the specular Cornell box (scenes/cornell-specular/whitted.xml): finite, and the mirror
//    and glass spheres show the room, where `direct` leaves them nearly black;
//  - on a scene of diffuse surfaces and delta lights both `whitted` and `direct` are exact:
//    with one light they agree sample by sample, with three (direct picks one of them per
//    sample) their image means agree within 4 standard errors.
// Spectra are flat, so the only noise in the closed-form cases is that of the hero
// wavelengths' estimate of Y (∫ ȳ of a flat spectrum by 4 samples); the tolerances are
// 4 standard errors of the image mean from the pixels' spread (pixels are independent
// with the box filter) plus the stated geometric variation across the tiny
// orthographic view (< 2e-5 relative). All renders are seeded (RenderControl's default).
#include "scene_text.hpp"

#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <catch2/catch.hpp>

#include <fmt/format.h>

#include <cmath>

using namespace effigi;

namespace {

const double Pi_ = 3.14159265358979323846;
/// Y of a flat spectrum of value 1: what the film shows for unit flat radiance.
const double FlatY = cie::luminance([](float) { return 1.f; });

struct Rendered {
    Image image;
    RenderStats stats;
};

Rendered renderScene(Scene& scene) {
    RenderControl control;
    control.progress = false;
    RenderStats stats = scene.renderer().render(scene, control);
    return {scene.camera().film().develop(), stats};
}

/// `body` seen by an orthographic camera at `origin` looking at `target` over a 0.02 × 0.02
/// square, 8 × 8 luminance pixels, box filter, `spp` samples per pixel.
Rendered renderOrtho(const std::string& integrator, const std::string& origin, const std::string& target,
                     const std::string& body, int spp) {
    std::string xml = fmt::format(R"(<scene version="3.0.0">
  {}
  <sensor type="orthographic">
    <transform name="to_world"><scale value="0.01, 0.01, 1"/><lookat origin="{}" target="{}" up="0, 1, 0"/></transform>
    <sampler type="independent"><integer name="sample_count" value="{}"/></sampler>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/>
      <string name="pixel_format" value="luminance"/><rfilter type="box"/></film>
  </sensor>
  {}
</scene>)",
                                  integrator, origin, target, spp, body);
    auto scene = loadScene(*xml::parseString(xml, "whitted-test.xml"));
    return renderScene(*scene);
}

struct Stats {
    double mean, se;
};

/// Mean of channel c over the image, its standard error from the pixels' spread.
Stats imageStats(const Image& img, int c = 0) {
    double s = 0, s2 = 0;
    int n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) {
            double v = img.at(x, y, c);
            s += v, s2 += v * v, ++n;
        }
    double m = s / n;
    return {m, std::sqrt(std::max(0.0, s2 / n - m * m) / (n - 1))};
}

/// Mean of the luminance-like grey (R + G + B)/3 over pixels [x0, x1] × [y0, y1].
double regionGrey(const Image& img, int x0, int x1, int y0, int y1) {
    double s = 0;
    int n = 0;
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x, ++n)
            for (int c = 0; c < 3; ++c) s += img.at(x, y, c) / 3.0;
    return s / n;
}

void checkFinite(const Rendered& r) {
    CHECK(r.stats.rejectedSamples == 0);
    std::size_t bad = 0;
    for (float v : r.image.pixels) bad += !std::isfinite(v);  // (sRGB may be < 0 out of gamut)
    CHECK(bad == 0);
}

const std::string Whitted = R"(<integrator type="whitted"/>)";

} // namespace

TEST_CASE("whitted: a diffuse plane under a point and a directional light shows rho/pi E", "[whitted][render]") {
    // Plane z = 0, ρ = 0.5, seen around (2, 2, 0) (away from the origin: see the mirror
    // case); point light I = 10 at height 2 above that (E = I / 4 = 2.5 below it);
    // directional light E⊥ = 3 travelling at 60° from the normal (E = 3 cos 60° = 1.5).
    // Over the viewed ±0.01 square, I cos θ / d² = I h / (h² + r²)^1.5 changes by < 1.5e-4 · r²/h²
    // relative ≈ 1e-8: nothing systematic.
    const std::string body = R"(
  <shape type="rectangle"><transform name="to_world"><scale value="5"/></transform>
    <bsdf type="diffuse"><float name="reflectance" value="0.5"/></bsdf></shape>
  <emitter type="point"><point name="position" x="2" y="2" z="2"/><spectrum name="intensity" value="10"/></emitter>
  <emitter type="directional"><vector name="direction" x="0.8660254" y="0" z="-0.5"/>
    <spectrum name="irradiance" value="3"/></emitter>)";
    Rendered r = renderOrtho(Whitted, "2, 2, 5", "2, 2, 0", body, 64);
    checkFinite(r);
    const double expected = FlatY * 0.5 / Pi_ * (10.0 / 4.0 + 3.0 * 0.5);
    Stats s = imageStats(r.image);
    INFO("plane: " << s.mean << " ± " << s.se << ", expected " << expected << ", relative error "
                   << (s.mean - expected) / expected);
    CHECK(std::abs(s.mean - expected) < 4 * s.se + 1e-6 * expected);
    CHECK(s.se < 1e-3 * expected);

    // Pass-through surfaces: a `null` sheet at z = 3 across the camera's rays (crossed
    // straight on) and a mask of opacity 0.5 at z = 1 across the directional light's
    // shadow ray only (it passes half): E = 2.5 + 1.5 · 0.5.
    const std::string passThrough = R"(
  <shape type="rectangle"><transform name="to_world"><scale value="10"/><translate value="2, 2, 3"/></transform>
    <bsdf type="null"/></shape>
  <shape type="rectangle"><transform name="to_world"><scale value="0.5"/><translate value="0.27, 2, 1"/></transform>
    <bsdf type="mask"><float name="opacity" value="0.5"/><bsdf type="diffuse"/></bsdf></shape>)";
    Rendered m = renderOrtho(Whitted, "2, 2, 5", "2, 2, 0", body + passThrough, 64);
    checkFinite(m);
    const double masked = FlatY * 0.5 / Pi_ * (10.0 / 4.0 + 3.0 * 0.5 * 0.5);
    Stats sm = imageStats(m.image);
    INFO("null and mask: " << sm.mean << " ± " << sm.se << ", expected " << masked << ", relative error "
                           << (sm.mean - masked) / masked);
    CHECK(std::abs(sm.mean - masked) < 4 * sm.se + 1e-6 * masked);
}

TEST_CASE("whitted: a receiver seen in a mirror shows R rho/pi I cos / d^2", "[whitted][render][conductor]") {
    // The camera at (0, 10, 20) looks down −z at a mirror (conductor, specular_reflectance
    // R = 0.8) through (0, 10, 0) facing (1, 0, 1)/√2: its rays turn to +x and meet the
    // receiver x = 10 (facing −x, ρ = 0.5) at (10, 10 + y, z), |y|, |z| ≤ 0.01, lit by a
    // point light I = 10 at (5, 10, 0): E = I · 5 / d³, d² = 25 + y² + z², within 1.2e-5 of
    // I / 25. The same scene moved down to put the mirror through the world origin must
    // give the same: rays leave a hit point pushed off by the magnitude of the triangle's
    // vertices (SurfaceInteraction::pScale), not of the point itself, which near the
    // origin is smaller than the point's rounding error (they used to hit the mirror
    // again and lose ~30 % of the light).
    const std::string body = R"(
  <shape type="rectangle"><transform name="to_world"><scale value="2"/><rotate y="1" angle="45"/>
    <translate value="0, 10, 0"/></transform>
    <bsdf type="conductor"><spectrum name="specular_reflectance" value="0.8"/></bsdf></shape>
  <shape type="rectangle"><transform name="to_world"><scale value="3"/><rotate y="1" angle="-90"/>
    <translate value="10, 10, 0"/></transform>
    <bsdf type="diffuse"><float name="reflectance" value="0.5"/></bsdf></shape>
  <emitter type="point"><point name="position" x="5" y="10" z="0"/><spectrum name="intensity" value="10"/></emitter>)";
    Rendered r = renderOrtho(Whitted, "0, 10, 20", "0, 10, 0", body, 64);
    checkFinite(r);
    const double expected = FlatY * 0.8 * 0.5 / Pi_ * 10.0 / 25.0;
    Stats s = imageStats(r.image);
    INFO("mirror: " << s.mean << " ± " << s.se << ", expected " << expected << ", relative error "
                    << (s.mean - expected) / expected);
    CHECK(std::abs(s.mean - expected) < 4 * s.se + 1.2e-5 * expected);
    CHECK(s.se < 1e-3 * expected);
    std::string atOrigin = body;
    for (const auto& [from, to] : {std::pair<std::string, std::string>{"0, 10, 0", "0, 0, 0"}, {"10, 10, 0", "10, 0, 0"},
                                   {R"(y="10")", R"(y="0")"}}) {
        const auto at = atOrigin.find(from);
        REQUIRE(at != std::string::npos);
        atOrigin.replace(at, from.size(), to);
    }
    Rendered o = renderOrtho(Whitted, "0, 0, 20", "0, 0, 0", atOrigin, 64);
    Stats so = imageStats(o.image);
    INFO("mirror through the origin: " << so.mean << " ± " << so.se);
    CHECK(std::abs(so.mean - expected) < 4 * so.se + 1.2e-5 * expected);

    // max_depth 2 stops at the mirror (it has no non-delta part to light): black.
    Rendered shallow = renderOrtho(R"(<integrator type="whitted"><integer name="max_depth" value="2"/></integrator>)",
                                   "0, 10, 20", "0, 10, 0", body, 1);
    CHECK(imageStats(shallow.image).mean == 0.0);
}

TEST_CASE("whitted: a window pane and a glass slab pass (1 - F)/(1 + F) of the light", "[whitted][render][dielectric]") {
    // Glass in front of a black area light of radiance 2, at normal incidence (F = 0.04):
    // what passes, all inner reflections summed, is (1 − F)/(1 + F). The branches of the
    // glass are chosen per sample, so each sample carries 2 or 0 (binomial, p ≈ 0.92):
    // 4 standard errors of the image mean (8 × 8 px × 256 spp), nothing systematic. The
    // slab needs its chains of inner reflections, the default max_depth (unbounded) allows them.
    const double expected = FlatY * 2.0 * (1 - 0.04) / (1 + 0.04);
    const std::string light = R"(
  <shape type="rectangle"><transform name="to_world"><scale value="30"/><translate value="0, 10, -10"/></transform>
    <emitter type="area"><spectrum name="radiance" value="2"/></emitter>
    <bsdf type="diffuse"><float name="reflectance" value="0"/></bsdf></shape>)";
    const std::string pane = R"(
  <shape type="rectangle"><transform name="to_world"><scale value="5"/><translate value="0, 10, 0"/></transform>
    <bsdf type="thindielectric"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf></shape>)";
    const std::string slab = R"(
  <shape type="cube"><transform name="to_world"><scale value="5, 5, 0.2"/><translate value="0, 10, 0"/></transform>
    <bsdf type="dielectric"><float name="int_ior" value="1.5"/><float name="ext_ior" value="1"/></bsdf></shape>)";
    for (const auto& [name, glass] : {std::pair<const char*, std::string>{"pane", pane}, {"slab", slab}}) {
        Rendered r = renderOrtho(Whitted, "0, 10, 20", "0, 10, 0", light + glass, 256);
        checkFinite(r);
        Stats s = imageStats(r.image);
        INFO(name << ": " << s.mean << " ± " << s.se << ", expected " << expected << ", relative error "
                  << (s.mean - expected) / expected);
        CHECK(std::abs(s.mean - expected) < 4 * s.se);
        CHECK(s.se < 0.005 * expected);
    }
}

TEST_CASE("whitted: the specular Cornell box shows the room in its mirror and glass spheres", "[whitted][render]") {
    const std::string file = EFFIGI_SOURCE_DIR "/scenes/cornell-specular/whitted.xml";
    const std::map<std::string, std::string> defines{{"res", "64"}, {"spp", "8"}};
    auto whitted = test::loadEdited(file, {}, defines);
    Rendered w = renderScene(*whitted);
    checkFinite(w);
    auto direct = test::loadWithIntegrator(file, R"(<integrator type="direct"/>)", defines);
    Rendered d = renderScene(*direct);
    // Blocks of 3 × 3 pixels around points of the spheres projected by the camera (at
    // z = 3.9 looking down −z, 39.3077° field of view, 64 px: x = (1 + X/(Z t))/2 · 64,
    // y = (1 − Y/(Z t))/2 · 64, t = tan(fov/2), Z = 3.9 − z). The spheres are ≥ 7 px in radius.
    const double t = std::tan(39.3077 / 2 * Pi_ / 180);
    struct RGB {
        double r = 0, g = 0, b = 0;
        double grey() const { return (r + g + b) / 3; }
    };
    auto block = [&](const Image& img, double X, double Y, double Z) {
        const int px = int((1 + X / ((3.9 - Z) * t)) / 2 * 64), py = int((1 - Y / ((3.9 - Z) * t)) / 2 * 64);
        RGB m;
        for (int y = py - 1; y <= py + 1; ++y)
            for (int x = px - 1; x <= px + 1; ++x)
                m.r += img.at(x, y, 0) / 9, m.g += img.at(x, y, 1) / 9, m.b += img.at(x, y, 2) / 9;
        return m;
    };
    // The point of the mirror sphere (centre (−0.4, −0.65, −0.3), radius 0.35) whose normal
    // n ∝ r − v turns the view direction v into r = −x: it shows the red wall.
    const double cx = -0.4, cy = -0.65, cz = -0.3, vl = std::sqrt(cx * cx + cy * cy + (cz - 3.9) * (cz - 3.9));
    double nx = -1 - cx / vl, ny = -cy / vl, nz = -(cz - 3.9) / vl;
    const double nl = std::sqrt(nx * nx + ny * ny + nz * nz);
    nx /= nl, ny /= nl, nz /= nl;
    const RGB redW = block(w.image, cx + 0.35 * nx, cy + 0.35 * ny, cz + 0.35 * nz);
    const RGB redD = block(d.image, cx + 0.35 * nx, cy + 0.35 * ny, cz + 0.35 * nz);
    // The glass sphere's centre (0.4, −0.65, 0.3): the floor and back wall seen through it.
    const RGB glassW = block(w.image, 0.4, -0.65, 0.3), glassD = block(d.image, 0.4, -0.65, 0.3);
    const double image = regionGrey(w.image, 0, 63, 0, 63);
    INFO("image mean " << image << "; mirror sphere toward the red wall: whitted " << redW.r << ", " << redW.g << ", "
                       << redW.b << ", direct grey " << redD.grey() << "; glass sphere centre: whitted grey "
                       << glassW.grey() << ", direct " << glassD.grey());
    CHECK(image > 0.05);
    // Where direct shows next to nothing (it finds only the light's reflection; the
    // Gaussian filter brings in a little of the wall beside the mirror's edge), whitted
    // shows the red wall in the mirror (seen: R 0.064, G 0.006, B 0.002, direct's grey
    // 0.002) and the lit room through the glass (grey 0.044, direct 0; image mean 0.125).
    CHECK(redW.r > 0.25 * image);
    CHECK(redW.r > 3 * redW.g);
    CHECK(redD.grey() < 0.25 * redW.grey());
    CHECK(glassW.grey() > 0.15 * image);
    CHECK(glassD.grey() < 0.1 * glassW.grey());
}

TEST_CASE("whitted: equals direct on diffuse surfaces under delta lights", "[whitted][render]") {
    // An open box (floor, back, red and green walls) and a diffuse sphere. With one point
    // light both renderers make the same computation from the same sampler dimensions
    // (camera, wavelengths, one light sample): they agree pixel by pixel to float
    // rounding (1e-5 relative to the image's largest pixel).
    const std::string walls = R"(
  <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="-90"/><translate value="0, -1, 0"/></transform>
    <bsdf type="diffuse"><float name="reflectance" value="0.8"/></bsdf></shape>
  <shape type="rectangle"><transform name="to_world"><translate value="0, 0, -1"/></transform>
    <bsdf type="diffuse"><float name="reflectance" value="0.7"/></bsdf></shape>
  <shape type="rectangle"><transform name="to_world"><rotate y="1" angle="90"/><translate value="-1, 0, 0"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.1, 0.1"/></bsdf></shape>
  <shape type="rectangle"><transform name="to_world"><rotate y="1" angle="-90"/><translate value="1, 0, 0"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.1, 0.5, 0.1"/></bsdf></shape>
  <shape type="sphere"><point name="center" x="0.3" y="-0.6" z="-0.2"/><float name="radius" value="0.4"/>
    <bsdf type="diffuse"><float name="reflectance" value="0.5"/></bsdf></shape>
  <emitter type="point"><point name="position" x="-0.3" y="0.6" z="0.2"/><spectrum name="intensity" value="3"/></emitter>)";
    const std::string more = R"(
  <emitter type="spot"><transform name="to_world"><lookat origin="0.5, 0.8, 0.5" target="0, -1, -0.5"/></transform>
    <spectrum name="intensity" value="4"/><float name="cutoff_angle" value="35"/></emitter>
  <emitter type="directional"><vector name="direction" x="0.3" y="-1" z="-0.4"/><spectrum name="irradiance" value="1"/></emitter>)";
    auto render = [&](const std::string& integrator, const std::string& body, int spp) {
        std::string xml = fmt::format(R"(<scene version="3.0.0">{}
  <sensor type="perspective"><float name="fov" value="45"/>
    <transform name="to_world"><lookat origin="0, 0, 3.5" target="0, 0, 0" up="0, 1, 0"/></transform>
    <sampler type="independent"><integer name="sample_count" value="{}"/></sampler>
    <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/><rfilter type="box"/></film>
  </sensor>{}</scene>)",
                                      integrator, spp, body);
        auto scene = loadScene(*xml::parseString(xml, "whitted-vs-direct.xml"));
        Rendered r = renderScene(*scene);
        checkFinite(r);
        return r.image;
    };
    {
        Image w = render(Whitted, walls, 4), d = render(R"(<integrator type="direct"/>)", walls, 4);
        REQUIRE(w.pixels.size() == d.pixels.size());
        float peak = 0.f, worst = 0.f;
        for (std::size_t i = 0; i < w.pixels.size(); ++i) {
            peak = std::max(peak, d.pixels[i]);
            worst = std::max(worst, std::abs(w.pixels[i] - d.pixels[i]));
        }
        INFO("one point light: largest pixel " << peak << ", largest difference " << worst);
        CHECK(peak > 0.f);
        CHECK(worst <= 1e-5f * peak);
    }
    {
        // Three delta lights: whitted takes each, direct one chosen at random per sample.
        // The image means (grey) must agree within 4 standard errors of their difference,
        // estimated from the per-pixel differences' spread.
        Image w = render(Whitted, walls + more, 16), d = render(R"(<integrator type="direct"/>)", walls + more, 16);
        double sum = 0, sum2 = 0;
        const int n = w.width * w.height;
        for (int y = 0; y < w.height; ++y)
            for (int x = 0; x < w.width; ++x) {
                double g = regionGrey(w, x, x, y, y) - regionGrey(d, x, x, y, y);
                sum += g, sum2 += g * g;
            }
        const double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / (n - 1));
        const double ref = regionGrey(w, 0, 23, 0, 23);
        INFO("three lights: whitted " << ref << ", direct − whitted " << -mean << " ± " << se);
        CHECK(ref > 0.0);
        CHECK(std::abs(mean) < 4 * se);
        CHECK(se < 0.02 * ref);
    }
}
