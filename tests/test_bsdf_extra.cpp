// The BSDFs of issue 10, part one: orennayar and phong — their analytic limits (σ = 0 is
// Lambertian), closed forms, energy bounds and parameter errors. normalmap and bumpmap
// are tested in test_bsdf_perturbed.cpp, principled and principledthin in
// test_bsdf_principled.cpp. Statistical checks are seeded; each states its significance
// level.
#include "bsdf_extra_helpers.hpp"

#include "effigi/core/error.hpp"
#include "effigi/math/rng.hpp"

#include <catch2/catch.hpp>

#include <numbers>

using namespace effigi;
using namespace effigi::test;

// ---- orennayar ---------------------------------------------------------------------

TEST_CASE("orennayar: sigma 0 is the Lambertian diffuse BSDF", "[bsdf][orennayar]") {
    SurfaceInteraction si = probe();
    for (bool fast : {false, true}) {
        Ref<IBSDF> on = makeBSDF("orennayar", {{"sigma", 0.0}, {"reflectance", 0.7}, {"use_fast_approx", fast}});
        Ref<IBSDF> d = makeBSDF("diffuse", {{"reflectance", 0.7}});
        requireSameBSDF(*on, *d, si, 1e-6f, 3);
    }
}

TEST_CASE("orennayar: reciprocal, retro-reflective, and alpha is sigma times sqrt 2", "[bsdf][orennayar]") {
    SurfaceInteraction si = probe();
    Ref<IBSDF> b = makeBSDF("orennayar", {{"sigma", 0.5}});
    Ref<IBSDF> viaAlpha = makeBSDF("orennayar", {{"alpha", 0.5 * std::sqrt(2.0)}});
    requireSameBSDF(*b, *viaAlpha, si, 1e-5f, 4);
    SampledWavelengths l = SampledWavelengths::constant(550.f);
    PCG32 rng(9, 1);
    for (int i = 0; i < 2000; ++i) {
        Vector3f a = upperDirection(rng), c = upperDirection(rng);
        REQUIRE(b->f(si, a, c, l, TransportMode::Radiance)[0] ==
                Approx(b->f(si, c, a, l, TransportMode::Radiance)[0]).epsilon(1e-5));
    }
    // Rough surfaces scatter back toward the light more than forward (Oren & Nayar 1994,
    // fig. 2): at 60° incidence, the retro direction is brighter than the mirror one and
    // brighter than Lambert's ρ/π, and normal viewing sees less than Lambert (A < 1).
    Vector3f wo = directionFromCos(0.5f, 0.f);
    float retro = b->f(si, wo, wo, l, TransportMode::Radiance)[0];
    float mirror = b->f(si, wo, reflectLocal(wo), l, TransportMode::Radiance)[0];
    CHECK(retro > mirror);
    CHECK(retro > 0.5f * InvPi);
    CHECK(b->f(si, Vector3f(0, 0, 1), Vector3f(0, 0, 1), l, TransportMode::Radiance)[0] < 0.5f * InvPi);
}

TEST_CASE("orennayar: the qualitative model matches its closed form", "[bsdf][orennayar]") {
    // f = ρ/π (A + B max(0, cos Δφ) sin α tan β), written here from angles (atan2, not
    // the component's cosines), at random pairs.
    SurfaceInteraction si = probe();
    const double sigma = 0.4, s2 = sigma * sigma, rho = 0.6;
    const double A = 1.0 - 0.5 * s2 / (s2 + 0.33), B = 0.45 * s2 / (s2 + 0.09);
    Ref<IBSDF> b = makeBSDF("orennayar", {{"sigma", sigma}, {"reflectance", rho}, {"use_fast_approx", true}});
    SampledWavelengths l = SampledWavelengths::constant(550.f);
    PCG32 rng(21, 2);
    for (int i = 0; i < 1000; ++i) {
        Vector3f wo = upperDirection(rng), wi = upperDirection(rng);
        double to = std::acos(double(wo.z)), ti = std::acos(double(wi.z));
        double dphi = std::atan2(double(wo.y), double(wo.x)) - std::atan2(double(wi.y), double(wi.x));
        double expected = rho / std::numbers::pi *
                          (A + B * std::max(0.0, std::cos(dphi)) * std::sin(std::max(to, ti)) * std::tan(std::min(to, ti)));
        REQUIRE(b->f(si, wo, wi, l, TransportMode::Radiance)[0] == Approx(expected).epsilon(2e-4));
    }
}

TEST_CASE("orennayar: alpha and sigma together are an error", "[bsdf][orennayar]") {
    CHECK_THROWS_AS(makeBSDF("orennayar", {{"sigma", 0.3}, {"alpha", 0.2}}), Error);
}

// ---- phong -------------------------------------------------------------------------

TEST_CASE("phong: the glossy lobe's albedo is rho_s at normal incidence and never above", "[bsdf][phong]") {
    // Seeded; each comparison allows 5 standard errors (two-sided level ~6e-7 per check).
    SurfaceInteraction si = probe();
    for (double n : {1e-3, 1.0, 30.0, 1000.0}) {
        Ref<IBSDF> b = makeBSDF("phong", {{"exponent", n}, {"specular_reflectance", 1.0}, {"diffuse_reflectance", 0.0}});
        auto [a0, se0] = sampledAlbedo(*b, si, Vector3f(0, 0, 1), 200000, 17);
        CHECK(a0 == Approx(1.0).margin(5 * se0 + 1e-4));
        for (float c : {0.8f, 0.4f, 0.1f}) {
            auto [a, se] = sampledAlbedo(*b, si, directionFromCos(c), 200000, 18);
            CHECK(a <= 1.0 + 5 * se + 1e-4);
        }
    }
}

TEST_CASE("phong: f is the modified Phong formula and the sum of both lobes", "[bsdf][phong]") {
    SurfaceInteraction si = probe();
    const double n = 12.0, rs = 0.3, rd = 0.4;
    Ref<IBSDF> b = makeBSDF("phong", {{"exponent", n}, {"specular_reflectance", rs}, {"diffuse_reflectance", rd}});
    SampledWavelengths l = SampledWavelengths::constant(550.f);
    PCG32 rng(5, 8);
    for (int i = 0; i < 1000; ++i) {
        Vector3f wo = upperDirection(rng), wi = upperDirection(rng);
        // The cosine between wi and the mirror direction of wo.
        Vector3f r(-wo.x, -wo.y, wo.z);
        double c = std::max(0.0, double(dot(normalize(r), wi)));
        double expected = rd / std::numbers::pi + rs * (n + 2.0) / (2.0 * std::numbers::pi) * std::pow(c, n);
        REQUIRE(b->f(si, wo, wi, l, TransportMode::Radiance)[0] == Approx(expected).epsilon(1e-4));
    }
}
