// Warps in use (issue 14), the lights and the camera: point, spot and constant emitters
// draw their emission directions (constant also its direct-lighting ones) and the thin
// lens its lens points through a warp; the area light's defaults are checked in
// test_warps_in_use.cpp, its nested warp's estimate here.
// - Defaults are the warp components' code, bit for bit: `uniform_sphere` for point and
//   constant, `uniform_cone` with cos_cutoff = cos(cutoff_angle) for spot (in its frame),
//   `square_to_disk` for the lens (with a ray weight of exactly 1); each also equals the
//   same component nested as <warp>.
// - A nested warp runs and keeps the estimates unbiased: the emitted intensity integrated
//   by L/pdf over sampled directions (4π I for the point light, I ∫ falloff dω for the
//   spot, π L for the area light's exitance), the constant light's irradiance π L, and
//   the thin lens' ray weights averaging to 1 (and weighting r² to its disk mean ½).
//   Tolerances are 4 standard errors of the seeded estimate (two-sided 6e-5 each; 11
//   checks: a false failure below 1e-3), plus float rounding; measured |z| <= 2.6, and
//   the two largest (constant, lens importance) at 0.3–1.6 over five 2M-sample seeds.
// The wrong-domain errors are checked in test_warps_in_use.cpp.
#include "camera_helpers.hpp"
#include "emitter_helpers.hpp"
#include "mc_mean.hpp"
#include "warps_in_use_helpers.hpp"

#include "effigi/interfaces/icamera_importance.hpp"
#include "effigi/math/frame.hpp"
#include "effigi/math/rng.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace effigi;
using namespace effigi::test;

namespace {

/// Whether an estimate (mean, standard error) lies within 4 standard errors of `expected`,
/// plus 1e-5 relative for float rounding (a default that is exact has no error at all).
bool agrees(std::pair<double, double> e, double expected) {
    return std::abs(e.first - expected) <= 4.0 * e.second + 1e-5 * std::abs(expected);
}

/// L / pdfDirection of the emission sample for uDir: an estimate of ∫ L dω.
double emittedOverPdf(const IEmitter& e, const Point2f& uDir) {
    EmissionSample es = e.sampleEmission(Point2f(0.5f), uDir, Green);
    return es.pdfDirection > 0.f ? double(es.L[0]) / es.pdfDirection : 0.0;
}

Ref<ICamera> lens(const Params& extra = {}) {
    Params p = {{"aperture_radius", 1.0}, {"focus_distance", 5.0}, {"fov", 40.0}};
    p.insert(p.end(), extra.begin(), extra.end());
    return makeCamera("thinlens", 32, 32, p);
}

} // namespace

