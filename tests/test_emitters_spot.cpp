// Emitters after Mitsuba 3: spot (Mitsuba's falloff curve, cutoff, inverse-square law,
// cone power, texture) and projector (irradiance normalisation, frustum, emission). Images
// are written as PFM files. Every Monte Carlo check is seeded and states its tolerance
// (a number of standard errors).
#include "emitter_helpers.hpp"

#include "effigi/core/error.hpp"
#include "effigi/math/rng.hpp"

#include <catch2/catch.hpp>

using namespace effigi;
using namespace effigi::test;

// ---------------------------------------------------------------- spot

namespace {
/// The intensity the spot sends at angle θ (degrees) from its axis, at distance dist:
/// the sample's L times dist² (undoing the inverse-square law).
float spotIntensity(const IEmitter& e, float thetaDeg, float dist = 2.f) {
    float t = degToRad(thetaDeg);
    Point3f ref = dist * Vector3f(std::sin(t), 0.f, std::cos(t));
    EmitterSample es = e.sampleDirect(ref, {0.5f, 0.5f}, Green);
    REQUIRE(es.delta);
    return es.L[0] * dist * dist;
}
} // namespace

TEST_CASE("spot: Mitsuba's falloff, linear in angle between beam width and cutoff", "[emitter][spot]") {
    auto e = makeEmitter("spot", {{"intensity", flat(5.0)}, {"cutoff_angle", 30.0}, {"beam_width", 10.0}});
    CHECK(e->flags() == EmitterDeltaPosition);
    CHECK(spotIntensity(*e, 0.f) == Approx(5.f));
    CHECK(spotIntensity(*e, 9.9f) == Approx(5.f));
    for (float theta : {12.f, 20.f, 25.f, 29.f})
        CHECK(spotIntensity(*e, theta) == Approx(5.f * (30.f - theta) / 20.f).epsilon(1e-4));
    CHECK(spotIntensity(*e, 30.1f) == 0.f);
    CHECK(spotIntensity(*e, 90.f) == 0.f);
    CHECK(spotIntensity(*e, 180.f) == 0.f);
}

TEST_CASE("spot: inverse-square law, placement and aim by to_world", "[emitter][spot]") {
    Transform toWorld = Transform::lookAt(Point3f(1.f, 2.f, 3.f), Point3f(1.f, 2.f, -3.f), Vector3f(0.f, 1.f, 0.f));
    auto e = makeEmitter("spot", {{"intensity", flat(4.0)}, {"to_world", toWorld}});
    for (float dist : {0.5f, 1.f, 3.f, 10.f}) {
        EmitterSample es = e->sampleDirect(Point3f(1.f, 2.f, 3.f - dist), {0.1f, 0.9f}, Green);
        CHECK(es.L[0] == Approx(4.f / (dist * dist)));
        CHECK(es.dist == Approx(dist));
        CHECK(length(es.wi - Vector3f(0.f, 0.f, 1.f)) < 1e-5f);
    }
    // Behind the light (the lookAt points it along −z): dark.
    CHECK(e->sampleDirect(Point3f(1.f, 2.f, 5.f), {0.5f, 0.5f}, Green).L[0] == 0.f);
    // Default beam width ¾ of the default cutoff (20°): full at 14.9°, dimmer at 16°.
    auto d = makeEmitter("spot", {{"intensity", flat(1.0)}});
    CHECK(spotIntensity(*d, 14.9f) == Approx(1.f));
    CHECK(spotIntensity(*d, 17.5f) == Approx(0.5f).epsilon(1e-4));
    CHECK(spotIntensity(*d, 20.5f) == 0.f);
}

