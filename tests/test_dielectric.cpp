// Smooth dielectrics: the `dielectric` and `thindielectric` BSDFs (lobe probabilities,
// sample weights, directions, total internal reflection, energy of a slab by a random walk
// through the BSDF, dispersion and its hero-wavelength estimator) and the named glasses
// (Sellmeier indices against published values, a prism that splits blue from red).
// Statistical tests are seeded; each states its tolerance.
#include "bsdf_helpers.hpp"

#include "effigi/math/rng.hpp"
#include "effigi/render/fresnel.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/glass.hpp"

#include <catch2/catch.hpp>

using namespace effigi;
using namespace effigi::test;

namespace {

const SurfaceInteraction NoSi{};

Vector3f dirAt(float thetaDeg, float side = 1.f) {
    float t = thetaDeg * Pi / 180.f;
    return {std::sin(t) * 0.6f, std::sin(t) * 0.8f, side * std::cos(t)};
}

} // namespace

TEST_CASE("dielectric: reflection with probability F, weights F/F and (1-F)/(1-F)/eta^2", "[bsdf][dielectric]") {
    Ref<IBSDF> b = makeBSDF("dielectric", {{"int_ior", 1.5}, {"ext_ior", 1.0}});
    CHECK(b->flags() == (BSDFReflection | BSDFTransmission | BSDFSpecular));
    CHECK(b->isPureSpecular());
    for (float side : {1.f, -1.f}) {
        for (float deg : {0.f, 30.f, 60.f, 85.f}) {
            if (side < 0 && deg > 40.f) continue;  // beyond the critical angle: see the TIR test
            Vector3f wo = dirAt(deg, side);
            float F = fresnelDielectric(wo.z, 1.5f);
            float etaRel = side > 0 ? 1.5f : 1.f / 1.5f;
            INFO("side " << side << ", theta " << deg << ", F = " << F);
            for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
                SampledWavelengths l = SampledWavelengths::constant(550.f);
                auto r = b->sample(NoSi, wo, F * 0.999f, {0.5f, 0.5f}, l, mode);
                REQUIRE(r);
                CHECK(r->flags == (BSDFReflection | BSDFSpecular));
                CHECK(r->pdf == Approx(F).epsilon(1e-6));
                CHECK(r->wi == reflectLocal(wo));
                CHECK(weight(*r) == Approx(1.f).epsilon(1e-5));

                auto t = b->sample(NoSi, wo, F + (1.f - F) * 0.001f, {0.5f, 0.5f}, l, mode);
                REQUIRE(t);
                CHECK(t->flags == (BSDFTransmission | BSDFSpecular));
                CHECK(t->pdf == Approx(1.f - F).epsilon(1e-6));
                CHECK(t->eta == Approx(etaRel));
                // Radiance is compressed by 1/η² entering a denser medium (Veach 1997, §5.2).
                float expect = mode == TransportMode::Radiance ? 1.f / (etaRel * etaRel) : 1.f;
                CHECK(weight(*t) == Approx(expect).epsilon(1e-5));
                // Snell's law across the interface.
                float sinO = std::sqrt(wo.x * wo.x + wo.y * wo.y), sinT = std::sqrt(t->wi.x * t->wi.x + t->wi.y * t->wi.y);
                CHECK(sinO == Approx(etaRel * sinT).epsilon(1e-5));
                CHECK(t->wi.z * wo.z < 0.f);
                CHECK_FALSE(l.secondaryTerminated());  // a constant index never terminates
            }
            SampledWavelengths l = SampledWavelengths::constant(550.f);
            CHECK(b->f(NoSi, wo, reflectLocal(wo), l, TransportMode::Radiance).isBlack());
            CHECK(b->pdf(NoSi, wo, reflectLocal(wo), l, TransportMode::Radiance) == 0.f);
        }
    }
    // The factors scale the two lobes.
    Ref<IBSDF> tinted = makeBSDF("dielectric", {{"int_ior", 1.5}, {"ext_ior", 1.0},
                                                {"specular_reflectance", 0.3}, {"specular_transmittance", 0.6}});
    SampledWavelengths l = SampledWavelengths::constant(550.f);
    Vector3f wo = dirAt(20.f);
    CHECK(weight(*tinted->sample(NoSi, wo, 0.f, {0.5f, 0.5f}, l, TransportMode::Importance)) == Approx(0.3f));
    CHECK(weight(*tinted->sample(NoSi, wo, 0.99f, {0.5f, 0.5f}, l, TransportMode::Importance)) == Approx(0.6f));
}

