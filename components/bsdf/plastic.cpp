// bsdf "plastic" — a smooth dielectric coating over a diffuse substrate (Mitsuba 3's
// smooth plastic): a delta reflection off the coating, weighted by the Fresnel
// reflectance F(θo) and specular_reflectance, plus the substrate's diffuse light that
// crosses the coating twice (components/bsdf/plastic_common.hpp has the model):
//
//   f(wo, wi) = ρ / (1 − R_int·(ρ | 1)) · (1 − F(θo)) (1 − F(θi)) / (π η²)   (+ the delta)
//
// R_int = 1 − (2/η²) ∫ (1 − F(μ)) μ dμ, the diffuse Fresnel reflectance seen from inside,
// is integrated at construction (Simpson in a variable that removes the square-root
// kink at the critical angle). One-sided like Mitsuba's: black seen from below.
//
// Sampling: the delta with probability P ∝ F(θo)·w, else the cosine-weighted diffuse lobe
// (w: the specular sampling weight), drawn through the nested `warp` if one is given
// (plastic_common.hpp). The delta's weight is F·R_s / P.
//
// Parameters (as Mitsuba 3): int_ior (default "polypropylene", 1.49), ext_ior (default
// "air"), diffuse_reflectance (0.5), specular_reflectance (1), nonlinear (false); and
//   warp  nested warp (optional)  sampler of the diffuse lobe; default cosine-weighted
//
// References: A. Weidlich, A. Wilkie, "Arbitrarily Layered Micro-Facet Surfaces",
// GRAPHITE 2007; Mitsuba 3 documentation, "Smooth plastic material (plastic)".
#include "plastic_common.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/render/fresnel.hpp"

namespace effigi {
namespace {

/// ∫₀¹ (1 − F(μ)) μ dμ for the smooth coating. Below the critical cosine μc (η < 1) the
/// integrand is 0; above it behaves like √(μ − μc), so μ = μc + (1 − μc) s² makes it
/// smooth in s for Simpson's rule (1024 intervals: error far below float precision).
double smoothTransmittanceMoment(float eta) {
    double muC = eta < 1.f ? std::sqrt(std::max(0.0, 1.0 - double(eta) * eta)) : 0.0;
    auto g = [&](double s) {
        double mu = muC + (1.0 - muC) * s * s;
        return (1.0 - fresnelDielectric(float(mu), eta)) * mu * 2.0 * (1.0 - muC) * s;
    };
    constexpr int N = 1024;
    double sum = g(0.0) + g(1.0);
    for (int i = 1; i < N; ++i) sum += (i % 2 ? 4.0 : 2.0) * g(double(i) / N);
    return sum / (3.0 * N);
}

/// R_int of a smooth coating from the moment ∫ T μ dμ by reciprocity (the radiance form,
/// Veach 1997, §5.2): what a diffuse distribution inside transmits equals what enters
/// from a diffuse distribution outside, scaled by 1/η², so 1 − R_int = (2/η²) ∫ T μ dμ.
/// Mitsuba uses a polynomial fit of the same quantity (a few 1e-3 apart); the exact value
/// makes the model conserve energy exactly: a white plastic reflects all the light.
float internalReflectance(double moment, float eta) {
    double r = 1.0 - 2.0 * moment / (double(eta) * eta);
    return float(std::clamp(r, 0.0, 1.0 - 1e-6));
}

class Plastic final : public Implements<IBSDF> {
public:
    static Schema schema() {
        Schema s("bsdf", "plastic", "Smooth plastic: a specular dielectric coating over a diffuse substrate, one-sided.");
        s.cite("A. Weidlich, A. Wilkie, Arbitrarily Layered Micro-Facet Surfaces, GRAPHITE 2007; Mitsuba 3 plastic");
        declarePlastic(s);
        // effigi-conform: ordinary and extreme coatings and substrates.
        s.addConformance({"default", {}});
        s.addConformance({"white nonlinear", {{"diffuse_reflectance", 1.0}, {"nonlinear", true}}});
        s.addConformance({"white linear", {{"diffuse_reflectance", 1.0}}});
        s.addConformance({"black substrate", {{"diffuse_reflectance", 0.0}}});
        s.addConformance({"no specular", {{"specular_reflectance", 0.0}}});
        s.addConformance({"ior 1.0001", {{"int_ior", 1.0001}, {"ext_ior", 1.0}, {"diffuse_reflectance", 1.0}}});
        s.addConformance({"ior 3.5", {{"int_ior", 3.5}, {"ext_ior", 1.0}, {"diffuse_reflectance", 1.0}}});
        s.addConformance({"inverted (ior 1 in 1.5)", {{"int_ior", 1.0}, {"ext_ior", 1.5}, {"diffuse_reflectance", 1.0}}});
        s.addConformance({"named polypropylene, saturated rgb",
                          {{"int_ior", std::string("polypropylene")},
                           {"diffuse_reflectance", RGBValue{{0.98f, 0.02f, 0.01f}}},
                           {"nonlinear", true}}});
        return s;
    }

