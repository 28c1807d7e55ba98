// null, mask and blendbsdf, and the path renderer's pass-through surfaces: the null lobe
// (wi = −wo, weight 1, not a bounce), mask as a blend of its BSDF and the null lobe,
// blendbsdf as the weighted sum of two BSDFs, shadow rays through null and mask
// surfaces (Scene::transmittance), and an end-to-end render against Mitsuba 3's volpath.
#include "../components/bsdf/delta_bsdf.hpp"
#include "../components/bsdf/null_lobe.hpp"
#include "bsdf_helpers.hpp"
#include "reference_regions.hpp"

#include "conformance/conformance.hpp"
#include "effigi/core/error.hpp"
#include "effigi/math/rng.hpp"

#include <filesystem>

#include <catch2/catch.hpp>

using namespace effigi;
using namespace effigi::test;

namespace {

const SurfaceInteraction NoSi{};
using Params = std::vector<std::pair<std::string, PropertyValue>>;

Vector3f randomDirection(PCG32& rng) {
    float z = 1.f - 2.f * rng.nextFloat(), phi = 2.f * Pi * rng.nextFloat(), s = std::sqrt(std::max(0.f, 1.f - z * z));
    return {s * std::cos(phi), s * std::sin(phi), z};
}

PropertyValue nested(const std::string& type, const Params& params = {}) {
    return ComponentValue{"bsdf", makeBSDF(type, params)};
}

std::optional<BSDFSample> sampleAt(const IBSDF& b, const Vector3f& wo, float uc, Point2f u = Point2f(0.3f, 0.6f)) {
    SampledWavelengths l = SampledWavelengths::constant(550.f);
    return b.sample(NoSi, wo, uc, u, l, TransportMode::Radiance);
}

/// A null BSDF whose shadow-ray transmission (0.5) disagrees with its sampled
/// pass-through weight (1): what the conformance suite's null check must catch.
class InconsistentNull final : public DeltaBSDF {
public:
    std::uint32_t flags() const override { return BSDFNull; }
    std::optional<BSDFSample> sample(const SurfaceInteraction&, const Vector3f& wo, float, const Point2f&,
                                     SampledWavelengths&, TransportMode) const override {
        return nullLobeSample(wo, 1.f, SampledSpectrum(1.f));
    }
    SampledSpectrum evalNullTransmission(const SurfaceInteraction&, const SampledWavelengths&) const override {
        return SampledSpectrum(0.5f);
    }
};

/// The conformance suite (quick) on bsdf components named `name`.
conform::Session conformOn(const std::string& name) {
    static std::once_flag once;
    std::call_once(once, [] {
        Schema s("bsdf", "test_inconsistent_null", "test component (tests/test_mask_null.cpp)");
        Registry::instance().add(
            ComponentInfo{s, [](const Properties&) -> Ref<IComponent> { return std::make_shared<InconsistentNull>(); }, {}});
    });
    conform::Options o;
    o.tag = "bsdf";
    o.component = name;
    o.quick = true;
    o.threads = 1;
    o.outDir = std::filesystem::temp_directory_path() / "effigi-test-mask-null";
    conform::Session session(o);
    session.run();
    return session;
}

} // namespace

TEST_CASE("conformance: null and mask pass, a null lobe inconsistent with its transmission fails", "[bsdf][mask]") {
    for (const char* name : {"null", "mask"}) {
        conform::Session s = conformOn(name);
        INFO(name);
        CHECK(s.count(conform::Verdict::Fail) == 0);
        CHECK(s.count(conform::Verdict::Pass) >= 5);
        CHECK(s.find(name, "delta").size() >= 1);  // the null lobe is checked as a delta
    }
    conform::Session bad = conformOn("test_inconsistent_null");
    auto rows = bad.find("test_inconsistent_null", "delta");
    REQUIRE(rows.size() == 1);
    CHECK(rows[0]->verdict == conform::Verdict::Fail);
    std::filesystem::remove_all(std::filesystem::temp_directory_path() / "effigi-test-mask-null");
}

TEST_CASE("null: a pass-through lobe only", "[bsdf][null]") {
    Ref<IBSDF> b = makeBSDF("null", {});
    CHECK(b->flags() == BSDFNull);
    CHECK(b->isPureSpecular());
    PCG32 rng(3, 1);
    SampledWavelengths l = SampledWavelengths::constant(550.f);
    for (int i = 0; i < 100; ++i) {
        Vector3f wo = randomDirection(rng), wi = randomDirection(rng);
        CHECK(b->f(NoSi, wo, wi, l, TransportMode::Radiance).isBlack());
        CHECK(b->pdf(NoSi, wo, wi, l, TransportMode::Radiance) == 0.f);
        auto bs = sampleAt(*b, wo, rng.nextFloat());
        REQUIRE(bs);
        CHECK((bs->flags & BSDFNull));
        CHECK(bs->wi == -wo);
        CHECK(weight(*bs) == Approx(1.f));
    }
    CHECK(b->evalNullTransmission(NoSi, l)[0] == 1.f);
}

