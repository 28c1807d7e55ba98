// Emitters: area lights on a rectangle (sampling densities, irradiance against Lambert's
// closed form, one-sidedness, emission sampling, error cases), point lights (inverse
// square law, placement) and the constant environment (irradiance π·L, bounding
// sphere). Monte Carlo checks are seeded; tolerances are stated where they are used.
#include "emitter_helpers.hpp"

#include "effigi/interfaces/ishape.hpp"
#include "effigi/math/rng.hpp"

#include <catch2/catch.hpp>

using namespace effigi;
using namespace effigi::test;

namespace {

/// A unit square [-½,½]² at z = 0, normal +z, carrying the given emitter.
Ref<IShape> makeUnitSquare(const Ref<IEmitter>& emitter) {
    Properties p("shape", "rectangle");
    p.set("to_world", Transform::scale(Vector3f(0.5f, 0.5f, 1.f)));
    p.set("emitter", ComponentValue{"emitter", emitter});
    Ref<IShape> s = query<IShape>(Registry::instance().create("shape", "rectangle", p));
    REQUIRE(s);
    return s;
}

/// Irradiance at x (normal nx) from a uniformly emitting polygon of radiance L entirely
/// above x's tangent plane: Lambert's formula E = L · ½ Σ_i Θ_i (n · Γ_i), with Θ_i the
/// angle edge i subtends at x and Γ_i the unit normal of the plane through x and the edge
/// (J. H. Lambert 1760; see Arvo, "The Irradiance Jacobian for Partially Occluded
/// Polyhedral Sources", SIGGRAPH 1994, eq. 3).
double lambertIrradiance(const std::vector<Vector3d>& poly, const Vector3d& x, const Vector3d& nx, double L) {
    double sum = 0.0;
    for (std::size_t i = 0; i < poly.size(); ++i) {
        Vector3d a = glm::normalize(poly[i] - x), b = glm::normalize(poly[(i + 1) % poly.size()] - x);
        double theta = std::acos(std::clamp(glm::dot(a, b), -1.0, 1.0));
        Vector3d gamma = glm::normalize(glm::cross(a, b));
        sum += theta * glm::dot(nx, gamma);
    }
    return 0.5 * L * std::abs(sum);
}

struct McResult {
    double mean = 0, stderr_ = 0;
};

/// Irradiance at ref (normal n) estimated by light sampling: E ≈ mean of L cos/pdf.
McResult irradianceByLightSampling(const IEmitter& e, const Point3f& ref, const Vector3f& n, int count,
                                   std::uint64_t seed) {
    PCG32 rng(seed, 11);
    auto lambda = SampledWavelengths::constant(550.f);
    double sum = 0, sum2 = 0;
    for (int i = 0; i < count; ++i) {
        EmitterSample es = e.sampleDirect(ref, {rng.nextFloat(), rng.nextFloat()}, lambda);
        double v = 0;
        if (es.pdf > 0.f) v = double(es.L[0]) * std::max(0.f, dot(n, es.wi)) / (es.delta ? 1.0 : double(es.pdf));
        sum += v;
        sum2 += v * v;
    }
    McResult r;
    r.mean = sum / count;
    r.stderr_ = std::sqrt(std::max(0.0, sum2 / count - r.mean * r.mean) / count);
    return r;
}

} // namespace

TEST_CASE("area emitter: irradiance from a unit square matches Lambert's formula", "[emitter]") {
    auto light = makeEmitter("area", {{"radiance", flat(1.0)}});
    auto square = makeUnitSquare(light);
    light->preprocess(square->bbox());
    CHECK(light->flags() == EmitterSurface);
    CHECK(light->power() == Approx(Pi));  // π · area 1 · radiance 1

    std::vector<Vector3d> poly{{-0.5, -0.5, 0}, {0.5, -0.5, 0}, {0.5, 0.5, 0}, {-0.5, 0.5, 0}};
    struct Receiver {
        Point3f p;
        Vector3f n;
    };
    std::vector<Receiver> receivers{
        {{0.f, 0.f, 1.f}, {0.f, 0.f, -1.f}},
        {{0.3f, -0.2f, 0.5f}, {0.f, 0.f, -1.f}},
        {{1.2f, 0.7f, 0.8f}, glm::normalize(Vector3f(-0.6f, -0.3f, -1.f))},
        {{0.f, 0.f, 0.2f}, {0.f, 0.f, -1.f}},  // close: most of the hemisphere
    };
    for (const auto& r : receivers) {
        double exact = lambertIrradiance(poly, Vector3d(r.p), Vector3d(r.n), 1.0);
        McResult mc = irradianceByLightSampling(*light, r.p, r.n, 1000000, 5);
        INFO("receiver at " << r.p.x << "," << r.p.y << "," << r.p.z << ": exact " << exact << ", MC " << mc.mean
                            << " ± " << mc.stderr_);
        // Seeded; within 4 standard errors, which are small enough (< 0.3%) for the
        // comparison to mean something, and within 1%.
        CHECK(std::abs(mc.mean - exact) < 4.0 * mc.stderr_);
        CHECK(mc.stderr_ < 0.003 * exact);
        CHECK(mc.mean == Approx(exact).epsilon(0.01));
    }
}