TEST_CASE("dielectric: the lobe frequencies are the Fresnel reflectance", "[bsdf][dielectric]") {
    // uc on a regular grid of 10^5 points: the fraction of reflections is F up to 1e-5.
    Ref<IBSDF> b = makeBSDF("dielectric", {{"int_ior", 1.33}, {"ext_ior", 1.0}});
    Vector3f wo = dirAt(70.f);
    const int n = 100000;
    int reflected = 0;
    for (int i = 0; i < n; ++i) {
        SampledWavelengths l = SampledWavelengths::constant(500.f);
        auto s = b->sample(NoSi, wo, (i + 0.5f) / n, {0.5f, 0.5f}, l, TransportMode::Radiance);
        REQUIRE(s);
        reflected += s->flags & BSDFReflection ? 1 : 0;
    }
    CHECK(double(reflected) / n == Approx(fresnelDielectric(wo.z, 1.33f)).margin(2e-5));
}

TEST_CASE("dielectric: total internal reflection inside beyond the critical angle", "[bsdf][dielectric]") {
    Ref<IBSDF> b = makeBSDF("dielectric", {{"int_ior", 1.5}, {"ext_ior", 1.0}});
    for (float deg : {42.f, 60.f, 89.f}) {  // critical angle asin(1/1.5) = 41.8°
        Vector3f wo = dirAt(deg, -1.f);
        for (float uc : {0.f, 0.5f, 0.9999f}) {
            SampledWavelengths l = SampledWavelengths::constant(550.f);
            auto s = b->sample(NoSi, wo, uc, {0.5f, 0.5f}, l, TransportMode::Radiance);
            REQUIRE(s);
            CHECK(s->flags == (BSDFReflection | BSDFSpecular));
            CHECK(s->pdf == 1.f);
            CHECK(s->wi == reflectLocal(wo));
            CHECK(weight(*s) == Approx(1.f).epsilon(1e-5));
        }
    }
}

namespace {

/// A seeded random walk through an infinite slab (faces z = 0 and z = 1, glass between)
/// using only the BSDF: light arrives on the top face at angle θ; the walk ends when it
/// leaves through either face. Returns the mean weight leaving at the top (R) and at the
/// bottom (T) and the largest deviation of a single path's weight from 1.
struct SlabResult {
    double R = 0, T = 0, maxWeightError = 0;
    int n = 0, failed = 0;
};

SlabResult slabWalk(const IBSDF& glass, float thetaDeg, int n, std::uint64_t seed) {
    PCG32 rng(seed, 1);
    SlabResult res;
    res.n = n;
    const Frame top(Vector3f(0, 0, 1)), bottom(Vector3f(0, 0, -1));
    for (int i = 0; i < n; ++i) {
        Vector3f d = -dirAt(thetaDeg);  // travelling down onto the top face
        bool atTop = true;
        float beta = 1.f;
        for (int bounce = 0; bounce < 1000; ++bounce) {
            const Frame& fr = atTop ? top : bottom;
            SampledWavelengths l = SampledWavelengths::constant(550.f);
            auto s = glass.sample(NoSi, fr.toLocal(-d), rng.nextFloat(), {rng.nextFloat(), rng.nextFloat()}, l,
                                  TransportMode::Radiance);
            if (!s) {  // a dielectric always has a lobe to take
                ++res.failed;
                break;
            }
            beta *= weight(*s);
            d = fr.toWorld(s->wi);
            bool up = d.z > 0.f;
            if (atTop && up) {  // leaves through the top
                res.R += beta;
                res.maxWeightError = std::max(res.maxWeightError, double(std::abs(beta - 1.f)));
                break;
            }
            if (!atTop && !up) {  // leaves through the bottom
                res.T += beta;
                res.maxWeightError = std::max(res.maxWeightError, double(std::abs(beta - 1.f)));
                break;
            }
            atTop = up;  // crosses the slab to the other face
        }
    }
    res.R /= n;
    res.T /= n;
    return res;
}

} // namespace

