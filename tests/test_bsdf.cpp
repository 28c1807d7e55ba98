// BSDFs: the `diffuse` component (value, one-sidedness, reciprocity, sample/pdf
// consistency, distribution of its samples, albedo, grazing angles) and the default
// IBSDF::albedo estimate. Statistical tests are seeded and state their significance.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/math/stats.hpp"
#include "effigi/math/warp_functions.hpp"

#include <catch2/catch.hpp>

using namespace effigi;

namespace {

Ref<IBSDF> makeDiffuse(double reflectance) {
    Properties p("bsdf", "diffuse");
    p.set("reflectance", reflectance);
    Ref<IBSDF> b = query<IBSDF>(Registry::instance().create("bsdf", "diffuse", p));
    REQUIRE(b);
    return b;
}

Vector3f dirFromAngles(float theta, float phi) {
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

/// A BSDF that keeps the default albedo(): Lambertian with uniform hemisphere sampling,
/// so f·cos/pdf varies from sample to sample and the estimate has to integrate.
class UniformLambert final : public Implements<IBSDF> {
public:
    explicit UniformLambert(float rho) : m_rho(rho) {}
    std::uint32_t flags() const override { return BSDFReflection | BSDFDiffuse; }
    SampledSpectrum f(const SurfaceInteraction&, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&,
                      TransportMode) const override {
        return SampledSpectrum(wo.z > 0 && wi.z > 0 ? m_rho * InvPi : 0.f);
    }
    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float, const Point2f& u,
                                     SampledWavelengths& l, TransportMode m) const override {
        BSDFSample s;
        s.wi = warp::squareToUniformHemisphere(u);
        s.pdf = pdf(si, wo, s.wi, l, m);
        s.f = f(si, wo, s.wi, l, m);
        s.flags = flags();
        return s.pdf > 0 ? std::optional(s) : std::nullopt;
    }
    float pdf(const SurfaceInteraction&, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&,
              TransportMode) const override {
        return wo.z > 0 && wi.z > 0 ? Inv2Pi : 0.f;
    }

private:
    float m_rho;
};

/// A perfect mirror that keeps the default albedo(): delta lobes must count fully.
class Mirror final : public Implements<IBSDF> {
public:
    std::uint32_t flags() const override { return BSDFReflection | BSDFSpecular; }
    SampledSpectrum f(const SurfaceInteraction&, const Vector3f&, const Vector3f&, const SampledWavelengths&,
                      TransportMode) const override {
        return SampledSpectrum(0.f);
    }
    std::optional<BSDFSample> sample(const SurfaceInteraction&, const Vector3f& wo, float, const Point2f&,
                                     SampledWavelengths&, TransportMode) const override {
        BSDFSample s;
        s.wi = Vector3f(-wo.x, -wo.y, wo.z);
        s.pdf = 1.f;
        s.f = SampledSpectrum(0.8f / std::abs(s.wi.z));
        s.flags = flags();
        return s;
    }
    float pdf(const SurfaceInteraction&, const Vector3f&, const Vector3f&, const SampledWavelengths&,
              TransportMode) const override {
        return 0.f;
    }
};

} // namespace

TEST_CASE("diffuse: f = ρ/π above the surface, zero below (one-sided)", "[bsdf]") {
    auto bsdf = makeDiffuse(0.7);
    SurfaceInteraction si;
    auto lambda = SampledWavelengths::sampleVisible(0.37f);
    CHECK(bsdf->flags() == (BSDFReflection | BSDFDiffuse));
    PCG32 rng(1, 1);
    for (int i = 0; i < 1000; ++i) {
        Vector3f wo = warp::squareToUniformSphere({rng.nextFloat(), rng.nextFloat()});
        Vector3f wi = warp::squareToUniformSphere({rng.nextFloat(), rng.nextFloat()});
        SampledSpectrum f = bsdf->f(si, wo, wi, lambda, TransportMode::Radiance);
        float pdf = bsdf->pdf(si, wo, wi, lambda, TransportMode::Radiance);
        bool above = wo.z > 0 && wi.z > 0;
        for (int k = 0; k < NSpectrumSamples; ++k) CHECK(f[k] == Approx(above ? 0.7f * InvPi : 0.f));
        CHECK(pdf == Approx(above ? wi.z * InvPi : 0.f));
        // Reciprocity: swapping the directions changes nothing.
        SampledSpectrum g = bsdf->f(si, wi, wo, lambda, TransportMode::Radiance);
        for (int k = 0; k < NSpectrumSamples; ++k) CHECK(g[k] == f[k]);
    }
    // Seen from below nothing can be sampled.
    SampledWavelengths l = lambda;
    CHECK_FALSE(bsdf->sample(si, Vector3f(0.f, 0.6f, -0.8f), 0.5f, {0.3f, 0.6f}, l, TransportMode::Radiance));
}