TEST_CASE("area emitter: sampleDirect pdf equals pdfDirect, eval is one-sided", "[emitter]") {
    auto light = makeEmitter("area", {{"radiance", flat(3.0)}});
    auto square = makeUnitSquare(light);
    light->preprocess(square->bbox());
    auto lambda = SampledWavelengths::sampleVisible(0.2f);
    PCG32 rng(9, 1);
    Point3f ref(0.4f, 0.9f, 1.3f);
    for (int i = 0; i < 1000; ++i) {
        EmitterSample es = light->sampleDirect(ref, {rng.nextFloat(), rng.nextFloat()}, lambda);
        REQUIRE(es.pdf > 0.f);
        CHECK_FALSE(es.delta);
        CHECK(length(es.wi) == Approx(1.f).epsilon(1e-5));
        CHECK(length(es.p - (ref + es.dist * es.wi)) < 1e-4f);
        CHECK(es.L[0] == Approx(3.f));
        SurfaceInteraction si;
        si.p = es.p;
        si.n = es.n;
        si.wo = -es.wi;
        CHECK(light->pdfDirect(ref, si) == Approx(es.pdf).epsilon(1e-3));
        CHECK(light->eval(si, lambda)[1] == Approx(3.f));
        si.wo = es.wi;  // the back of the light
        CHECK(light->eval(si, lambda).isBlack());
        CHECK(light->pdfDirect(ref, si) == 0.f);
    }
}

TEST_CASE("area emitter: the back side is dark", "[emitter]") {
    auto light = makeEmitter("area", {{"radiance", flat(1.0)}});
    auto square = makeUnitSquare(light);
    light->preprocess(square->bbox());
    McResult mc = irradianceByLightSampling(*light, {0.1f, 0.f, -1.f}, {0.f, 0.f, 1.f}, 1000, 3);
    CHECK(mc.mean == 0.0);
    auto lambda = SampledWavelengths::constant(500.f);
    EmitterSample es = light->sampleDirect({0.1f, 0.f, -1.f}, {0.3f, 0.3f}, lambda);
    CHECK(es.pdf == 0.f);
    CHECK(es.L.isBlack());
}

TEST_CASE("area emitter: emission samples leave the front cosine-weighted", "[emitter]") {
    auto light = makeEmitter("area", {{"radiance", flat(2.0)}});
    auto square = makeUnitSquare(light);
    auto lambda = SampledWavelengths::constant(600.f);
    PCG32 rng(4, 2);
    double cosSum = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        EmissionSample es = light->sampleEmission({rng.nextFloat(), rng.nextFloat()}, {rng.nextFloat(), rng.nextFloat()},
                                                  lambda);
        REQUIRE(es.pdfDirection > 0.f);
        CHECK(es.pdfPosition == Approx(1.f));  // 1 / area
        CHECK(es.ray.d.z > 0.f);
        CHECK(es.pdfDirection == Approx(es.ray.d.z * InvPi).epsilon(1e-4));
        CHECK(std::abs(es.ray.o.x) <= 0.5f + 1e-4f);
        CHECK(std::abs(es.ray.o.z) < 1e-4f);
        CHECK(es.L[0] == Approx(2.f));
        cosSum += es.ray.d.z;
    }
    // E[cos θ] under a cosine-weighted density is 2/3 (standard error ≈ 0.0017).
    CHECK(cosSum / n == Approx(2.0 / 3.0).margin(0.007));
}