    explicit Plastic(const Properties& p) : m_params(p) {
        m_rInt = internalReflectance(smoothTransmittanceMoment(m_params.eta), m_params.eta);
    }

    std::uint32_t flags() const override { return BSDFReflection | m_params.lobes(BSDFSpecular); }

    SampledSpectrum f(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                      const SampledWavelengths& lambda, TransportMode) const override {
        if (!(wo.z > 0.f && wi.z > 0.f)) return SampledSpectrum(0.f);
        return m_params.substrate(si, lambda, transmittance(wo.z), transmittance(wi.z), m_rInt);
    }

    float pdf(const SurfaceInteraction&, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&,
              TransportMode) const override {
        if (!(wo.z > 0.f && wi.z > 0.f)) return 0.f;
        float pDiffuse = 1.f - m_params.specularProbability(transmittance(wo.z));
        return pDiffuse * m_params.diffuseWarp.pdf(wi);
    }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float uc, const Point2f& u,
                                     SampledWavelengths& lambda, TransportMode mode) const override {
        if (!(wo.z > 0.f)) return std::nullopt;  // one-sided
        float tO = transmittance(wo.z);
        float pSpecular = m_params.specularProbability(tO);
        BSDFSample bs;
        if (uc < pSpecular) {
            bs.wi = reflectLocal(wo);
            bs.pdf = pSpecular;
            // f·cosθ/pdf = F·R_s/P: the delta's weight.
            bs.f = m_params.specular->eval(si, lambda) * ((1.f - tO) / wo.z);
            bs.flags = BSDFReflection | BSDFSpecular;
            return bs;
        }
        bs.wi = m_params.diffuseWarp.sample(u);
        bs.pdf = pdf(si, wo, bs.wi, lambda, mode);
        if (!(bs.pdf > 0.f)) return std::nullopt;  // the rim of the disk (wi.z = 0), or below the surface
        bs.f = f(si, wo, bs.wi, lambda, mode);
        bs.flags = BSDFReflection | BSDFDiffuse;
        return bs;
    }

    /// Seen from the normal: F(0)·R_s + the diffuse part, integrated in closed form
    /// (∫ T(θi) cosθi/π dωi = 2 ∫ T μ dμ).
    SampledSpectrum albedo(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        float t0 = transmittance(1.f), eta2 = m_params.eta * m_params.eta;
        float diffuseOut = (1.f - m_rInt) * eta2;  // = 2 ∫ T μ dμ, by the reciprocity relation
        return m_params.specular->eval(si, lambda) * (1.f - t0) +
               m_params.substrate(si, lambda, t0, 1.f, m_rInt) * (Pi * diffuseOut);
    }

private:
    float transmittance(float cosTheta) const { return 1.f - fresnelDielectric(cosTheta, m_params.eta); }

    PlasticParams m_params;
    float m_rInt = 0.f;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Plastic)