TEST_CASE("mask: opacity blends the nested BSDF with the null lobe", "[bsdf][mask]") {
    Params inner = {{"reflectance", 0.6}};
    Ref<IBSDF> diffuse = makeBSDF("diffuse", inner);
    SampledWavelengths l = SampledWavelengths::constant(550.f);
    SECTION("opacity 1 is the nested BSDF, opacity 0 is null") {
        Ref<IBSDF> opaque = makeBSDF("mask", {{"opacity", 1.0}, {"bsdf", nested("diffuse", inner)}});
        Ref<IBSDF> clear = makeBSDF("mask", {{"opacity", 0.0}, {"bsdf", nested("diffuse", inner)}});
        CHECK(opaque->flags() == diffuse->flags());
        CHECK(clear->flags() == BSDFNull);
        Vector3f wo = directionFromCos(0.7f), wi = directionFromCos(0.4f, 2.f);
        CHECK(opaque->f(NoSi, wo, wi, l, TransportMode::Radiance)[0] ==
              diffuse->f(NoSi, wo, wi, l, TransportMode::Radiance)[0]);
        CHECK(clear->f(NoSi, wo, wi, l, TransportMode::Radiance).isBlack());
        CHECK(opaque->evalNullTransmission(NoSi, l)[0] == 0.f);
        CHECK(clear->evalNullTransmission(NoSi, l)[0] == 1.f);
        auto bs = sampleAt(*clear, wo, 0.99f);
        REQUIRE(bs);
        CHECK(bs->wi == -wo);
    }
    SECTION("opacity 0.3: f scaled, the null lobe sampled 70 % of the time with weight 1") {
        Ref<IBSDF> b = makeBSDF("mask", {{"opacity", 0.3}, {"bsdf", nested("diffuse", inner)}});
        CHECK((b->flags() & BSDFNull));
        CHECK(b->evalNullTransmission(NoSi, l)[0] == Approx(0.7f));
        PCG32 rng(5, 9);
        const int n = 20000;
        int nulls = 0;
        for (int i = 0; i < n; ++i) {
            Vector3f wo = directionFromCos(0.2f + 0.8f * rng.nextFloat(), 6.f * rng.nextFloat());
            Vector3f wi = directionFromCos(0.1f + 0.9f * rng.nextFloat(), 6.f * rng.nextFloat());
            if (i < 200) {
                CHECK(b->f(NoSi, wo, wi, l, TransportMode::Radiance)[0] ==
                      Approx(0.3f * diffuse->f(NoSi, wo, wi, l, TransportMode::Radiance)[0]));
                CHECK(b->pdf(NoSi, wo, wi, l, TransportMode::Radiance) ==
                      Approx(0.3f * diffuse->pdf(NoSi, wo, wi, l, TransportMode::Radiance)));
            }
            auto bs = sampleAt(*b, wo, rng.nextFloat(), Point2f(rng.nextFloat(), rng.nextFloat()));
            REQUIRE(bs);
            if (bs->flags & BSDFNull) {
                ++nulls;
                CHECK(weight(*bs) == Approx(1.f));
            } else {
                CHECK(weight(*bs) == Approx(0.6f));  // the nested diffuse sample's own weight
            }
        }
        // Binomial(n, 0.7): 5 standard deviations, two-sided false alarm 6e-7.
        CHECK(std::abs(nulls - 0.7 * n) < 5.0 * std::sqrt(n * 0.7 * 0.3));
    }
}

TEST_CASE("blendbsdf: the weighted sum of its two BSDFs", "[bsdf][blendbsdf]") {
    Params d = {{"reflectance", 0.9}}, r = {{"distribution", std::string("ggx")}, {"alpha", 0.3}};
    Ref<IBSDF> a = makeBSDF("diffuse", d), c = makeBSDF("roughconductor", r);
    for (double w : {0.0, 0.25, 1.0}) {
        Ref<IBSDF> b = makeBSDF("blendbsdf", {{"weight", w}, {"bsdf_0", nested("diffuse", d)},
                                             {"bsdf_1", nested("roughconductor", r)}});
        if (w == 0.0) CHECK(b->flags() == a->flags());
        if (w == 1.0) CHECK(b->flags() == c->flags());
        PCG32 rng(2, 8);
        SampledWavelengths l = SampledWavelengths::constant(550.f);
        for (int i = 0; i < 500; ++i) {
            Vector3f wo = randomDirection(rng), wi = randomDirection(rng);
            float fa = a->f(NoSi, wo, wi, l, TransportMode::Radiance)[0];
            float fc = c->f(NoSi, wo, wi, l, TransportMode::Radiance)[0];
            float pa = a->pdf(NoSi, wo, wi, l, TransportMode::Radiance);
            float pc = c->pdf(NoSi, wo, wi, l, TransportMode::Radiance);
            CHECK(b->f(NoSi, wo, wi, l, TransportMode::Radiance)[0] ==
                  Approx((1.0 - w) * fa + w * fc).epsilon(1e-5).margin(1e-7));
            CHECK(b->pdf(NoSi, wo, wi, l, TransportMode::Radiance) ==
                  Approx((1.0 - w) * pa + w * pc).epsilon(1e-5).margin(1e-7));
        }
    }
}

