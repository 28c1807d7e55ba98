// Emitters after Mitsuba 3: directional (parallel light, emission from the bounding
// disk), and small scenes rendered by effigi and Mitsuba 3 (tests/data/emitters) for the
// directional, spot, envmap and projector emitters. Spot and projector are tested in
// test_emitters_spot.cpp, envmap in test_emitters_envmap.cpp. Every Monte Carlo check is
// seeded and states its tolerance (a number of standard errors) or significance level.
#include "emitter_helpers.hpp"
#include "image_helpers.hpp"

#include "effigi/core/error.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/xml/loader.hpp"

#include <catch2/catch.hpp>

using namespace effigi;
using namespace effigi::test;

// ---------------------------------------------------------------- directional

TEST_CASE("directional: parallel light of constant irradiance", "[emitter][directional]") {
    auto e = makeEmitter("directional", {{"direction", VectorValue{Vector3f(0.f, 0.f, -2.f)}},
                                         {"irradiance", flat(3.0)}});
    e->preprocess(BBox3f(Point3f(-1.f), Point3f(1.f)));
    CHECK(e->flags() == (EmitterDeltaDirection | EmitterInfinite));
    for (Point3f ref : {Point3f(0.f), Point3f(5.f, -3.f, 2.f), Point3f(100.f, 0.f, 0.f)}) {
        EmitterSample es = e->sampleDirect(ref, {0.3f, 0.7f}, Green);
        CHECK(es.delta);
        CHECK(es.pdf == 1.f);
        CHECK(std::isinf(es.dist));
        CHECK(es.wi.z == Approx(1.f));  // toward the light: against its travel direction
        CHECK(es.L[0] == Approx(3.f));
        // The stand-in light point lies beyond the scene, in the direction of the light.
        CHECK(length(es.p) > std::sqrt(3.f));
    }
    // Never hit by an escaping ray.
    CHECK(e->evalEnvironment(Vector3f(0.f, 0.f, 1.f), Green)[0] == 0.f);
    CHECK(e->pdfEnvironment(Point3f(0.f), Vector3f(0.f, 0.f, 1.f)) == 0.f);
}

TEST_CASE("directional: to_world aims the light like direction does", "[emitter][directional]") {
    auto viaTransform = makeEmitter("directional", {{"to_world", Transform::rotate(Vector3f(1.f, 0.f, 0.f), 90.f)}});
    Vector3f d = Transform::rotate(Vector3f(1.f, 0.f, 0.f), 90.f).vector(Vector3f(0.f, 0.f, 1.f));
    auto viaDirection = makeEmitter("directional", {{"direction", VectorValue{d}}});
    for (auto& e : {viaTransform, viaDirection}) e->preprocess(BBox3f(Point3f(-1.f), Point3f(1.f)));
    Vector3f a = viaTransform->sampleDirect(Point3f(0.f), {0.5f, 0.5f}, Green).wi;
    Vector3f b = viaDirection->sampleDirect(Point3f(0.f), {0.5f, 0.5f}, Green).wi;
    CHECK(length(a - b) < 1e-6f);
    CHECK(length(a + d) < 1e-6f);
}

TEST_CASE("directional: emission rays cover the scene's bounding disk", "[emitter][directional]") {
    auto e = makeEmitter("directional", {{"direction", VectorValue{Vector3f(1.f, 1.f, 0.f)}}, {"irradiance", flat(2.0)}});
    BBox3f bounds(Point3f(-1.f, 0.f, 2.f), Point3f(3.f, 2.f, 4.f));
    e->preprocess(bounds);
    Point3f c = bounds.center();
    float r = bounds.boundingRadius();
    Vector3f d = normalize(Vector3f(1.f, 1.f, 0.f));
    PCG32 rng(7, 1);
    for (int i = 0; i < 200; ++i) {
        EmissionSample es = e->sampleEmission({rng.nextFloat(), rng.nextFloat()}, {0.5f, 0.5f}, Green);
        CHECK(length(es.ray.d - d) < 1e-5f);
        // The origin lies behind the centre by one radius, within one radius of the axis.
        Vector3f o = es.ray.o - c;
        CHECK(dot(o, d) == Approx(-r).margin(1e-4f));
        CHECK(length(o - dot(o, d) * d) <= r * (1.f + 1e-5f));
        CHECK(es.pdfPosition == Approx(1.f / (Pi * r * r)));
        CHECK(es.L[0] == Approx(2.f));
    }
    // Flux through the disk: π r² E.
    CHECK(e->power() == Approx(Pi * r * r * 2.f).epsilon(1e-3));
}

TEST_CASE("directional: bad parameters are errors", "[emitter][directional]") {
    CHECK_THROWS_AS(makeEmitter("directional", {{"direction", VectorValue{Vector3f(0.f)}}}), Error);
    CHECK_THROWS_AS(makeEmitter("directional", {{"direction", VectorValue{Vector3f(0.f, 0.f, 1.f)}},
                                                {"to_world", Transform::translate(Vector3f(1.f))}}),
                    Error);
    CHECK_THROWS_AS(makeEmitter("directional", {{"irradiance", -1.0}}), Error);
}

