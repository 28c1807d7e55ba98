// Dispersion in the `dielectric` BSDF: which samples terminate the secondary wavelengths,
// the hero-wavelength estimator of a dispersive slab against quadrature (with radiance
// gathered before the slab, as a path tracer has it), with a negative control showing the
// test can see a biased variant, and a BK7 prism that sends blue and red to opposite sides.
// Statistical tests are seeded; each states its tolerance.
#include "../components/bsdf/delta_bsdf.hpp"
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

SpectrumValue namedValue(const std::string& name) {
    SpectrumValue s;
    s.name = name;
    return s;
}

/// A strongly dispersive index (1.05 at 360 nm to 4.0 at 830 nm, F from 6e-4 to 0.36),
/// so that a wrong estimator shows.
SpectrumValue rampIOR() { return tabulated({360.f, 830.f}, {1.05f, 4.0f}); }
float rampIndex(float l) { return 1.05f + (l - 360.f) / 470.f * 2.95f; }
/// Radiance a path gathered before it reached the slab (e.g. direct light at an earlier
/// vertex): varies with λ, so it is weighted differently by the hero and the secondaries.
float prefix(float l) { return (l - 360.f) / 470.f; }

/// The same lobe choice with F at the HERO wavelength (termination on refraction only): the
/// chance of terminating then depends on which wavelength is the hero, which biases the
/// radiance gathered before this vertex. Used only as the negative control.
class HeroChoiceDielectric final : public DeltaBSDF {
public:
    std::uint32_t flags() const override { return BSDFReflection | BSDFTransmission | BSDFSpecular; }
    std::optional<BSDFSample> sample(const SurfaceInteraction&, const Vector3f& wo, float uc, const Point2f&,
                                     SampledWavelengths& l, TransportMode) const override {
        SampledSpectrum F;
        for (int i = 0; i < NSpectrumSamples; ++i) F[i] = fresnelDielectric(wo.z, rampIndex(l[i]));
        BSDFSample s;
        float c = std::abs(wo.z);
        if (uc < F[0]) {
            s.wi = reflectLocal(wo), s.pdf = F[0], s.flags = BSDFReflection | BSDFSpecular;
            s.f = F / c;
            return s;
        }
        if (!refractLocal(wo, rampIndex(l[0]), s.wi, s.eta)) return std::nullopt;
        l.terminateSecondary();
        s.pdf = 1.f - F[0], s.flags = BSDFTransmission | BSDFSpecular;
        s.f = (SampledSpectrum(1.f) - F) / (s.eta * s.eta * std::abs(s.wi.z));
        return s;
    }
};

struct Estimate {
    double mean, se;
    bool anyTerminated;
};

/// Luminance reflected by a slab (faces z = 0 and 1) lit from above at θ, plus the
/// prefix, estimated exactly as the path renderer accumulates: L += β·Le along the walk,
/// β *= f·|cos|/pdf, and cie::toY(L, λ) with the (possibly terminated) wavelengths.
Estimate slabLuminance(const IBSDF& glass, float thetaDeg, int n, std::uint64_t seed) {
    PCG32 rng(seed, 1);
    const Frame top(Vector3f(0, 0, 1)), bottom(Vector3f(0, 0, -1));
    double sum = 0, sum2 = 0;
    bool anyTerminated = false;
    float t = thetaDeg * Pi / 180.f;
    for (int i = 0; i < n; ++i) {
        SampledWavelengths lambda = SampledWavelengths::sampleVisible(rng.nextFloat());
        SampledSpectrum L(0.f), beta(1.f);
        for (int k = 0; k < NSpectrumSamples; ++k) L[k] = prefix(lambda[k]);
        Vector3f d(std::sin(t), 0.f, -std::cos(t));
        bool atTop = true;
        for (int bounce = 0; bounce < 1000; ++bounce) {
            const Frame& fr = atTop ? top : bottom;
            auto s = glass.sample(NoSi, fr.toLocal(-d), rng.nextFloat(), {rng.nextFloat(), rng.nextFloat()}, lambda,
                                  TransportMode::Radiance);
            if (!s) break;
            beta *= s->f * (std::abs(s->wi.z) / s->pdf);
            d = fr.toWorld(s->wi);
            bool up = d.z > 0.f;
            if (atTop && up) {  // leaves at the top, toward a white sky of radiance 1
                L += beta;
                break;
            }
            if (!atTop && !up) break;  // leaves at the bottom: dark
            atTop = up;
        }
        anyTerminated |= lambda.secondaryTerminated();
        double y = cie::toY(L, lambda);
        sum += y;
        sum2 += y * y;
    }
    double mean = sum / n, var = std::max(0.0, sum2 / n - mean * mean);
    return {mean, std::sqrt(var / (n - 1)), anyTerminated};
}