TEST_CASE("dielectric: a slab reflects 2R/(1+R) and transmits the rest, through the BSDF alone", "[bsdf][dielectric]") {
    Ref<IBSDF> glass = makeBSDF("dielectric", {{"int_ior", 1.5}, {"ext_ior", 1.0}});
    for (float deg : {0.f, 45.f}) {
        const int n = 400000;
        SlabResult r = slabWalk(*glass, deg, n, 17 + std::uint64_t(deg));
        // Without absorption the inter-reflections sum to R_slab = R + T²R/(1 − R²) = 2R/(1 + R)
        // (exact for the unpolarised F the BSDF uses at each face; at normal incidence
        // R = ((n − 1)/(n + 1))² = 0.04 and R_slab = 0.076923).
        float F = fresnelDielectric(std::cos(deg * Pi / 180.f), 1.5f);
        double Rslab = 2.0 * F / (1.0 + F);
        // Each path's weight is exactly 1 (the 1/η² in and η² out cancel): energy is
        // conserved path by path, so R + T = 1 up to float rounding.
        CHECK(r.failed == 0);
        CHECK(r.maxWeightError < 1e-5);
        CHECK(r.R + r.T == Approx(1.0).margin(1e-5));
        // Binomial standard error sqrt(p(1 − p)/n) = 4.2e-4 at p = 0.077; 5 standard errors
        // (two-sided false alarm 6e-7; the walk is seeded, so the outcome is fixed).
        double se = std::sqrt(Rslab * (1 - Rslab) / n);
        INFO("theta " << deg << ": R_slab MC " << r.R << " vs closed form " << Rslab << " (se " << se << ")");
        CHECK(std::abs(r.R - Rslab) < 5 * se);
    }
    CHECK(2 * 0.04 / 1.04 == Approx(0.0769231).epsilon(1e-6));
}

TEST_CASE("thindielectric: reflects R' = 2R/(1+R), passes straight through otherwise", "[bsdf][dielectric]") {
    Ref<IBSDF> b = makeBSDF("thindielectric", {{"int_ior", 1.5}, {"ext_ior", 1.0}});
    CHECK(b->isPureSpecular());
    CHECK(b->hasNull());
    for (float side : {1.f, -1.f}) {
        for (float deg : {0.f, 45.f, 80.f}) {
            Vector3f wo = dirAt(deg, side);
            float R = fresnelDielectric(std::abs(wo.z), 1.5f);
            float Rp = R + (1 - R) * (1 - R) * R / (1 - R * R);  // R + T²R/(1 − R²)
            CHECK(Rp == Approx(2 * R / (1 + R)).epsilon(1e-6));
            SampledWavelengths l = SampledWavelengths::constant(600.f);
            auto r = b->sample(NoSi, wo, Rp * 0.999f, {0.f, 0.f}, l, TransportMode::Radiance);
            REQUIRE(r);
            CHECK(r->flags == (BSDFReflection | BSDFSpecular));
            CHECK(r->pdf == Approx(Rp).epsilon(1e-5));
            CHECK(r->wi == reflectLocal(wo));
            CHECK(weight(*r) == Approx(1.f).epsilon(1e-5));
            auto t = b->sample(NoSi, wo, Rp + (1 - Rp) * 0.01f, {0.f, 0.f}, l, TransportMode::Radiance);
            REQUIRE(t);
            // The straight pass is a pass-through lobe (Mitsuba 3's Null component): not a
            // bounce, and shadow rays cross the pane keeping T' = 1 − R' at their angle.
            CHECK(t->flags == (BSDFNull | BSDFTransmission | BSDFSpecular));
            CHECK(t->pdf == Approx(1 - Rp).epsilon(1e-5));
            CHECK(t->wi == -wo);
            CHECK(t->eta == 1.f);
            CHECK(weight(*t) == Approx(1.f).epsilon(1e-5));  // no net change of medium
            SurfaceInteraction si;
            si.wo = Vector3f(wo.x, wo.y, wo.z);  // identity shading frame: local = world
            CHECK(b->evalNullTransmission(si, l)[0] == Approx(1 - Rp).epsilon(1e-5));
        }
    }
    // Albedo at normal incidence: R' + T' = 1.
    SampledWavelengths l = SampledWavelengths::constant(600.f);
    CHECK(b->albedo(NoSi, l)[0] == Approx(1.f).epsilon(1e-6));
}