// ---------------------------------------------------------------- end to end

namespace {

/// Per-pixel RGB of an effigi render of tests/data/emitters/<name>.xml at `spp`.
test::ExrImage renderScene(const std::string& name, int spp) {
    xml::ParseOptions opt;
    opt.defines = {{"spp", std::to_string(spp)}};
    auto scene = loadSceneFile(EFFIGI_SOURCE_DIR "/tests/data/emitters/" + name + ".xml", opt);
    RenderControl control;
    control.progress = false;
    RenderStats stats = scene->renderer().render(*scene, control);
    CHECK(stats.rejectedSamples == 0);
    Image img = scene->camera().film().develop();
    test::ExrImage out;
    out.spec = OIIO::ImageSpec(img.width, img.height, 3, OIIO::TypeDesc::FLOAT);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 3; ++c) out.px.push_back(img.at(x, y, c));
    return out;
}

struct BlockStats {
    double mean = 0, stderr_ = 0;
};

/// Mean of channel c (−1: the mean of R, G, B) over the block [x0, x1) × [y0, y1), and
/// its standard error from differences of horizontally adjacent pixels: with a box
/// filter pixels are independent, so σ² ≈ ⟨(p(x) − p(x+1))²⟩ / 2 (an overestimate where
/// the image itself varies, which only widens the tolerance).
BlockStats blockStats(const test::ExrImage& img, int c, int x0, int y0, int x1, int y1) {
    auto v = [&](int x, int y) {
        return c >= 0 ? double(img.at(x, y, c)) : (img.at(x, y, 0) + img.at(x, y, 1) + img.at(x, y, 2)) / 3.0;
    };
    double sum = 0, diff2 = 0;
    int n = 0, nd = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            sum += v(x, y);
            ++n;
            if (x + 1 < x1) diff2 += sqr(float(v(x, y) - v(x + 1, y))), ++nd;
        }
    return {sum / n, std::sqrt(diff2 / (2.0 * std::max(nd, 1)) / n)};
}

/// effigi at 256 spp against Mitsuba 3 scalar_spectral at 4096 spp
/// (python3 bench/mitsuba_reference.py tests/data/emitters/<name>.xml
///  tests/data/emitters/<name>-mitsuba.exr --spp 4096).
/// Tolerances: per channel of the whole image 2 % + 4 standard errors of our estimate;
/// per 12 × 12 block (grey) 4 % of max(block, ¼ image mean) + 4 standard errors (the
/// floor keeps dark blocks from demanding relative precision). Four standard errors:
/// two-sided false alarm 6e-5 per comparison; the renders are seeded, so the outcome
/// is deterministic. The reference's own noise (16× the samples) is neglected.
void compareWithMitsuba(const std::string& name) {
    test::ExrImage ours = renderScene(name, 256);
    test::ExrImage ref = test::readExr(EFFIGI_SOURCE_DIR "/tests/data/emitters/" + name + "-mitsuba.exr");
    int w = ours.spec.width, h = ours.spec.height;
    REQUIRE(ref.spec.width == w);
    REQUIRE(ref.spec.height == h);
    double imageMean = blockStats(ref, -1, 0, 0, w, h).mean;
    REQUIRE(imageMean > 0.0);
    for (int c = 0; c < 3; ++c) {
        BlockStats a = blockStats(ours, c, 0, 0, w, h), b = blockStats(ref, c, 0, 0, w, h);
        double tol = 0.02 * b.mean + 4.0 * a.stderr_;
        INFO(name << " channel " << c << ": effigi " << a.mean << " ± " << a.stderr_ << ", mitsuba " << b.mean);
        CHECK(std::abs(a.mean - b.mean) <= tol);
    }
    const int B = 12;
    for (int y = 0; y + B <= h; y += B)
        for (int x = 0; x + B <= w; x += B) {
            BlockStats a = blockStats(ours, -1, x, y, x + B, y + B), b = blockStats(ref, -1, x, y, x + B, y + B);
            double tol = 0.04 * std::max(b.mean, 0.25 * imageMean) + 4.0 * a.stderr_;
            INFO(name << " block (" << x << ", " << y << "): effigi " << a.mean << " ± " << a.stderr_ << ", mitsuba "
                      << b.mean << ", tolerance " << tol);
            CHECK(std::abs(a.mean - b.mean) <= tol);
        }
}

} // namespace

TEST_CASE("directional: a lit sphere and floor agree with Mitsuba 3", "[emitter][directional][render]") {
    compareWithMitsuba("directional");
}

TEST_CASE("spot: the cone and its soft edge agree with Mitsuba 3", "[emitter][spot][render]") {
    compareWithMitsuba("spot");
}

TEST_CASE("envmap: background and lighting agree with Mitsuba 3", "[emitter][envmap][render]") {
    compareWithMitsuba("envmap");
}

TEST_CASE("projector: a projected slide agrees with Mitsuba 3", "[emitter][projector][render]") {
    compareWithMitsuba("projector");
}
