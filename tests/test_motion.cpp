// Time and motion blur: AnimatedTransform (include/effigi/math/animated_transform.hpp),
// <animation> in the grammar, shutter_open/shutter_close on cameras, moving shapes placed
// by instances (src/xml/animation.cpp, components/shape/instance.cpp), moving cameras, and
// the renderers that time their rays.
// - Interpolation: keys are met exactly; between them rotation stays rigid (a half-way
//   pose of a 90° turn is the 45° turn, not a shrunk matrix), translation and scale are
//   linear; motion bounds hold every pose.
// - An exact motion-blur image: an orthographic view of a black sphere (radius r) crossing
//   a white environment from x = −1 to 1 during the shutter. A ray at (x, y) with
//   |x| ≤ 1 − √(r² − y²) is blocked for a fraction √(r² − y²) of the shutter, so its value
//   is 1 − √(r² − y²) of the open sky's. Rows of the middle band are compared with that
//   (their width-average over the pixel's y extent), at 64 spp per pixel over 32 columns:
//   a row's standard error is under 0.01; the tolerance 0.03.
// - A camera moving right sees what a still camera sees of the scene moving left (image
//   means within 1 %, 128 spp: noise ~0.3 %); bdpt and path agree on moving shapes.
// - Errors: renderers that cannot time their rays refuse a moving scene in one line, as
//   do an emitter on a moving shape, keyframes out of order, an animation where a still
//   transform is expected, and a shutter closing before it opens.
#include "cornell_regions.hpp"
#include "scene_text.hpp"

#include "effigi/math/animated_transform.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace effigi;
using namespace effigi::test;

namespace {

std::unique_ptr<Scene> load(const std::string& text) { return loadScene(*xml::parseString(text, "motion.xml")); }

/// A black sphere of radius 0.5 moving along x, seen through `sensor` against a white sky.
std::string crossing(const std::string& integrator, const std::string& sensor, const std::string& sphereMotion) {
    return R"(<scene version="3.0.0">)" + integrator + sensor +
           R"(<emitter type="constant"><rgb name="radiance" value="1"/></emitter>
              <shape type="sphere"><float name="radius" value="0.5"/>)" +
           sphereMotion + R"(<bsdf type="diffuse"><rgb name="reflectance" value="0"/></bsdf></shape></scene>)";
}

const std::string MovingRight = R"(<animation name="to_world"><transform time="0"><translate x="-1"/></transform>
                                   <transform time="1"><translate x="1"/></transform></animation>)";

std::string orthographic(int spp) {
    return R"(<sensor type="orthographic"><float name="shutter_open" value="0"/><float name="shutter_close" value="1"/>
        <transform name="to_world"><scale value="2"/><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value=")" +
           std::to_string(spp) + R"("/></sampler>
        <film type="hdrfilm"><integer name="width" value="128"/><integer name="height" value="64"/>
        <rfilter type="box"/></film></sensor>)";
}

double grey(const Image& img, int x, int y) { return (img.at(x, y, 0) + img.at(x, y, 1) + img.at(x, y, 2)) / 3.0; }

} // namespace