TEST_CASE("spot: emission samples integrate to the cone's power", "[emitter][spot]") {
    for (auto [cutoff, beam] : {std::pair{30.0, 10.0}, std::pair{60.0, 60.0}, std::pair{5.0, 0.0}}) {
        auto e = makeEmitter("spot", {{"cutoff_angle", cutoff}, {"beam_width", beam}, {"intensity", flat(1.0)}});
        // ∫ I(ω) dω estimated as the mean of L / pdf over emission samples; 5 standard
        // errors (a false alarm has probability < 1e-6).
        PCG32 rng(11, 2);
        const int n = 100000;
        double sum = 0, sum2 = 0;
        for (int i = 0; i < n; ++i) {
            EmissionSample es = e->sampleEmission({0.5f, 0.5f}, {rng.nextFloat(), rng.nextFloat()}, Green);
            REQUIRE(es.pdfDirection > 0.f);
            double v = es.L[0] / es.pdfDirection;
            sum += v, sum2 += v * v;
        }
        double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
        INFO("cutoff " << cutoff << " beam " << beam << ": MC " << mean << " ± " << se << ", power " << e->power());
        CHECK(std::abs(mean - e->power()) <= 5.0 * se + 1e-5 * mean);
    }
}

TEST_CASE("spot: a texture is read at Mitsuba's uv across the cone", "[emitter][spot]") {
    // 2 × 2 image: top-left white, top-right black, bottom row grey (0.25). Mitsuba's spot
    // maps the local direction (x, y, z) to uv = ½ + ½ (x, y) / (z tan cutoff): +x is the
    // image's right, +y its bottom.
    TempImage img("slide", 2, 2, [](int x, int y) { return y == 0 ? Vector3f(x == 0 ? 1.f : 0.f) : Vector3f(0.25f); });
    Properties tp("texture", "bitmap");
    tp.set("filename", img.path.string());
    tp.set("filter_type", std::string("nearest"));
    Ref<IComponent> tex = Registry::instance().create("texture", "bitmap", tp);
    auto e = makeEmitter("spot", {{"cutoff_angle", 40.0}, {"beam_width", 40.0}, {"intensity", flat(2.0)},
                                  {"texture", ComponentValue{"texture", tex}}});
    auto at = [&](float x, float y) {
        return e->sampleDirect(Point3f(x, y, 1.f) * 2.f, {0.5f, 0.5f}, Green).L[0] * 4.f * (1.f + x * x + y * y);
    };
    float t = 0.5f * std::tan(degToRad(40.f));  // halfway to the cone's edge
    CHECK(at(-t, -t) == Approx(2.f).epsilon(1e-3));       // u < ½, v < ½: white
    CHECK(at(t, -t) == Approx(0.f).margin(1e-4));         // u > ½: black
    CHECK(at(-t, t) == Approx(0.5f).epsilon(1e-2));       // v > ½: grey
    CHECK(at(t, t) == Approx(0.5f).epsilon(1e-2));
}

TEST_CASE("spot: bad parameters are errors", "[emitter][spot]") {
    CHECK_THROWS_AS(makeEmitter("spot", {{"cutoff_angle", 20.0}, {"beam_width", 25.0}}), Error);
    CHECK_THROWS_AS(makeEmitter("spot", {{"cutoff_angle", 0.0}}), Error);
    // Below 0.5° float cannot hold the cone (1 − cos rounds away; at 1e-3° the light was dark).
    CHECK_THROWS_AS(makeEmitter("spot", {{"cutoff_angle", 0.01}}), Error);
    CHECK_THROWS_AS(makeEmitter("spot", {{"cutoff_angle", 200.0}}), Error);
    CHECK_THROWS_AS(makeEmitter("spot", {{"intensity", -1.0}}), Error);
}

// ---------------------------------------------------------------- projector

