#pragma once
// Helpers shared by the BSDF tests (test_dielectric, test_dispersion, test_conductor):
// creating a BSDF through the registry with parameters, and a sample's weight f·|cos|/pdf.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"

#include <catch2/catch.hpp>

#include <string>
#include <utility>
#include <vector>

namespace effigi::test {

inline Ref<IBSDF> makeBSDF(const std::string& name, const std::vector<std::pair<std::string, PropertyValue>>& params) {
    Properties p("bsdf", name);
    for (const auto& [k, v] : params) p.set(k, v);
    Ref<IBSDF> b = query<IBSDF>(Registry::instance().create("bsdf", name, p));
    REQUIRE(b);
    return b;
}

/// f·|cosθi|/pdf of the sample's hero wavelength (all four for a constant spectrum).
inline float weight(const BSDFSample& s, int i = 0) { return s.f[i] * std::abs(s.wi.z) / s.pdf; }

/// A tabulated spectrum value as the XML parser writes it.
inline SpectrumValue tabulated(std::vector<float> lambdas, std::vector<float> values) {
    SpectrumValue s;
    s.lambdas = std::move(lambdas);
    s.values = std::move(values);
    return s;
}

} // namespace effigi::test