TEST_CASE("motion: keyframes are interpolated rigidly", "[motion]") {
    const AnimatedTransform a({{0.f, Transform::translate({0.f, 0.f, 0.f})},
                               {2.f, Transform::translate({2.f, 0.f, 0.f}) * Transform::rotate({0.f, 0.f, 1.f}, 90.f) *
                                         Transform::scale({1.f, 3.f, 1.f})}});
    CHECK(a.isAnimated());
    auto close = [](const Transform& x, const Transform& y) {
        for (int c = 0; c < 4; ++c)
            for (int r = 0; r < 4; ++r)
                if (std::abs(x.matrix()[c][r] - y.matrix()[c][r]) > 1e-4f) return false;
        return true;
    };
    CHECK(close(a.at(0.f), a.keys()[0].transform));
    CHECK(close(a.at(2.f), a.keys()[1].transform));
    CHECK(close(a.at(-5.f), a.keys()[0].transform));  // still before the first key
    CHECK(close(a.at(9.f), a.keys()[1].transform));   // and after the last
    const Transform half = Transform::translate({1.f, 0.f, 0.f}) * Transform::rotate({0.f, 0.f, 1.f}, 45.f) *
                           Transform::scale({1.f, 2.f, 1.f});
    CHECK(close(a.at(1.f), half));
    // Motion bounds hold the unit box in every pose.
    const BBox3f unit(Point3f(-1.f), Point3f(1.f));
    const BBox3f b = a.motionBounds(unit);
    for (int i = 0; i <= 200; ++i) {
        const Transform t = a.at(2.f * float(i) / 200.f);
        for (int c = 0; c < 8; ++c) {
            const Point3f p = t.point(Point3f(c & 1 ? 1.f : -1.f, c & 2 ? 1.f : -1.f, c & 4 ? 1.f : -1.f));
            CHECK((p.x >= b.min.x && p.y >= b.min.y && p.z >= b.min.z && p.x <= b.max.x && p.y <= b.max.y &&
                   p.z <= b.max.z));
        }
    }
}

TEST_CASE("motion: a sphere crossing the shutter blurs exactly", "[motion][render]") {
    for (const char* wavefront : {"true", "false"}) {
        auto scene = load(crossing(std::string(R"(<integrator type="path"><boolean name="wavefront" value=")") +
                                       wavefront + R"("/></integrator>)",
                                   orthographic(64), MovingRight));
        const Image img = renderSeeded(*scene, 5);
        REQUIRE(allFinite(img));
        // The open sky: the corner columns, where the sphere never passes.
        double sky = 0.0;
        for (int y = 0; y < img.height; ++y)
            for (int x : {0, 1, img.width - 2, img.width - 1}) sky += grey(img, x, y) / (4.0 * img.height);
        REQUIRE(sky > 0.0);
        // Pixel columns within |x| < 0.45 (x spans [−2, 2]); rows within |y| < 0.45.
        for (int y = 0; y < img.height; ++y) {
            const double y0 = 1.0 - 2.0 * y / img.height, y1 = 1.0 - 2.0 * (y + 1) / img.height;
            if (std::abs(0.5 * (y0 + y1)) > 0.45) continue;
            double expected = 0.0;
            constexpr int N = 200;
            for (int k = 0; k < N; ++k) {
                const double yy = y0 + (y1 - y0) * (k + 0.5) / N;
                expected += (1.0 - std::sqrt(std::max(0.0, 0.25 - yy * yy))) / N;
            }
            double sum = 0.0;
            int n = 0;
            for (int x = 0; x < img.width; ++x) {
                const double cx = -2.0 + 4.0 * (x + 0.5) / img.width;
                if (std::abs(cx) >= 0.45) continue;
                sum += grey(img, x, y) / sky;
                ++n;
            }
            INFO("wavefront " << wavefront << ", row " << y << ": " << sum / n << " vs exact " << expected);
            CHECK(std::abs(sum / n - expected) < 0.03);
        }
    }
}

TEST_CASE("motion: a moving camera sees the scene move the other way", "[motion][render]") {
    const std::string perspective = R"(<sensor type="perspective"><float name="fov" value="50"/>
        <float name="shutter_open" value="0"/><float name="shutter_close" value="1"/>)";
    const std::string tail = R"(<sampler type="independent"><integer name="sample_count" value="128"/></sampler>
        <film type="hdrfilm"><integer name="width" value="48"/><integer name="height" value="32"/></film></sensor>)";
    const std::string movingCamera =
        perspective + R"(<animation name="to_world">
            <transform time="0"><lookat origin="-1, 0, 4" target="-1, 0, 0" up="0, 1, 0"/></transform>
            <transform time="1"><lookat origin="1, 0, 4" target="1, 0, 0" up="0, 1, 0"/></transform></animation>)" + tail;
    const std::string stillCamera =
        perspective + R"(<transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>)" +
        tail;
    const std::string movingLeft = R"(<animation name="to_world"><transform time="0"><translate x="1"/></transform>
                                      <transform time="1"><translate x="-1"/></transform></animation>)";
    const std::string path = R"(<integrator type="path"/>)";
    const Image a = renderSeeded(*load(crossing(path, movingCamera, "")), 3);
    const Image b = renderSeeded(*load(crossing(path, stillCamera, movingLeft)), 4);
    const double ma = regionMean(a, 0.f, 0.f, 1.f, 1.f), mb = regionMean(b, 0.f, 0.f, 1.f, 1.f);
    INFO("moving camera " << ma << ", moving sphere " << mb);
    CHECK(std::abs(ma - mb) < 0.01 * mb);
    CHECK(ma < 0.98 * regionMean(a, 0.f, 0.f, 0.1f, 1.f));  // the sphere is there, blurred
}