/// The exact value by quadrature: Y of prefix(λ) + R_slab(λ), R_slab = 2F/(1 + F).
template <typename Index> double slabReference(float thetaDeg, Index index) {
    float c = std::cos(thetaDeg * Pi / 180.f);
    return cie::luminance([&](float l) {
        float F = fresnelDielectric(c, index(l));
        return prefix(l) + 2.f * F / (1.f + F);
    });
}

} // namespace

TEST_CASE("dispersion: only refraction at a dispersive index terminates the secondary wavelengths", "[bsdf][dispersion]") {
    Ref<IBSDF> bk7 = makeBSDF("dielectric", {{"int_ior", namedValue("bk7")}, {"ext_ior", 1.0}});
    Vector3f wo = normalize(Vector3f(0.3f, 0.f, 0.9f));
    const SampledWavelengths start = SampledWavelengths::sampleVisible(0.37f);

    SampledWavelengths l = start;
    auto r = bk7->sample(NoSi, wo, 0.f, {0.f, 0.f}, l, TransportMode::Radiance);  // uc = 0: reflection
    REQUIRE(r);
    CHECK(r->flags == (BSDFReflection | BSDFSpecular));
    CHECK_FALSE(l.secondaryTerminated());  // a mirror direction serves every wavelength

    auto t = bk7->sample(NoSi, wo, 0.99f, {0.f, 0.f}, l, TransportMode::Radiance);
    REQUIRE(t);
    CHECK(t->flags == (BSDFTransmission | BSDFSpecular));
    REQUIRE(l.secondaryTerminated());
    CHECK(l.pdf()[0] == Approx(start.pdf()[0] / NSpectrumSamples));
    for (int i = 1; i < NSpectrumSamples; ++i) CHECK(l.pdf()[i] == 0.f);
    // The direction is the hero's: Snell with n_BK7(λ_hero).
    float n0 = float(findSellmeierGlass("bk7")->index(start[0]));
    CHECK(std::sqrt(1 - wo.z * wo.z) == Approx(n0 * std::sqrt(1 - t->wi.z * t->wi.z)).epsilon(2e-5));

    // No termination: a constant index, a tabulated but flat one, a thin slab.
    for (auto [name, ior] : {std::pair<const char*, PropertyValue>{"dielectric", 1.5},
                             {"dielectric", tabulated({400.f, 700.f}, {1.5f, 1.5f})},
                             {"thindielectric", namedValue("bk7")}}) {
        Ref<IBSDF> b = makeBSDF(name, {{"int_ior", ior}});
        SampledWavelengths l2 = start;
        auto s = b->sample(NoSi, wo, 0.99f, {0.f, 0.f}, l2, TransportMode::Radiance);
        REQUIRE(s);
        INFO(name << ": pdfs " << l2.pdf()[0] << " " << l2.pdf()[1] << " " << l2.pdf()[2] << " " << l2.pdf()[3]);
        CHECK(s->isTransmission());
        CHECK_FALSE(l2.secondaryTerminated());
    }
}

TEST_CASE("dispersion: the hero-wavelength estimate of a dispersive slab is unbiased", "[bsdf][dispersion]") {
    // 10^6 walks; the standard error is about 0.1 % of the value. Tolerance: 5 standard
    // errors (two-sided false alarm 6e-7), the walks seeded. Quadrature error of
    // cie::luminance on its 1 nm grid is below 1e-5 relative.
    const int n = 1000000;
    Ref<IBSDF> ramp = makeBSDF("dielectric", {{"int_ior", rampIOR()}, {"ext_ior", 1.0}});
    for (float deg : {0.f, 30.f}) {
        Estimate e = slabLuminance(*ramp, deg, n, 101 + std::uint64_t(deg));
        double ref = slabReference(deg, rampIndex);
        INFO("ramp index, theta " << deg << ": MC " << e.mean << " ± " << e.se << ", quadrature " << ref);
        CHECK(e.anyTerminated);
        CHECK(std::abs(e.mean - ref) < 5 * e.se);
        CHECK(e.se < 1.5e-3 * ref);  // sharp enough to see the control's bias below
    }
    // Negative control: choosing the lobe by F at the hero wavelength is off by ~1 % here
    // (about 9 standard errors), and this test sees it.
    HeroChoiceDielectric biased;
    Estimate c = slabLuminance(biased, 0.f, n, 101);
    double ref = slabReference(0.f, rampIndex);
    INFO("control: MC " << c.mean << " ± " << c.se << ", quadrature " << ref);
    CHECK(std::abs(c.mean - ref) > 5 * c.se);
}

