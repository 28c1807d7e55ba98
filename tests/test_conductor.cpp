// The `conductor` BSDF: the mirror direction and the delta's weight F·R, the measured
// metals (gold reflects more red than blue, as |(n − 1 + ik)/(n + 1 + ik)|² of the shipped
// table says), explicit η and k, and its error messages.
#include "bsdf_helpers.hpp"

#include "effigi/render/fresnel.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>

using namespace effigi;
using namespace effigi::test;

namespace {

const SurfaceInteraction NoSi{};

/// data/spectra/<name>.csv read here on its own (not through namedSpectrum) and
/// interpolated linearly, as an independent path to the measured values.
float tableValue(const std::string& name, float lambda) {
    std::ifstream in(std::string(EFFIGI_SOURCE_DIR) + "/data/spectra/" + name + ".csv");
    REQUIRE(in);
    std::string line;
    std::vector<std::pair<float, float>> rows;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#' || line == "lambda,value") continue;
        std::istringstream ss(line);
        float l, v;
        char comma;
        ss >> l >> comma >> v;
        rows.emplace_back(l, v);
    }
    for (std::size_t i = 1; i < rows.size(); ++i)
        if (lambda <= rows[i].first) {
            float t = (lambda - rows[i - 1].first) / (rows[i].first - rows[i - 1].first);
            return (1 - t) * rows[i - 1].second + t * rows[i].second;
        }
    return rows.back().second;
}

