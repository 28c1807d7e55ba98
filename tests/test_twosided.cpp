// The `twosided` adapter: the front is the nested BSDF unchanged, the back the nested (or
// second) BSDF in the frame mirrored through the surface, opposite sides get nothing, and
// transmitting BSDFs are refused.
#include "bsdf_helpers.hpp"

#include "effigi/math/rng.hpp"
#include "effigi/render/fresnel.hpp"

#include <catch2/catch.hpp>

using namespace effigi;
using namespace effigi::test;

namespace {

const SurfaceInteraction NoSi{};

Vector3f mirrored(const Vector3f& w) { return {w.x, w.y, -w.z}; }

Vector3f randomDirection(PCG32& rng) {
    float z = 1.f - 2.f * rng.nextFloat(), phi = 2.f * Pi * rng.nextFloat(), s = std::sqrt(std::max(0.f, 1.f - z * z));
    return {s * std::cos(phi), s * std::sin(phi), z};
}

PropertyValue nested(const std::string& type, const std::vector<std::pair<std::string, PropertyValue>>& params = {}) {
    return ComponentValue{"bsdf", makeBSDF(type, params)};
}

} // namespace

TEST_CASE("twosided: the back is the front mirrored through the surface", "[bsdf][twosided]") {
    std::vector<std::pair<std::string, PropertyValue>> rough = {
        {"distribution", std::string("ggx")}, {"alpha_u", 0.1}, {"alpha_v", 0.4}, {"material", std::string("Cu")}};
    Ref<IBSDF> inner = makeBSDF("roughconductor", rough);
    Ref<IBSDF> b = makeBSDF("twosided", {{"bsdf", nested("roughconductor", rough)}});
    CHECK(b->flags() == inner->flags());
    PCG32 rng(7, 3);
    int compared = 0;
    for (int i = 0; i < 2000; ++i) {
        Vector3f wo = randomDirection(rng), wi = randomDirection(rng);
        SampledWavelengths l = SampledWavelengths::sampleVisible(rng.nextFloat());
        for (TransportMode mode : {TransportMode::Radiance, TransportMode::Importance}) {
            SampledSpectrum f = b->f(NoSi, wo, wi, l, mode);
            float pdf = b->pdf(NoSi, wo, wi, l, mode);
            if (wo.z * wi.z < 0.f) {  // opposite sides: no transmission
                CHECK(f.isBlack());
                CHECK(pdf == 0.f);
                continue;
            }
            // Above: the nested BSDF itself; below: the nested BSDF of the mirrored pair.
            Vector3f a = wo.z > 0.f ? wo : mirrored(wo), c = wo.z > 0.f ? wi : mirrored(wi);
            SampledSpectrum fi = inner->f(NoSi, a, c, l, mode);
            for (int k = 0; k < NSpectrumSamples; ++k) CHECK(f[k] == fi[k]);
            CHECK(pdf == inner->pdf(NoSi, a, c, l, mode));
            compared += !fi.isBlack();
        }
        // sample() from below returns the nested sample, mirrored.
        float uc = rng.nextFloat();
        Point2f u(rng.nextFloat(), rng.nextFloat());
        SampledWavelengths l1 = l, l2 = l;
        auto s = b->sample(NoSi, wo, uc, u, l1, TransportMode::Radiance);
        auto si = inner->sample(NoSi, wo.z > 0.f ? wo : mirrored(wo), uc, u, l2, TransportMode::Radiance);
        REQUIRE(bool(s) == bool(si));
        if (!s) continue;
        CHECK(s->wi == (wo.z > 0.f ? si->wi : mirrored(si->wi)));
        CHECK(s->wi.z * wo.z > 0.f);
        CHECK(s->pdf == si->pdf);
    }
    CHECK(compared > 500);  // the lobe was actually hit from both sides
}

TEST_CASE("twosided: a second BSDF is the back, and a delta back stays a delta", "[bsdf][twosided]") {
    Ref<IBSDF> b = makeBSDF("twosided", {{"bsdf", nested("diffuse", {{"reflectance", 0.8}})},
                                         {"bsdf_back", nested("conductor", {{"eta", 0.2}, {"k", 3.0}})}});
    CHECK(b->flags() == (BSDFReflection | BSDFDiffuse | BSDFSpecular));
    SampledWavelengths l = SampledWavelengths::constant(550.f);
    Vector3f up = normalize(Vector3f(0.3f, 0.2f, 0.9f)), down = mirrored(up);
    // Front: the diffuse, 0.8/π.
    CHECK(b->f(NoSi, up, normalize(Vector3f(-0.5f, 0.1f, 0.7f)), l, TransportMode::Radiance)[0] ==
          Approx(0.8f * InvPi));
    // Back: the conductor's mirror direction, below the surface, with weight F.
    auto s = b->sample(NoSi, down, 0.5f, {0.3f, 0.6f}, l, TransportMode::Radiance);
    REQUIRE(s);
    CHECK(s->isSpecular());
    CHECK(s->wi == Vector3f(-down.x, -down.y, down.z));
    CHECK(weight(*s) == Approx(fresnelConductor(0.9f / length(Vector3f(0.3f, 0.2f, 0.9f)), 0.2f, 3.f)).epsilon(1e-5));
    CHECK(b->f(NoSi, down, normalize(Vector3f(0.1f, 0.1f, -0.9f)), l, TransportMode::Radiance).isBlack());
}

TEST_CASE("twosided: a transmitting nested BSDF is refused, naming it", "[bsdf][twosided]") {
    std::string message;
    try {
        makeBSDF("twosided", {{"bsdf", nested("roughdielectric")}});
    } catch (const Error& e) {
        message = e.what();
    }
    CHECK_THAT(message, Catch::Contains("roughdielectric") && Catch::Contains("reflection-only"));
    CHECK_THROWS_AS(makeBSDF("twosided", {}), Error);  // the nested BSDF is required
}