TEST_CASE("diffuse: sample() agrees with f() and pdf()", "[bsdf]") {
    auto bsdf = makeDiffuse(0.25);
    SurfaceInteraction si;
    PCG32 rng(2, 1);
    int sampled = 0;
    for (int i = 0; i < 2000; ++i) {
        Vector3f wo = warp::squareToCosineHemisphere({rng.nextFloat(), rng.nextFloat()});
        auto lambda = SampledWavelengths::sampleVisible(rng.nextFloat());
        auto bs = bsdf->sample(si, wo, rng.nextFloat(), {rng.nextFloat(), rng.nextFloat()}, lambda,
                               TransportMode::Radiance);
        if (!bs) continue;
        ++sampled;
        CHECK(bs->wi.z > 0.f);
        CHECK(length(bs->wi) == Approx(1.f).epsilon(1e-5));
        CHECK(bs->flags == (BSDFReflection | BSDFDiffuse));
        CHECK(bs->pdf == Approx(bsdf->pdf(si, wo, bs->wi, lambda, TransportMode::Radiance)).epsilon(1e-5));
        SampledSpectrum f = bsdf->f(si, wo, bs->wi, lambda, TransportMode::Radiance);
        for (int k = 0; k < NSpectrumSamples; ++k) CHECK(bs->f[k] == Approx(f[k]));
        // Cosine sampling makes the weight f·cos/pdf exactly the albedo.
        CHECK(bs->f[0] * bs->wi.z / bs->pdf == Approx(0.25f).epsilon(1e-4));
    }
    CHECK(sampled > 1990);
}

