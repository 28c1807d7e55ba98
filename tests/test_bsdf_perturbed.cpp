// The shading-normal adapters of issue 10: normalmap and bumpmap — a flat normal map or a
// constant height is the nested BSDF, a bump is the normal map of its slope, tilted maps
// keep the adjoint law that effigi-conform does not check (tilted normals are not
// reciprocal) and conserve energy; the (u, v) derivatives bumps need; parameter errors.
// Statistical checks are seeded; each states its significance level.
#include "bsdf_extra_helpers.hpp"
#include "shape_helpers.hpp"

#include "effigi/core/error.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/math/rng.hpp"

#include <catch2/catch.hpp>

using namespace effigi;
using namespace effigi::test;

namespace {

/// A test texture: height h = a u + b v (gradient (a, b)), and a fixed raw RGB triple.
class LinearTexture final : public Implements<ITexture> {
public:
    LinearTexture(Vector2f grad, Vector3f rgb) : m_grad(grad), m_rgb(rgb) {}
    SampledSpectrum eval(const SurfaceInteraction& si, const SampledWavelengths&) const override {
        return SampledSpectrum(evalFloat(si));
    }
    float evalFloat(const SurfaceInteraction& si) const override { return m_grad.x * si.uv.x + m_grad.y * si.uv.y; }
    float maxValue() const override { return std::abs(m_grad.x) + std::abs(m_grad.y); }
    Vector3f evalVector(const SurfaceInteraction&) const override { return m_rgb; }
    Vector2f evalFloatGradient(const SurfaceInteraction&) const override { return m_grad; }

private:
    Vector2f m_grad;
    Vector3f m_rgb;
};

PropertyValue texture(Vector2f grad, Vector3f rgb = Vector3f(0.5f, 0.5f, 1.f)) {
    return ComponentValue{"texture", std::make_shared<LinearTexture>(grad, rgb)};
}
PropertyValue nested(const std::string& type, const Params& params = {}) {
    return ComponentValue{"bsdf", makeBSDF(type, params)};
}

} // namespace

// ---- normalmap ---------------------------------------------------------------------

TEST_CASE("normalmap: a flat map is the nested BSDF", "[bsdf][normalmap]") {
    SurfaceInteraction si = probe();
    Params rough = {{"distribution", std::string("ggx")}, {"alpha", 0.2}};
    Ref<IBSDF> inner = makeBSDF("roughconductor", rough);
    Ref<IBSDF> viaRGB = makeBSDF("normalmap", {{"bsdf", nested("roughconductor", rough)},
                                               {"normalmap", RGBValue{{0.5f, 0.5f, 1.f}}}});
    Ref<IBSDF> viaTexture = makeBSDF("normalmap", {{"bsdf", nested("roughconductor", rough)},
                                                   {"normalmap", texture(Vector2f(0.f))}});
    requireSameBSDF(*viaRGB, *inner, si, 1e-5f, 6);
    requireSameBSDF(*viaTexture, *inner, si, 1e-5f, 7);
}

TEST_CASE("normalmap: a tilted diffuse surface reflects rho/pi cos to the tilted normal", "[bsdf][normalmap]") {
    // With the options off f·|cos θi| is Mitsuba's value: ρ/π max(0, wi·n) wherever wo and
    // wi see both the original and the tilted surface from above.
    SurfaceInteraction si = probe();
    Vector3f rgb(0.75f, 0.4f, 0.9f), n = normalize(2.f * rgb - Vector3f(1.f));
    Ref<IBSDF> b = makeBSDF("normalmap", {{"bsdf", nested("diffuse", {{"reflectance", 0.8}})},
                                          {"normalmap", RGBValue{rgb}},
                                          {"flip_invalid_normals", false},
                                          {"use_shadowing_function", false}});
    SampledWavelengths l = SampledWavelengths::constant(550.f);
    PCG32 rng(13, 4);
    int compared = 0;
    for (int i = 0; i < 3000; ++i) {
        Vector3f wo = upperDirection(rng), wi = upperDirection(rng);
        float value = b->f(si, wo, wi, l, TransportMode::Radiance)[0] * wi.z;
        bool visible = dot(wo, n) > 0.f && dot(wi, n) > 0.f;
        if (!visible) {
            REQUIRE(value == 0.f);
            continue;
        }
        ++compared;
        REQUIRE(value == Approx(0.8 * InvPi * dot(wi, n)).epsilon(1e-4));
    }
    CHECK(compared > 1000);
}

TEST_CASE("normalmap: tilted maps keep the adjoint law, sample consistently, conserve energy", "[bsdf][normalmap]") {
    SurfaceInteraction si = probe();
    Vector3f rgb(0.8f, 0.35f, 0.85f);
    for (const char* inner : {"diffuse", "roughconductor"}) {
        Ref<IBSDF> b = makeBSDF("normalmap", {{"bsdf", nested(inner, {})},
                                              {"normalmap", RGBValue{rgb}},
                                              {"flip_invalid_normals", false}});
        PCG32 rng(31, 6);
        SampledWavelengths l = SampledWavelengths::constant(550.f);
        for (int i = 0; i < 3000; ++i) {
            Vector3f a = randomDirection(rng), c = randomDirection(rng);
            // Importance mode is the adjoint of radiance mode (Veach 1997, §5.3).
            REQUIRE(b->f(si, a, c, l, TransportMode::Importance)[0] ==
                    Approx(b->f(si, c, a, l, TransportMode::Radiance)[0]).epsilon(1e-4).margin(1e-7));
            for (TransportMode m : {TransportMode::Radiance, TransportMode::Importance}) {
                auto bs = b->sample(si, a, rng.nextFloat(), Point2f(rng.nextFloat(), rng.nextFloat()), l, m);
                if (!bs) continue;
                REQUIRE(bs->f[0] == Approx(b->f(si, a, bs->wi, l, m)[0]).epsilon(1e-3).margin(1e-6));
                REQUIRE(bs->pdf == Approx(b->pdf(si, a, bs->wi, l, m)).epsilon(1e-3));
            }
        }
        // Radiance mode conserves energy: the albedo is the nested one over the directions
        // both surfaces pass (5 standard errors: one-sided level ~3e-7).
        for (float c : {1.f, 0.6f, 0.2f}) {
            auto [albedo, se] = sampledAlbedo(*b, si, directionFromCos(c, 2.f), 100000, 23);
            CHECK(albedo <= 1.0 + 5 * se);
        }
    }
}