TEST_CASE("area emitter: misuse is an error, never a crash", "[emitter]") {
    auto loose = makeEmitter("area", {{"radiance", flat(1.0)}});
    auto lambda = SampledWavelengths::constant(550.f);
    EmitterSample es = loose->sampleDirect({0.f, 0.f, 1.f}, {0.5f, 0.5f}, lambda);
    CHECK(es.pdf == 0.f);
    CHECK(loose->power() == 0.f);
    (void)loose->sampleEmission({0.5f, 0.5f}, {0.5f, 0.5f}, lambda);
    CHECK_THROWS_WITH(loose->preprocess(BBox3f()), Catch::Contains("nested in a shape"));

    // One emitter cannot belong to two shapes.
    auto shared = makeEmitter("area", {{"radiance", flat(1.0)}});
    auto first = makeUnitSquare(shared);
    CHECK_THROWS_AS(makeUnitSquare(shared), Error);

    // Only area emitters can be attached.
    auto point = makeEmitter("point");
    Properties p("shape", "rectangle");
    p.set("emitter", ComponentValue{"emitter", point});
    CHECK_THROWS_WITH(Registry::instance().create("shape", "rectangle", p), Catch::Contains("cannot be attached"));
}

TEST_CASE("point emitter: inverse-square law and placement", "[emitter]") {
    auto light = makeEmitter("point", {{"position", PointValue{{1.f, 2.f, 3.f}}}, {"intensity", flat(5.0)}});
    CHECK(light->flags() == EmitterDeltaPosition);
    CHECK(light->isDelta());
    CHECK(light->power() == Approx(4.0 * M_PI * 5.0));
    auto lambda = SampledWavelengths::sampleVisible(0.6f);
    for (float d : {0.5f, 2.f, 10.f}) {
        Point3f ref(1.f, 2.f, 3.f - d);
        EmitterSample es = light->sampleDirect(ref, {0.3f, 0.7f}, lambda);
        CHECK(es.delta);
        CHECK(es.pdf == 1.f);
        CHECK(es.dist == Approx(d));
        CHECK(es.wi.z == Approx(1.f));
        CHECK(es.L[0] == Approx(5.f / (d * d)));
        CHECK(es.L[3] == Approx(5.f / (d * d)));
    }
    // At the light itself: no sample, no NaN.
    EmitterSample at = light->sampleDirect({1.f, 2.f, 3.f}, {0.3f, 0.7f}, lambda);
    CHECK(at.pdf == 0.f);
    CHECK(at.L.isFinite());

    // to_world's translation places it the same way.
    auto moved = makeEmitter("point", {{"to_world", Transform::translate({1.f, 2.f, 3.f})}, {"intensity", flat(5.0)}});
    EmitterSample es = moved->sampleDirect({1.f, 2.f, 1.f}, {0.f, 0.f}, lambda);
    CHECK(es.dist == Approx(2.f));
    CHECK(es.L[0] == Approx(1.25f));

    Properties both("emitter", "point");
    both.set("position", PointValue{{0.f, 0.f, 0.f}});
    both.set("to_world", Transform::translate({1.f, 0.f, 0.f}));
    CHECK_THROWS_AS(Registry::instance().create("emitter", "point", both), Error);

    // Emission: uniform directions from the light's position.
    PCG32 rng(8, 8);
    Vector3f meanDir(0.f);
    for (int i = 0; i < 10000; ++i) {
        EmissionSample em = light->sampleEmission({0.5f, 0.5f}, {rng.nextFloat(), rng.nextFloat()}, lambda);
        CHECK(em.ray.o == Point3f(1.f, 2.f, 3.f));
        CHECK(em.pdfDirection == Approx(Inv4Pi));
        meanDir += em.ray.d / 10000.f;
    }
    CHECK(length(meanDir) < 0.04f);  // |mean| of 1e4 uniform unit vectors: ~0.01
}