TEST_CASE("warps in use: the lights' and the lens' default warps are the components' code, bit for bit",
          "[warp][emitter][camera]") {
    Ref<IWarp> sphere = makeWarp("uniform_sphere"), disk = makeWarp("square_to_disk");
    const float cosCutoff = std::cos(degToRad(20.f));  // spot's default cutoff_angle, as the spot computes it
    Properties coneProps("warp", "uniform_cone");
    coneProps.set("cos_cutoff", double(cosCutoff));
    Ref<IWarp> cone = query<IWarp>(Registry::instance().create("warp", "uniform_cone", coneProps));
    Ref<IEmitter> point = makeEmitter("point"), pointNested = makeEmitter("point", {{"warp", warpValue(sphere)}});
    Ref<IEmitter> spot = makeEmitter("spot"), spotNested = makeEmitter("spot", {{"warp", warpValue(cone)}});
    Ref<IEmitter> env = makeEmitter("constant");
    env->preprocess(BBox3f(Point3f(-1.f), Point3f(1.f)));
    Ref<ICamera> cam = lens(), camNested = lens({{"warp", warpValue(disk)}});
    PCG32 rng(1403, 1);  // seeded
    for (int i = 0; i < 50000; ++i) {
        const Point2f u(rng.nextFloat(), rng.nextFloat()), film(32.f * rng.nextFloat(), 32.f * rng.nextFloat());
        INFO("u = " << u.x << ", " << u.y);
        const Vector3f ws = sphere->sample(u), wc = cone->sample(u);
        EmissionSample a = point->sampleEmission(Point2f(0.5f), u, Green), b = pointNested->sampleEmission(Point2f(0.5f), u, Green);
        CHECK(sameBits(a.ray.d, ws));
        CHECK(sameBits(a.pdfDirection, sphere->pdf(ws)));
        CHECK((sameBits(b.ray.d, ws) && sameBits(b.pdfDirection, a.pdfDirection)));
        float pdfPos = 0.f, pdfDir = 0.f;
        point->pdfEmission(a.ray.o, a.n, a.ray.d, pdfPos, pdfDir);
        CHECK(sameBits(pdfDir, a.pdfDirection));
        a = spot->sampleEmission(Point2f(0.5f), u, Green), b = spotNested->sampleEmission(Point2f(0.5f), u, Green);
        CHECK(sameBits(a.pdfDirection, cone->pdf(wc)));
        CHECK((sameBits(b.ray.d, a.ray.d) && sameBits(b.pdfDirection, a.pdfDirection)));
        EmitterSample d = env->sampleDirect(Point3f(0.f), u, Green);
        CHECK((sameBits(d.wi, ws) && sameBits(d.pdf, sphere->pdf(ws)) && sameBits(env->pdfEnvironment({}, ws), d.pdf)));
        a = env->sampleEmission(Point2f(0.5f), u, Green);
        CHECK((sameBits(a.ray.d, ws) && sameBits(a.pdfDirection, d.pdf)));
        // The lens: generateRay alike with and without the nested warp, weight exactly 1;
        // the lens point (identity to_world, radius 1) is the disk warp's.
        CameraSample cs;
        cs.pFilm = film;
        cs.pLens = u;
        SampledSpectrum w1(0.f), w2(0.f);
        Ray r1 = cam->generateRay(cs, Green, w1), r2 = camNested->generateRay(cs, Green, w2);
        CHECK((sameBits(r1.o, r2.o) && sameBits(r1.d, r2.d) && sameBits(r1.tMax, r2.tMax)));
        CHECK((w1[0] == 1.f && w2[0] == 1.f));
        CameraImportanceSample c1, c2;
        const Point3f ref(0.2f, -0.1f, 3.f);
        REQUIRE(query<ICameraImportance>(cam)->sampleDirection(ref, u, c1));
        REQUIRE(query<ICameraImportance>(camNested)->sampleDirection(ref, u, c2));
        CHECK(sameBits(c1.pCamera, disk->sample(u)));
        CHECK((sameBits(c2.pCamera, c1.pCamera) && sameBits(c2.weight, c1.weight)));
    }
}