TEST_CASE("blendbsdf: the weight is required, as in Mitsuba", "[bsdf][blendbsdf]") {
    CHECK_THROWS_AS(makeBSDF("blendbsdf", {{"bsdf_0", nested("diffuse")}, {"bsdf_1", nested("diffuse")}}), Error);
    CHECK_THROWS_AS(makeBSDF("blendbsdf", {{"weight", 0.5}, {"bsdf_0", nested("diffuse")}}), Error);
}

TEST_CASE("path: null and mask surfaces are crossed by camera, BSDF and shadow rays", "[render][mask]") {
    // Reference: Mitsuba 3.9.1 scalar_spectral volpath, 4096 spp (command in the scene
    // file). Margin 3 % per region and channel: at 2048 spp effigi agrees to 1.4 %.
    // Were shadow rays stopped at the null plane above the scene, every direct-lighting
    // term would vanish (the image would lose more than half of its light).
    compareWithReference("tests/data/mask/mask_null.xml", "tests/data/mask/mask_null-mitsuba.exr", {{"spp", "256"}},
                         {{"image", 0.f, 0.f, 1.f, 1.f},
                          {"behind the mask", 0.f, .2f, .5f, .7f},
                          {"inside the null sphere", .55f, .3f, .95f, .7f},
                          {"floor", 0.f, .7f, 1.f, 1.f}},
                         0.03);
}

TEST_CASE("path: a null crossing is not a bounce", "[render][mask]") {
    // max_depth = 1 shows only emitters seen directly. The top right corner sees the
    // constant environment (radiance 0.2, grey) through the null plane at y = 3, the top
    // left sees it through the null plane and the masked panel (opacity 0.4): 0.2 and
    // 0.12. If a crossing counted as a segment, both would be black.
    xml::ParseOptions opt;
    opt.defines = {{"spp", "256"}, {"max_depth", "1"}};
    auto s = loadSceneFile(EFFIGI_SOURCE_DIR "/tests/data/mask/mask_null.xml", opt);
    CHECK(s->hasNullBSDFs());
    RenderControl control;
    control.progress = false;
    s->renderer().render(*s, control);
    Image img = s->camera().film().develop();
    // Hero-wavelength noise and the mask's choice only: over 24 pixels at 256 spp the
    // means' standard errors are far below the 3 % allowed.
    auto mean = [&](int x0, int y0, int c) {
        double sum = 0.0;
        for (int y = y0; y < y0 + 3; ++y)
            for (int x = x0; x < x0 + 8; ++x) sum += img.at(x, y, c);
        return sum / 24.0;
    };
    for (int c = 0; c < 3; ++c) {
        CHECK(mean(img.width - 8, 0, c) == Approx(0.2).epsilon(0.03));
        CHECK(mean(0, 6, c) == Approx(0.6 * 0.2).epsilon(0.03));
    }
}

TEST_CASE("scene: the plain occlusion test stays for scenes without null surfaces", "[render][mask]") {
    auto s = loadSceneFile(EFFIGI_SOURCE_DIR "/tests/data/plastic/spheres.xml", {});
    CHECK_FALSE(s->hasNullBSDFs());
}

TEST_CASE("scene: transmittance multiplies the null transmissions along a shadow ray", "[render][mask]") {
    // Up and sideways from the red sphere's top, out of the null sphere around it and
    // through the null plane at y = 3 to the sky: nothing absorbs. From under the white
    // sphere straight up, its body blocks.
    auto s = loadSceneFile(EFFIGI_SOURCE_DIR "/tests/data/mask/mask_null.xml", {});
    SampledWavelengths l = SampledWavelengths::constant(550.f);
    Ray up{Point3f(1.2f, 0.81f, 0.f), normalize(Vector3f(0.6f, 1.f, 0.f)), Infinity};  // past the light
    CHECK(s->transmittance(up, l)[0] == 1.f);
    Ray blocked{Point3f(-1.1f, -0.9f, 0.f), Vector3f(0.f, 1.f, 0.f), Infinity};
    CHECK(s->transmittance(blocked, l)[0] == 0.f);
    // Through the masked panel (opacity 0.4, at z = 1.6) toward the camera: 0.6 is left.
    Ray through{Point3f(-1.2f, 0.3f, 1.f), Vector3f(0.f, 0.f, 1.f), Infinity};
    CHECK(s->transmittance(through, l)[0] == Approx(0.6f));
    // A finite shadow ray that ends before the panel crosses nothing.
    Ray shortRay{Point3f(-1.2f, 0.3f, 1.f), Vector3f(0.f, 0.f, 0.5f), 1.f};
    CHECK(s->transmittance(shortRay, l)[0] == 1.f);
}
