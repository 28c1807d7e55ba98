#pragma once
// Helpers shared by the BSDF tests (test_dielectric, test_dispersion, test_conductor,
// test_microfacet*): creating a BSDF through the registry with parameters, a sample's
// weight f·|cos|/pdf, local directions, the smooth refraction direction.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/render/fresnel.hpp"

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
/// The local direction with cos θ = cosTheta (z flipped by side = −1) at azimuth phi.
inline Vector3f directionFromCos(float cosTheta, float phi = 0.7f, float side = 1.f) {
    float sinTheta = std::sqrt(std::max(0.f, 1.f - cosTheta * cosTheta));
    return {sinTheta * std::cos(phi), sinTheta * std::sin(phi), side * cosTheta};
}

/// The smooth refraction of wo through the macro surface (direction of the α → 0 lobe).
inline Vector3f smoothRefraction(const Vector3f& wo, float eta) {
    Vector3f wt;
    float etaRel;
    REQUIRE(refractLocal(wo, eta, wt, etaRel));
    return wt;
}

inline float weight(const BSDFSample& s, int i = 0) { return s.f[i] * std::abs(s.wi.z) / s.pdf; }

/// A tabulated spectrum value as the XML parser writes it.
inline SpectrumValue tabulated(std::vector<float> lambdas, std::vector<float> values) {
    SpectrumValue s;
    s.lambdas = std::move(lambdas);
    s.values = std::move(values);
    return s;
}

} // namespace effigi::test