TEST_CASE("projector: the plane z = 1 receives pi * scale * irradiance inside the frustum", "[emitter][projector]") {
    // fov 90 along x and a constant (1 x 1) texture: the image spans [-1, 1]² at z = 1.
    auto e = makeEmitter("projector", {{"fov", 90.0}, {"scale", 2.0}, {"irradiance", flat(1.5)}});
    CHECK(e->flags() == EmitterDeltaPosition);
    for (Point2f xy : {Point2f(0.f), Point2f(0.9f, 0.f), Point2f(-0.5f, 0.95f), Point2f(0.99f, -0.99f)}) {
        Point3f ref(xy.x, xy.y, 1.f);
        EmitterSample es = e->sampleDirect(ref, {0.5f, 0.5f}, Green);
        REQUIRE(es.delta);
        // Irradiance on the plane (normal −z, facing the projector at the origin).
        float E = es.L[0] * dot(es.wi, Vector3f(0.f, 0.f, -1.f));
        CHECK(E == Approx(Pi * 2.f * 1.5f).epsilon(1e-4));
        // Inverse-square law along the same ray: twice as far, a quarter of the intensity.
        EmitterSample far = e->sampleDirect(2.f * ref, {0.5f, 0.5f}, Green);
        CHECK(far.L[0] == Approx(es.L[0] / 4.f).epsilon(1e-4));
    }
    for (Point3f outside : {Point3f(1.1f, 0.f, 1.f), Point3f(0.f, -1.2f, 1.f), Point3f(0.f, 0.f, -1.f)})
        CHECK(e->sampleDirect(outside, {0.5f, 0.5f}, Green).L[0] == 0.f);
}

TEST_CASE("projector: fov_axis and to_world place the frustum", "[emitter][projector]") {
    Transform toWorld = Transform::lookAt(Point3f(0.f, 0.f, 5.f), Point3f(0.f, 0.f, 0.f), Vector3f(0.f, 1.f, 0.f));
    auto e = makeEmitter("projector", {{"fov", 60.0}, {"fov_axis", std::string("y")}, {"to_world", toWorld}});
    // 5 units below the light, the image's half extent is 5 tan 30° on both axes (aspect 1).
    float h = 5.f * std::tan(degToRad(30.f));
    CHECK(e->sampleDirect(Point3f(0.f, 0.97f * h, 0.f), {0.5f, 0.5f}, Green).L[0] > 0.f);
    CHECK(e->sampleDirect(Point3f(0.f, 1.03f * h, 0.f), {0.5f, 0.5f}, Green).L[0] == 0.f);
    CHECK(e->sampleDirect(Point3f(-0.97f * h, 0.f, 0.f), {0.5f, 0.5f}, Green).L[0] > 0.f);
    CHECK(e->sampleDirect(Point3f(-1.03f * h, 0.f, 0.f), {0.5f, 0.5f}, Green).L[0] == 0.f);
    CHECK(e->sampleDirect(Point3f(0.f, 0.f, 10.f), {0.5f, 0.5f}, Green).L[0] == 0.f);  // behind
}

TEST_CASE("projector: emission samples carry the flux through the image", "[emitter][projector]") {
    auto e = makeEmitter("projector", {{"fov", 70.0}, {"scale", 3.0}, {"irradiance", flat(1.0)}});
    float hx = std::tan(degToRad(35.f));
    PCG32 rng(13, 1);
    double sum = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        EmissionSample es = e->sampleEmission({0.5f, 0.5f}, {rng.nextFloat(), rng.nextFloat()}, Green);
        REQUIRE(es.pdfDirection > 0.f);
        // The ray's direction must lie in the frustum, where sampleDirect sees the same intensity.
        Point3f ref = es.ray(3.f);
        EmitterSample ds = e->sampleDirect(ref, {0.5f, 0.5f}, Green);
        REQUIRE(ds.L[0] * 9.f == Approx(es.L[0]).epsilon(1e-3));
        sum += es.L[0] / es.pdfDirection;
    }
    // ∫ I dω over the frustum = ∫ E dA over the plane z = 1 = π · scale · (2 hx)².
    CHECK(sum / n == Approx(Pi * 3.f * 4.f * hx * hx).epsilon(1e-3));
    CHECK(e->power() == Approx(Pi * 3.f * 4.f * hx * hx).epsilon(1e-3));
}

TEST_CASE("projector: bad parameters are errors", "[emitter][projector]") {
    CHECK_THROWS_AS(makeEmitter("projector", {{"fov", 180.0}}), Error);
    CHECK_THROWS_AS(makeEmitter("projector", {{"fov", 40.0}, {"focal_length", std::string("50mm")}}), Error);
    CHECK_THROWS_AS(makeEmitter("projector", {{"scale", -1.0}}), Error);
    CHECK_THROWS_AS(makeEmitter("projector", {{"to_world", Transform::scale(Vector3f(0.f))}}), Error);
}