TEST_CASE("diffuse: sampled directions follow pdf() (chi-square)", "[bsdf]") {
    // Bins over (cos θ, φ) of the whole sphere; expected counts integrate pdf() over each
    // bin numerically (8×8 midpoint rule in (cos θ, φ), where dω = d cos θ dφ).
    // Significance 0.01 for each of three viewing directions.
    auto bsdf = makeDiffuse(0.5);
    SurfaceInteraction si;
    const int nz = 20, nphi = 40, n = 100000, sub = 8;
    const float thetas[] = {0.f, 1.f, 1.55f};
    for (float theta : thetas) {
        Vector3f wo = dirFromAngles(theta, 0.4f);
        PCG32 rng(77, std::uint64_t(theta * 100.f));
        std::vector<double> obs(std::size_t(nz * nphi), 0.0), exp(obs.size(), 0.0);
        for (int i = 0; i < n; ++i) {
            auto lambda = SampledWavelengths::constant(550.f);
            auto bs = bsdf->sample(si, wo, rng.nextFloat(), {rng.nextFloat(), rng.nextFloat()}, lambda,
                                   TransportMode::Radiance);
            if (!bs) continue;
            double phi = std::atan2(bs->wi.y, bs->wi.x);
            if (phi < 0) phi += 2 * M_PI;
            int iz = std::clamp(int((bs->wi.z + 1.0) / 2.0 * nz), 0, nz - 1);
            int ip = std::clamp(int(phi / (2 * M_PI) * nphi), 0, nphi - 1);
            obs[std::size_t(iz * nphi + ip)] += 1.0;
        }
        auto lambda = SampledWavelengths::constant(550.f);
        for (int iz = 0; iz < nz; ++iz)
            for (int ip = 0; ip < nphi; ++ip) {
                double dz = 2.0 / nz / sub, dphi = 2 * M_PI / nphi / sub, sum = 0.0;
                for (int a = 0; a < sub; ++a)
                    for (int b = 0; b < sub; ++b) {
                        double z = -1.0 + 2.0 * iz / nz + (a + 0.5) * dz;
                        double phi = 2 * M_PI * ip / nphi + (b + 0.5) * dphi;
                        double r = std::sqrt(std::max(0.0, 1 - z * z));
                        Vector3f wi(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
                        sum += bsdf->pdf(si, wo, wi, lambda, TransportMode::Radiance) * dz * dphi;
                    }
                exp[std::size_t(iz * nphi + ip)] = sum * n;
            }
        auto r = stats::chiSquareTest(obs, exp);
        INFO("theta_o = " << theta << ": " << r.summary());
        CHECK(r.passes(0.01));
    }
}

TEST_CASE("diffuse: albedo is the reflectance, the default albedo estimate agrees", "[bsdf]") {
    SurfaceInteraction si;
    auto lambda = SampledWavelengths::sampleVisible(0.5f);
    for (double rho : {0.0, 0.3, 1.0}) {
        auto bsdf = makeDiffuse(rho);
        SampledSpectrum a = bsdf->albedo(si, lambda);
        for (int k = 0; k < NSpectrumSamples; ++k) CHECK(a[k] == Approx(rho));
        // The base class's numerical estimate, called directly, gives the same value.
        SampledSpectrum d = bsdf->IBSDF::albedo(si, lambda);
        for (int k = 0; k < NSpectrumSamples; ++k) CHECK(d[k] == Approx(rho).margin(1e-5));
    }
    // Default estimate for BSDFs that do not override it: uniform sampling (integrand
    // 2ρ cos θ, stratified) and a delta lobe (weight 0.8).
    UniformLambert uniform(0.6f);
    CHECK(uniform.albedo(si, lambda)[0] == Approx(0.6f).epsilon(2e-3));
    Mirror mirror;
    CHECK(mirror.albedo(si, lambda)[2] == Approx(0.8f).epsilon(1e-5));
}

TEST_CASE("diffuse: grazing angles give finite, non-negative values", "[bsdf]") {
    auto bsdf = makeDiffuse(0.9);
    SurfaceInteraction si;
    auto lambda = SampledWavelengths::sampleVisible(0.1f);
    const float c = 1e-6f, s = std::sqrt(1.f - c * c);
    Vector3f grazing(s, 0.f, c), normal(0.f, 0.f, 1.f);
    for (auto [wo, wi] : {std::pair{grazing, normal}, std::pair{normal, grazing}, std::pair{grazing, grazing}}) {
        SampledSpectrum f = bsdf->f(si, wo, wi, lambda, TransportMode::Radiance);
        float pdf = bsdf->pdf(si, wo, wi, lambda, TransportMode::Radiance);
        CHECK(f.isFinite());
        CHECK(f[0] >= 0.f);
        CHECK(std::isfinite(pdf));
        CHECK(pdf >= 0.f);
    }
    // Samples from a grazing view and at the rim of the sample square.
    for (Point2f u : {Point2f(OneMinusEpsilon, 0.5f), Point2f(0.5f, OneMinusEpsilon), Point2f(0.f, 0.f)}) {
        SampledWavelengths l = lambda;
        auto bs = bsdf->sample(si, grazing, 0.5f, u, l, TransportMode::Radiance);
        if (!bs) continue;
        CHECK(bs->f.isFinite());
        CHECK(std::isfinite(bs->pdf));
        CHECK(bs->pdf > 0.f);
        CHECK(std::isfinite(bs->f[0] * bs->wi.z / bs->pdf));
    }
}

TEST_CASE("diffuse: bad parameters are errors", "[bsdf]") {
    Properties p("bsdf", "diffuse");
    p.set("reflectance", 1.5);
    CHECK_THROWS_AS(Registry::instance().create("bsdf", "diffuse", p), Error);
    Properties q("bsdf", "diffuse");
    q.set("reflectanse", 0.5);
    CHECK_THROWS_WITH(Registry::instance().create("bsdf", "diffuse", q), Catch::Contains("reflectance"));
}