TEST_CASE("motion: bdpt renders moving shapes as path does", "[motion][render]") {
    // bdpt needs a camera with a density of directions: a perspective one here.
    const std::string sensor = R"(<sensor type="perspective"><float name="fov" value="60"/>
        <float name="shutter_open" value="0"/><float name="shutter_close" value="1"/>
        <transform name="to_world"><lookat origin="0, 0, 3" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="64"/></sampler>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/></film></sensor>)";
    const std::string grey = R"(<bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>)";
    auto scene = [&](const std::string& integrator) {
        return R"(<scene version="3.0.0">)" + integrator + sensor +
               R"(<shape type="rectangle"><transform name="to_world"><scale value="0.3"/><rotate x="1" angle="90"/>
                   <translate y="1"/></transform><emitter type="area"><rgb name="radiance" value="10"/></emitter></shape>
                  <shape type="rectangle"><transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/>
                   <translate y="-0.6"/></transform>)" + grey + R"(</shape>
                  <shape type="sphere"><float name="radius" value="0.4"/>)" + MovingRight + grey + "</shape></scene>";
    };
    const Image b = renderSeeded(*load(scene(R"(<integrator type="bdpt"/>)")), 1);
    const Image p = renderSeeded(*load(scene(R"(<integrator type="path"/>)")), 2);
    const double mb = regionMean(b, 0.f, 0.f, 1.f, 1.f), mp = regionMean(p, 0.f, 0.f, 1.f, 1.f);
    INFO("bdpt " << mb << ", path " << mp);
    CHECK(allFinite(b));
    CHECK(std::abs(mb - mp) < 0.03 * mp);
}

TEST_CASE("motion: scenes that cannot move are refused in one line", "[motion]") {
    const std::string sensor = orthographic(1);
    CHECK_THROWS_WITH(load(crossing(R"(<integrator type="ptracer"/>)", sensor, MovingRight)),
                      Catch::Contains("motion.xml:1") && Catch::Contains("does not render motion blur"));
    CHECK_THROWS_WITH(load(crossing(R"(<integrator type="path"/>)", sensor,
                                    MovingRight + R"(<emitter type="area"><rgb name="radiance" value="1"/></emitter>)")),
                      Catch::Contains("an animated shape cannot be an emitter"));
    CHECK_THROWS_WITH(
        load(crossing("", sensor, R"(<animation name="to_world"><transform time="1"/><transform time="0.5"/></animation>)")),
        Catch::Contains("keyframe times must increase"));
    CHECK_THROWS_WITH(load(crossing("", sensor, R"(<animation name="to_world"/>)")),
                      Catch::Contains("needs at least one"));
    CHECK_THROWS_WITH(load(R"(<scene version="3.0.0"><emitter type="point"><animation name="to_world">
        <transform time="0"/><transform time="1"><translate x="1"/></transform></animation></emitter></scene>)"),
                      Catch::Contains("is an <animation>, but emitter 'point' does not move"));
    CHECK_THROWS_WITH(load(R"(<scene version="3.0.0"><sensor type="perspective"><float name="shutter_open" value="1"/>
        <float name="shutter_close" value="0.5"/></sensor></scene>)"),
                      Catch::Contains("'shutter_close' = 0.5 is before 'shutter_open' = 1"));
}