TEST_CASE("dispersion: a BK7 slab agrees with its quadrature and with the non-dispersive limit", "[bsdf][dispersion]") {
    const int n = 400000;
    const SellmeierGlass* g = findSellmeierGlass("bk7");
    Ref<IBSDF> bk7 = makeBSDF("dielectric", {{"int_ior", namedValue("bk7")}, {"ext_ior", 1.0}});
    Estimate d = slabLuminance(*bk7, 20.f, n, 7);
    double refD = slabReference(20.f, [&](float l) { return float(g->index(l)); });
    INFO("BK7: MC " << d.mean << " ± " << d.se << ", quadrature " << refD);
    CHECK(d.anyTerminated);
    CHECK(std::abs(d.mean - refD) < 5 * d.se);  // 5 standard errors, as above

    // The non-dispersive limit (n = n_d everywhere) keeps all four wavelengths and differs
    // from BK7 only by the small spread of its reflectance: |ΔY| < 1e-3 exactly (3.5e-4).
    const float nd = float(g->index(587.5618));
    Ref<IBSDF> flat = makeBSDF("dielectric", {{"int_ior", double(nd)}, {"ext_ior", 1.0}});
    Estimate f = slabLuminance(*flat, 20.f, n, 8);
    double refF = slabReference(20.f, [&](float) { return nd; });
    INFO("n_d constant: MC " << f.mean << " ± " << f.se << ", quadrature " << refF);
    CHECK_FALSE(f.anyTerminated);
    CHECK(std::abs(f.mean - refF) < 5 * f.se);
    CHECK(std::abs(refD - refF) < 1e-3);
    CHECK(std::abs(d.mean - f.mean) < std::abs(refD - refF) + 5 * std::hypot(d.se, f.se));
}

TEST_CASE("dispersion: a BK7 prism deviates blue more than green more than red", "[bsdf][dispersion]") {
    // A 60° prism, apex up, in the xz plane; light travels +x and enters the left face at
    // the angle of minimum deviation for 550 nm. Each ray is refracted by the BSDF at both
    // faces and lands on a wall x = 1 beyond the prism.
    Ref<IBSDF> glass = makeBSDF("dielectric", {{"int_ior", namedValue("bk7")}, {"ext_ior", 1.0}});
    const SellmeierGlass* g = findSellmeierGlass("bk7");
    const float A = 60.f * Pi / 180.f, h = 0.1f, b = h * std::tan(A / 2);
    const Vector3f n1(-std::cos(A / 2), 0, std::sin(A / 2)), n2(std::cos(A / 2), 0, std::sin(A / 2));
    const float theta1 = std::asin(float(g->index(550.0)) * std::sin(A / 2));
    const Vector3f d0(std::cos(theta1 - A / 2), 0, std::sin(theta1 - A / 2));
    const Point3f p1(-b / 2, 0, h / 2);  // middle of the left face
    const float wallX = 1.f;

    auto trace = [&](float lambdaNm, float& deviation) {
        SampledWavelengths l = SampledWavelengths::constant(lambdaNm);
        Frame f1(n1), f2(n2);
        auto s1 = glass->sample(NoSi, f1.toLocal(-d0), 0.9999f, {0.f, 0.f}, l, TransportMode::Radiance);
        REQUIRE(s1);
        REQUIRE(s1->isTransmission());
        Vector3f d1 = f1.toWorld(s1->wi);
        float t = dot(Point3f(b, 0, 0) - p1, n2) / dot(d1, n2);  // to the right face
        Point3f p2 = p1 + t * d1;
        auto s2 = glass->sample(NoSi, f2.toLocal(-d1), 0.9999f, {0.f, 0.f}, l, TransportMode::Radiance);
        REQUIRE(s2);
        REQUIRE(s2->isTransmission());
        Vector3f d2 = f2.toWorld(s2->wi);
        deviation = std::acos(std::clamp(dot(d0, d2), -1.f, 1.f));
        return p2.z + d2.z / d2.x * (wallX - p2.x);  // height where it meets the wall
    };
    float devB, devG, devR;
    float zBlue = trace(450.f, devB), zGreen = trace(550.f, devG), zRed = trace(650.f, devR);
    INFO("wall heights: blue " << zBlue << ", green " << zGreen << ", red " << zRed);
    // The prism bends light toward its base (−z); blue the most (n is larger).
    CHECK(devB > devG);
    CHECK(devG > devR);
    CHECK(zBlue < zGreen);
    CHECK(zRed > zGreen);  // opposite sides of the green spot
    CHECK(zGreen - zBlue > 1e-3f);
    CHECK(zRed - zGreen > 1e-3f);
    // Snell's law by hand: δ = θ1 + asin(n sin(A − asin(sin θ1 / n))) − A.
    for (auto [lam, dev] : {std::pair{450.f, devB}, std::pair{550.f, devG}, std::pair{650.f, devR}}) {
        double n = g->index(lam);
        double delta = theta1 + std::asin(n * std::sin(A - std::asin(std::sin(theta1) / n))) - A;
        CHECK(dev == Approx(delta).margin(2e-5));
    }
    // 550 nm passes at minimum deviation 2 θ1 − A (38.6° for n = 1.5185).
    CHECK(devG == Approx(2 * theta1 - A).margin(2e-5));
}