std::string errorOf(const std::string& name, const std::vector<std::pair<std::string, PropertyValue>>& params) {
    try {
        makeBSDF(name, params);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_CASE("conductor: a delta reflection with weight F·R", "[bsdf][conductor]") {
    Ref<IBSDF> b = makeBSDF("conductor", {{"eta", 0.2}, {"k", 3.0}, {"specular_reflectance", 0.5}});
    CHECK(b->flags() == (BSDFReflection | BSDFSpecular));
    for (float deg : {0.f, 45.f, 89.9f}) {
        float t = deg * Pi / 180.f;
        Vector3f wo(std::sin(t) * 0.8f, -std::sin(t) * 0.6f, std::cos(t));
        SampledWavelengths l = SampledWavelengths::sampleVisible(0.2f);
        auto s = b->sample(NoSi, wo, 0.7f, {0.3f, 0.9f}, l, TransportMode::Radiance);
        REQUIRE(s);
        CHECK(s->wi == reflectLocal(wo));  // mirror direction, whatever the random numbers
        CHECK(s->pdf == 1.f);
        CHECK(s->flags == (BSDFReflection | BSDFSpecular));
        CHECK(weight(*s) == Approx(0.5f * fresnelConductor(wo.z, 0.2f, 3.f)).epsilon(1e-5));
        CHECK(b->f(NoSi, wo, s->wi, l, TransportMode::Radiance).isBlack());
        CHECK(b->pdf(NoSi, wo, s->wi, l, TransportMode::Radiance) == 0.f);
        CHECK_FALSE(l.secondaryTerminated());
    }
    // One-sided: nothing from below; finite at grazing incidence.
    SampledWavelengths l = SampledWavelengths::constant(500.f);
    CHECK_FALSE(b->sample(NoSi, Vector3f(0, 0.6f, -0.8f), 0.5f, {0.5f, 0.5f}, l, TransportMode::Radiance));
    auto g = b->sample(NoSi, normalize(Vector3f(1, 0, 1e-6f)), 0.5f, {0.5f, 0.5f}, l, TransportMode::Radiance);
    REQUIRE(g);
    CHECK(g->f.isFinite());
    CHECK(weight(*g) == Approx(0.5f).epsilon(1e-4));  // F → 1 at grazing incidence
    // Normal-incidence albedo F(1)·R = 0.5 · 9.64/10.44.
    CHECK(b->albedo(NoSi, l)[0] == Approx(0.5 * 9.64 / 10.44).epsilon(1e-5));
}

TEST_CASE("conductor: material none is a perfect mirror", "[bsdf][conductor]") {
    Ref<IBSDF> b = makeBSDF("conductor", {});
    for (float c : {1.f, 0.5f, 1e-3f}) {
        Vector3f wo(std::sqrt(1 - c * c), 0, c);
        SampledWavelengths l = SampledWavelengths::sampleVisible(0.6f);
        auto s = b->sample(NoSi, wo, 0.f, {0.f, 0.f}, l, TransportMode::Radiance);
        REQUIRE(s);
        for (int i = 0; i < NSpectrumSamples; ++i) CHECK(weight(*s, i) == Approx(1.f).epsilon(1e-5));
    }
}

TEST_CASE("conductor: gold reflects red more than blue, as its measured index says", "[bsdf][conductor]") {
    Ref<IBSDF> gold = makeBSDF("conductor", {{"material", std::string("Au")}});
    auto reflectance = [&](float lambda) {
        SampledWavelengths l = SampledWavelengths::constant(lambda);
        auto s = gold->sample(NoSi, Vector3f(0, 0, 1), 0.f, {0.f, 0.f}, l, TransportMode::Radiance);
        REQUIRE(s);
        return weight(*s);
    };
    for (float lambda : {400.f, 450.f, 500.f, 550.f, 600.f, 650.f, 700.f}) {
        float n = tableValue("Au-eta", lambda), k = tableValue("Au-k", lambda);
        double expect = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
        INFO(lambda << " nm: n = " << n << ", k = " << k);
        CHECK(reflectance(lambda) == Approx(expect).epsilon(1e-4));
    }
    // Johnson & Christy's gold: about 0.41 at 450 nm, about 0.96 at 650 nm.
    CHECK(reflectance(650.f) > 0.9f);
    CHECK(reflectance(450.f) < 0.45f);
    CHECK(reflectance(650.f) > reflectance(550.f));
    CHECK(reflectance(550.f) > reflectance(450.f));
}

TEST_CASE("conductor: every shipped metal loads and stays in [0, 1]", "[bsdf][conductor]") {
    for (const char* metal : {"Au", "Ag", "Cu", "Al", "Cr", "Ni", "Pt", "Ti", "W"}) {
        Ref<IBSDF> b = makeBSDF("conductor", {{"material", std::string(metal)}});
        for (float lambda = 360.f; lambda <= 830.f; lambda += 10.f) {
            for (float c : {1.f, 0.5f, 1e-6f}) {
                SampledWavelengths l = SampledWavelengths::constant(lambda);
                auto s = b->sample(NoSi, Vector3f(std::sqrt(1 - c * c), 0, c), 0.f, {0.f, 0.f}, l,
                                   TransportMode::Radiance);
                REQUIRE(s);
                float w = weight(*s);
                INFO(metal << " at " << lambda << " nm, cos " << c);
                CHECK(std::isfinite(w));
                CHECK(w > 0.f);
                CHECK(w <= 1.f);
            }
        }
    }
    // Silver and aluminium are bright across the visible, copper is red.
    auto r = [](const char* m, float lambda) {
        float n = tableValue(std::string(m) + "-eta", lambda), k = tableValue(std::string(m) + "-k", lambda);
        return ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
    };
    CHECK(r("Ag", 550.f) > 0.95f);
    CHECK(r("Al", 550.f) > 0.9f);
    CHECK(r("Cu", 650.f) > r("Cu", 450.f) + 0.3f);
}

TEST_CASE("conductor: bad input is a one-line error", "[bsdf][conductor]") {
    std::string e = errorOf("conductor", {{"material", std::string("Gold")}});
    CHECK(e.find("'Gold'") != std::string::npos);
    CHECK(e.find("available: ") != std::string::npos);
    CHECK(e.find("Au") != std::string::npos);
    e = errorOf("conductor", {{"material", std::string("Cuu")}});
    CHECK(e.find("did you mean 'Cu'") != std::string::npos);
    e = errorOf("conductor", {{"material", std::string("Au")}, {"eta", 0.3}});
    CHECK(e.find("not both") != std::string::npos);
    e = errorOf("conductor", {{"k", -1.0}});
    CHECK(e.find("'k'") != std::string::npos);
    CHECK(e.find('\n') == std::string::npos);
}