TEST_CASE("warps in use: a nested warp in a light keeps its estimates unbiased", "[warp][emitter]") {
    Ref<IWarp> tilted = std::make_shared<TiltedSphereWarp>();
    SECTION("point: ∫ I dω = 4π I, directions and densities the warp's") {
        Ref<IEmitter> plain = makeEmitter("point"), nested = makeEmitter("point", {{"warp", warpValue(tilted)}});
        const double I = plain->sampleEmission(Point2f(0.5f), Point2f(0.5f), Green).L[0];
        for (const auto& e : {plain, nested})
            CHECK(agrees(mcMean([&](Point2f u) { return emittedOverPdf(*e, u); }, 100000, 1), 4.0 * Pi * I));
        for (Point2f u : {Point2f(0.1f, 0.2f), Point2f(0.7f, 0.9f)}) {
            EmissionSample es = nested->sampleEmission(Point2f(0.5f), u, Green);
            float pdfPos = 0.f, pdfDir = 0.f;
            nested->pdfEmission(es.ray.o, es.n, es.ray.d, pdfPos, pdfDir);
            CHECK((sameBits(es.ray.d, tilted->sample(u)) && es.pdfDirection == tilted->pdf(es.ray.d) && pdfDir == es.pdfDirection));
        }
    }
    SECTION("spot in a wider cone: ∫ I falloff dω") {
        // The falloff (1 to 15°, linear in the angle to 0 at 20°) integrated by the midpoint rule.
        const double beam = 15.0 * std::numbers::pi / 180.0, cutoff = 20.0 * std::numbers::pi / 180.0;
        double solidAngle = 0.0;
        for (int k = 0; k < 100000; ++k) {
            double theta = (k + 0.5) * cutoff / 100000;
            double falloff = theta <= beam ? 1.0 : (cutoff - theta) / (cutoff - beam);
            solidAngle += falloff * 2.0 * std::numbers::pi * std::sin(theta) * cutoff / 100000;
        }
        Properties wide("warp", "uniform_cone");
        wide.set("cos_cutoff", 0.5);  // 60°: covers the 20° cone
        Ref<IWarp> w = query<IWarp>(Registry::instance().create("warp", "uniform_cone", wide));
        Ref<IEmitter> plain = makeEmitter("spot"), nested = makeEmitter("spot", {{"warp", warpValue(w)}});
        const double I = plain->sampleDirect(Point3f(0.f, 0.f, 1.f), Point2f(0.5f), Green).L[0];  // on the axis at 1
        for (const auto& e : {plain, nested})
            CHECK(agrees(mcMean([&](Point2f u) { return emittedOverPdf(*e, u); }, 200000, 2), I * solidAngle));
    }
    SECTION("constant: irradiance π L from direct lighting, emitted directions the warp's") {
        Ref<IEmitter> env = makeEmitter("constant", {{"warp", warpValue(tilted)}});
        env->preprocess(BBox3f(Point3f(-1.f), Point3f(1.f)));
        const double L = env->evalEnvironment(Vector3f(0.f, 0.f, 1.f), Green)[0];
        auto irradiance = mcMean([&](Point2f u) {
            EmitterSample es = env->sampleDirect(Point3f(0.f), u, Green);
            CHECK((sameBits(es.wi, tilted->sample(u)) && es.pdf == env->pdfEnvironment({}, es.wi)));
            return es.pdf > 0.f ? es.L[0] * std::max(0.f, es.wi.z) / es.pdf : 0.0;
        }, 100000, 3);
        CHECK(agrees(irradiance, Pi * L));
        EmissionSample es = env->sampleEmission(Point2f(0.3f), Point2f(0.6f, 0.2f), Green);
        CHECK((sameBits(es.ray.d, tilted->sample(Point2f(0.6f, 0.2f))) && es.pdfDirection == tilted->pdf(es.ray.d)));
    }
    SECTION("area: exitance π L through a warp on the whole sphere (the lower half is no sample)") {
        Ref<IEmitter> light = makeEmitter("area", {{"warp", warpValue(tilted)}});
        Ref<IShape> host = square(light);
        const double L = light->sampleEmission(Point2f(0.5f), Point2f(0.9f, 0.5f), Green).L[0];  // above: z ≈ 0.86
        auto exitance = mcMean([&](Point2f u) {
            EmissionSample es = light->sampleEmission(Point2f(0.5f), u, Green);
            float cosTheta = dot(es.n, es.ray.d);
            return es.pdfDirection > 0.f ? es.L[0] * cosTheta / es.pdfDirection : 0.0;
        }, 100000, 4);
        CHECK(agrees(exitance, Pi * L));
    }
}

TEST_CASE("warps in use: a nested lens warp keeps the thin lens unbiased", "[warp][camera]") {
    // The polar map's lens points have density 1/(2π r): the weights (1/π)/pdf = 2r must
    // average to 1 and weight r² to its mean over the disk, ½; as the default does.
    Ref<IWarp> polar = std::make_shared<PolarDiskWarp>();
    Ref<ICamera> plain = lens(), nested = lens({{"warp", warpValue(polar)}});
    for (const auto& cam : {plain, nested}) {
        auto rayWeight = [&](Point2f u, bool timesR2) {
            CameraSample cs;
            cs.pFilm = Point2f(11.f, 20.f);
            cs.pLens = u;
            SampledSpectrum w(0.f);
            Ray r = cam->generateRay(cs, Green, w);
            Point3f p = r.o - r.d * (0.01f / r.d.z);  // back to the lens plane z = 0 (near_clip 0.01)
            return double(w[0]) * (timesR2 ? double(p.x) * p.x + double(p.y) * p.y : 1.0);
        };
        CHECK(agrees(mcMean([&](Point2f u) { return rayWeight(u, false); }, 100000, 5), 1.0));
        CHECK(agrees(mcMean([&](Point2f u) { return rayWeight(u, true); }, 100000, 6), 0.5));
    }
    // Connections from a scene point: the same mean importance weight as the default.
    const Point3f ref(0.3f, 0.2f, 4.f);
    auto importance = [&](const Ref<ICamera>& cam) {
        return mcMean([&](Point2f u) {
            CameraImportanceSample cs;
            return query<ICameraImportance>(cam)->sampleDirection(ref, u, cs) ? double(cs.weight) / cs.pdf : 0.0;
        }, 100000, 7);
    };
    auto a = importance(plain), b = importance(nested);
    CHECK(std::abs(a.first - b.first) <= 4.0 * std::hypot(a.second, b.second));
}