TEST_CASE("constant environment: irradiance π·L, sampling consistent", "[emitter]") {
    auto env = makeEmitter("constant", {{"radiance", flat(2.0)}});
    CHECK(env->isInfinite());
    BBox3f bounds(Point3f(-1.f, 0.f, -2.f), Point3f(3.f, 1.f, 2.f));
    env->preprocess(bounds);
    Point3f ref(0.5f, 0.5f, 0.f);
    for (Vector3f n : {Vector3f(0, 0, 1), glm::normalize(Vector3f(1, -2, 0.5f))}) {
        McResult mc = irradianceByLightSampling(*env, ref, n, 200000, 17);
        INFO("E = " << mc.mean << " ± " << mc.stderr_);
        CHECK(std::abs(mc.mean - 2.0 * M_PI) < 4.0 * mc.stderr_);  // seeded; 4 standard errors
        CHECK(mc.mean == Approx(2.0 * M_PI).epsilon(0.01));
    }
    auto lambda = SampledWavelengths::constant(450.f);
    float radius = bounds.boundingRadius();
    for (int i = 0; i < 100; ++i) {
        Point2f u((i + 0.5f) / 100.f, 0.37f);
        EmitterSample es = env->sampleDirect(ref, u, lambda);
        CHECK(std::isinf(es.dist));
        CHECK(es.pdf == Approx(env->pdfEnvironment(ref, es.wi)));
        CHECK(env->evalEnvironment(es.wi, lambda)[0] == Approx(2.f));
        // The stand-in point is outside the scene's bounding sphere, along wi.
        CHECK(length(es.p - bounds.center()) > radius);
        CHECK(dot(glm::normalize(es.p - ref), es.wi) == Approx(1.f).epsilon(1e-4));

        // Emission rays start outside the sphere and head through it.
        EmissionSample em = env->sampleEmission({0.5f, (i + 0.5f) / 100.f}, u, lambda);
        Vector3f toCenter = bounds.center() - em.ray.o;
        CHECK(length(toCenter) >= radius * (1.f - 1e-5f));
        float missDistance = length(toCenter - dot(toCenter, em.ray.d) * em.ray.d);
        CHECK(missDistance <= radius * (1.f + 1e-5f));
        CHECK(dot(toCenter, em.ray.d) > 0.f);
        CHECK(em.pdfPosition == Approx(1.f / (Pi * radius * radius)));
        CHECK(em.pdfDirection == Approx(Inv4Pi));
    }
    CHECK(env->power() > 0.f);

    // A degenerate scene still gets a usable sphere.
    auto tiny = makeEmitter("constant");
    tiny->preprocess(BBox3f(Point3f(1.f), Point3f(1.f)));
    EmissionSample em = tiny->sampleEmission({0.3f, 0.3f}, {0.2f, 0.9f}, lambda);
    CHECK(std::isfinite(em.pdfPosition));
    CHECK(em.pdfPosition > 0.f);
    tiny->preprocess(BBox3f());
    CHECK(std::isfinite(tiny->sampleEmission({0.3f, 0.3f}, {0.2f, 0.9f}, lambda).pdfPosition));
}

TEST_CASE("emission given as a bare number is a grey of the colour space (Mitsuba's scaled D65)", "[emitter]") {
    // Mitsuba 3's spectral variants read <float name="radiance" value="v"/> as v · D65
    // (normalised), the same as <rgb value="v, v, v"/>, and <spectrum value="v"/> as flat.
    auto number = makeEmitter("constant", {{"radiance", 2.0}});
    auto grey = makeEmitter("constant", {{"radiance", RGBValue{Vector3f(2.f)}}});
    auto flatEnv = makeEmitter("constant", {{"radiance", flat(2.0)}});
    for (float l : {400.f, 450.f, 550.f, 650.f, 700.f}) {
        auto lambda = SampledWavelengths::constant(l);
        Vector3f d(0.f, 0.f, 1.f);
        INFO("lambda " << l);
        CHECK(number->evalEnvironment(d, lambda)[0] == Approx(grey->evalEnvironment(d, lambda)[0]).epsilon(1e-5));
        CHECK(flatEnv->evalEnvironment(d, lambda)[0] == Approx(2.f));
    }
    // D65 is not flat: blue and red ends differ (Mitsuba: 1.18 at 450 nm, 0.81 at 650 nm per unit).
    float blue = number->evalEnvironment({0.f, 0.f, 1.f}, SampledWavelengths::constant(450.f))[0];
    float red = number->evalEnvironment({0.f, 0.f, 1.f}, SampledWavelengths::constant(650.f))[0];
    CHECK(blue / red == Approx(1.18193 / 0.808373).epsilon(0.03));
}
