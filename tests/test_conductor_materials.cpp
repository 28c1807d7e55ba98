// Mitsuba 3's conductor presets (the `material` names of its docs' conductor-ior-list):
// every documented name either loads, with a normal-incidence reflectance in [0, 1] that
// is the Fresnel reflectance of the shipped n + ik table, or (Cu2O, CuO, HgTe, Se, SnTe:
// refractiveindex.info has no usable visible data for them) fails with a one-line error
// that says so; a misspelt name gets a did-you-mean.
#include "bsdf_helpers.hpp"

#include "effigi/spectral/named.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

using namespace effigi;
using namespace effigi::test;

namespace {

const SurfaceInteraction NoSi{};

/// The presets Mitsuba 3 documents for conductor / roughconductor, besides "none".
const std::vector<std::string> MitsubaPresets = {
    "a-C",       "Ag",      "Al",         "AlAs",       "AlAs_palik", "AlSb",       "AlSb_palik", "Au",
    "Be",        "Be_palik", "Cr",        "CsI",        "CsI_palik",  "Cu",         "Cu_palik",   "Cu2O",
    "Cu2O_palik", "CuO",    "CuO_palik",  "d-C",        "d-C_palik",  "Hg",         "Hg_palik",   "HgTe",
    "HgTe_palik", "Ir",     "Ir_palik",   "K",          "K_palik",    "Li",         "Li_palik",   "MgO",
    "MgO_palik", "Mo",      "Mo_palik",   "Na_palik",   "Nb",         "Nb_palik",   "Ni_palik",   "Rh",
    "Rh_palik",  "Se",      "Se_palik",   "SiC",        "SiC_palik",  "SnTe",       "SnTe_palik", "Ta",
    "Ta_palik",  "Te",      "Te_palik",   "ThF4",       "ThF4_palik", "TiC",        "TiC_palik",  "TiN",
    "TiN_palik", "TiO2",    "TiO2_palik", "VC",         "VC_palik",   "V_palik",    "VN",         "VN_palik",
    "W"};

/// Presets without data in the database (data/README.md); they must be refused clearly.
const std::vector<std::string> WithoutData = {"Cu2O", "Cu2O_palik", "CuO", "CuO_palik", "HgTe",
                                              "HgTe_palik", "Se", "Se_palik", "SnTe", "SnTe_palik"};

std::string errorOf(const std::string& plugin, const std::string& material) {
    try {
        makeBSDF(plugin, {{"material", material}});
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

bool hasData(const std::string& name) {
    return std::find(WithoutData.begin(), WithoutData.end(), name) == WithoutData.end();
}

/// Weight of the delta reflection at normal incidence for one wavelength: F(1) of the metal.
float normalReflectance(const Ref<IBSDF>& b, float lambda) {
    SampledWavelengths l = SampledWavelengths::constant(lambda);
    auto s = b->sample(NoSi, Vector3f(0, 0, 1), 0.f, {0.f, 0.f}, l, TransportMode::Radiance);
    REQUIRE(s);
    return weight(*s);
}

} // namespace

TEST_CASE("conductor materials: every documented Mitsuba preset with data loads, R in [0, 1]",
          "[bsdf][conductor][materials]") {
    int loaded = 0;
    for (const std::string& name : MitsubaPresets) {
        if (!hasData(name)) continue;
        INFO("material " << name);
        Ref<IBSDF> b = makeBSDF("conductor", {{"material", name}});
        // Independent of the BSDF: the named tables themselves, through Fresnel's normal-
        // incidence formula |(n − 1 + ik)/(n + 1 + ik)|².
        Spectrum eta = namedSpectrum(name + "-eta"), k = namedSpectrum(name + "-k");
        for (float lambda : {360.f, 420.f, 500.f, 575.f, 650.f, 740.f, 830.f}) {
            INFO(lambda << " nm");
            double n = eta(lambda), kk = k(lambda);
            REQUIRE(n > 0.0);
            REQUIRE(kk >= 0.0);
            double expect = ((n - 1) * (n - 1) + kk * kk) / ((n + 1) * (n + 1) + kk * kk);
            float r = normalReflectance(b, lambda);
            CHECK(std::isfinite(r));
            CHECK(r > 0.f);
            CHECK(r <= 1.f);
            CHECK(r == Approx(expect).epsilon(1e-4));
        }
        ++loaded;
    }
    CHECK(loaded == int(MitsubaPresets.size() - WithoutData.size()));
}

TEST_CASE("conductor materials: the presets load in roughconductor too", "[bsdf][conductor][materials]") {
    // The corpus' textured carbon scenes use roughconductor with a-C.
    for (const char* name : {"a-C", "TiN", "Hg", "d-C_palik"}) {
        Ref<IBSDF> b = makeBSDF("roughconductor", {{"material", std::string(name)}, {"alpha", 0.2}});
        SampledWavelengths l = SampledWavelengths::constant(550.f);
        Vector3f wo = directionFromCos(0.8f), wi = directionFromCos(0.8f, 0.7f + Pi);
        SampledSpectrum f = b->f(NoSi, wo, wi, l, TransportMode::Radiance);
        INFO(name);
        CHECK(f.isFinite());
        CHECK(f[0] > 0.f);
    }
}

TEST_CASE("conductor materials: Mitsuba presets without data, and misspellings, are one-line errors",
          "[bsdf][conductor][materials]") {
    for (const std::string& name : WithoutData) {
        for (const char* plugin : {"conductor", "roughconductor"}) {
            std::string e = errorOf(plugin, name);
            INFO(plugin << " " << name << ": " << e);
            CHECK(e.find("'" + name + "'") != std::string::npos);
            CHECK(e.find("no data") != std::string::npos);
            CHECK(e.find('\n') == std::string::npos);
        }
    }
    // Near misses get the closest preset; the list of what is available comes with it.
    for (auto [wrong, right] : {std::pair{"a-c", "a-C"}, std::pair{"TiNN", "TiN"}, std::pair{"Hg_palk", "Hg_palik"}}) {
        std::string e = errorOf("conductor", wrong);
        INFO(e);
        CHECK(e.find(std::string("did you mean '") + right + "'") != std::string::npos);
        CHECK(e.find("available: ") != std::string::npos);
        CHECK(e.find("none") != std::string::npos);
        CHECK(e.find('\n') == std::string::npos);
    }
}