TEST_CASE("normalmap: the normal map is required", "[bsdf][normalmap]") {
    CHECK_THROWS_AS(makeBSDF("normalmap", {{"bsdf", nested("diffuse")}}), Error);
}

// ---- bumpmap -----------------------------------------------------------------------

TEST_CASE("bumpmap: a constant height is the nested BSDF", "[bsdf][bumpmap]") {
    SurfaceInteraction si = probe();
    Ref<IBSDF> inner = makeBSDF("diffuse", {{"reflectance", 0.6}});
    Ref<IBSDF> b = makeBSDF("bumpmap", {{"bsdf", nested("diffuse", {{"reflectance", 0.6}})},
                                        {"height", texture(Vector2f(0.f))}, {"scale", 40.0}});
    requireSameBSDF(*b, *inner, si, 1e-6f, 8);
}

TEST_CASE("bumpmap: a sloped height is the normal map of its slope", "[bsdf][bumpmap]") {
    // h = a u + b v scaled by s on a unit (u, v) parametrisation tilts the normal to
    // (−s a, −s b, 1) normalised (Blinn 1978): the same BSDF as that normal map, both with
    // Mitsuba's options on. The texture carries any name (as Mitsuba allows).
    SurfaceInteraction si = probe();
    const float a = 0.3f, bb = -0.5f, s = 1.5f;
    Vector3f n = normalize(Vector3f(-s * a, -s * bb, 1.f));
    Params rough = {{"distribution", std::string("ggx")}, {"alpha", 0.3}};
    Ref<IBSDF> bump = makeBSDF("bumpmap", {{"bsdf", nested("roughconductor", rough)},
                                           {"my_bumps", texture(Vector2f(a, bb))}, {"scale", double(s)}});
    Ref<IBSDF> normal = makeBSDF("normalmap", {{"bsdf", nested("roughconductor", rough)},
                                               {"normalmap", RGBValue{0.5f * (n + Vector3f(1.f))}}});
    requireSameBSDF(*bump, *normal, si, 2e-3f, 9);
    // Without (u, v) derivatives (an analytic shape that gives none) the shading tangents
    // stand in: the same frame here.
    SurfaceInteraction bare = si;
    bare.dpdu = bare.dpdv = Vector3f(0.f);
    requireSameBSDF(*bump, *normal, bare, 2e-3f, 10);
}

TEST_CASE("bumpmap: exactly one height texture", "[bsdf][bumpmap]") {
    CHECK_THROWS_AS(makeBSDF("bumpmap", {{"bsdf", nested("diffuse")}}), Error);
    CHECK_THROWS_AS(makeBSDF("bumpmap", {{"bsdf", nested("diffuse")}, {"h1", texture(Vector2f(0.f))},
                                         {"h2", texture(Vector2f(1.f))}}),
                    Error);
}

TEST_CASE("bumpmap: spheres and disks give the (u, v) derivatives it needs", "[bsdf][bumpmap]") {
    // First order: between two nearby hits p2 − p1 ≈ ∂p/∂u Δu + ∂p/∂v Δv (the residual is
    // second order, ~|Δp|² / radius), away from the poles, the centre and the u seam.
    for (const char* type : {"sphere", "disk"}) {
        Properties props("shape", type);
        if (std::string(type) == "sphere") {
            props.set("radius", 2.0);
            props.set("center", PointValue{{0.3f, -0.2f, 0.5f}});
        } else {
            props.set("to_world", Transform::translate({0.3f, -0.2f, 0.5f}) * Transform::scale(Vector3f(2.f)));
        }
        Ref<IShape> shape = test::makeShape(type, props);
        PCG32 rng(19, 7);
        int checked = 0;
        for (int i = 0; i < 200; ++i) {
            Point2f q(0.3f + 1.0f * rng.nextFloat(), 0.2f + 1.0f * rng.nextFloat());
            auto hitAt = [&](Point2f o, SurfaceInteraction& si) {
                Ray ray{Point3f(o.x, o.y - 0.2f, -10.f), Vector3f(0.f, 0.f, 1.f), Infinity};
                Hit hit;
                if (!test::trace(*shape, ray, hit)) return false;
                si = shape->interaction(ray, hit);
                return true;
            };
            SurfaceInteraction a, b;
            if (!hitAt(q, a) || !hitAt(q + Point2f(1e-3f, 7e-4f), b)) continue;
            Vector2f duv = b.uv - a.uv;
            if (std::abs(duv.x) > 0.1f || std::abs(duv.y) > 0.1f) continue;  // across the seam
            Vector3f dp = b.p - a.p, predicted = a.dpdu * duv.x + a.dpdv * duv.y;
            INFO(type << ": dp = (" << dp.x << ", " << dp.y << ", " << dp.z << "), predicted (" << predicted.x << ", "
                      << predicted.y << ", " << predicted.z << ")");
            REQUIRE(length(dp - predicted) < 0.02f * length(dp));
            ++checked;
        }
        CHECK(checked > 50);
    }
}