TEST_CASE("glass: Sellmeier indices match the published values", "[glass][dielectric]") {
    // Schott N-BK7 data sheet: n_F (486.1327 nm) = 1.52238, n_d (587.5618 nm) = 1.51680,
    // n_C (656.2725 nm) = 1.51432, n_e (546.074 nm) = 1.51872; to 1e-4 as the issue asks
    // (the data sheet prints 5 decimals).
    const SellmeierGlass* bk7 = findSellmeierGlass("bk7");
    REQUIRE(bk7);
    CHECK(bk7->index(486.1327) == Approx(1.52238).margin(1e-4));
    CHECK(bk7->index(587.5618) == Approx(1.51680).margin(1e-4));
    CHECK(bk7->index(656.2725) == Approx(1.51432).margin(1e-4));
    CHECK(bk7->index(546.074) == Approx(1.51872).margin(1e-4));
    // Abbe number ν_d = (n_d − 1)/(n_F − n_C) = 64.17 for N-BK7.
    double abbe = (bk7->index(587.5618) - 1) / (bk7->index(486.1327) - bk7->index(656.2725));
    CHECK(abbe == Approx(64.17).margin(0.05));
    // Schott N-SF11 (dense flint): n_d = 1.78472, Abbe number 25.68.
    const SellmeierGlass* sf11 = findSellmeierGlass("sf11");
    REQUIRE(sf11);
    CHECK(sf11->index(587.5618) == Approx(1.78472).margin(1e-4));
    CHECK((sf11->index(587.5618) - 1) / (sf11->index(486.1327) - sf11->index(656.2725)) == Approx(25.68).margin(0.05));
    // Fused silica (Malitson 1965, measured): 1.46313 at 486.13 nm, 1.45846 at 587.56 nm,
    // 1.45637 at 656.27 nm.
    const SellmeierGlass* silica = findSellmeierGlass("fused-silica");
    REQUIRE(silica);
    CHECK(silica->index(486.13) == Approx(1.46313).margin(1e-4));
    CHECK(silica->index(587.56) == Approx(1.45846).margin(1e-4));
    CHECK(silica->index(656.27) == Approx(1.45637).margin(1e-4));
    // Diamond: n_D = 2.417 at 589.3 nm (the textbook value); Abbe number about 55.
    const SellmeierGlass* diamond = findSellmeierGlass("diamond");
    REQUIRE(diamond);
    CHECK(diamond->index(589.3) == Approx(2.417).margin(5e-4));
    double abbeDiamond = (diamond->index(587.5618) - 1) / (diamond->index(486.1327) - diamond->index(656.2725));
    CHECK(abbeDiamond == Approx(55.3).margin(0.5));

    // The spectra the BSDFs use (1 nm tables) agree with the formula.
    for (const char* name : {"bk7", "sf11", "fused-silica", "diamond"}) {
        std::optional<Spectrum> s = namedIOR(name);
        REQUIRE(s);
        CHECK(isDispersiveIOR(name));
        for (double l : {400.3, 486.1327, 587.5618, 656.2725, 799.9})
            CHECK((*s)(float(l)) == Approx(findSellmeierGlass(name)->index(l)).margin(2e-6));
    }
    // Mitsuba's constants.
    CHECK((*namedIOR("water"))(500.f) == Approx(1.333f));
    CHECK((*namedIOR("air"))(500.f) == Approx(1.000277f));
    CHECK_FALSE(isDispersiveIOR("water"));
    CHECK_FALSE(namedIOR("unobtainium"));
    try {
        iorByName("fused-silca", {"scene.xml", 7}, "int_ior");
        FAIL("no error");
    } catch (const Error& e) {
        std::string msg = e.what();
        CHECK(msg.find("scene.xml:7") != std::string::npos);
        CHECK(msg.find("int_ior") != std::string::npos);
        CHECK(msg.find("did you mean 'fused-silica'") != std::string::npos);
    }
}

TEST_CASE("dielectric: bad index input is a one-line error naming the parameter", "[bsdf][dielectric]") {
    auto errorOf = [](const std::string& bsdf, const std::string& param, PropertyValue v) -> std::string {
        try {
            makeBSDF(bsdf, {{param, std::move(v)}});
        } catch (const Error& e) {
            return e.what();
        }
        return "";
    };
    SpectrumValue misspelt;
    misspelt.name = "bk8";
    std::string e = errorOf("dielectric", "int_ior", misspelt);
    CHECK(e.find("int_ior") != std::string::npos);
    CHECK(e.find("did you mean 'bk7'") != std::string::npos);
    e = errorOf("thindielectric", "ext_ior", RGBValue{Vector3f(1.f)});
    CHECK(e.find("ext_ior") != std::string::npos);
    CHECK(e.find("not rgb") != std::string::npos);
    e = errorOf("dielectric", "int_ior", -1.5);
    CHECK(e.find("int_ior") != std::string::npos);
    e = errorOf("dielectric", "int_ior", tabulated({400.f, 500.f}, {1.5f, -1.f}));
    CHECK(e.find("positive") != std::string::npos);
    for (const std::string& m : {std::string("dielectric"), std::string("thindielectric")}) {
        e = errorOf(m, "int_ior", tabulated({400.f, 700.f}, {1.5f, 1.4f}));
        CHECK(e.empty());  // a spectral index is fine
    }
}

TEST_CASE("dielectric: int_ior and ext_ior by name, as Mitsuba writes them", "[bsdf][dielectric]") {
    // <string name="int_ior" value="water"/>: Mitsuba's names and effigi's glasses.
    Ref<IBSDF> water = makeBSDF("dielectric", {{"int_ior", std::string("water")}, {"ext_ior", std::string("vacuum")}});
    SampledWavelengths l = SampledWavelengths::constant(550.f);
    auto s = water->sample(NoSi, Vector3f(0, 0, 1), 0.f, {0.f, 0.f}, l, TransportMode::Radiance);
    REQUIRE(s);
    CHECK(s->pdf == Approx(std::pow(0.333 / 2.333, 2)).epsilon(1e-4));
    Ref<IBSDF> bk7 = makeBSDF("thindielectric", {{"int_ior", std::string("bk7")}});
    CHECK(bk7);
    try {
        makeBSDF("dielectric", {{"int_ior", std::string("watr")}});
        FAIL("no error");
    } catch (const Error& e) {
        CHECK(std::string(e.what()).find("did you mean 'water'") != std::string::npos);
    }
}
