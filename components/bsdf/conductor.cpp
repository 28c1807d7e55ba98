// bsdf "conductor" — a smooth metal: an ideal mirror whose reflectance is the Fresnel
// reflectance of a conductor with complex index of refraction η + ik.
//
// Reflection only, a Dirac delta in the mirror direction: sample() returns wi =
// reflect(wo) with probability 1 and the weight f·|cosθ|/pdf = F(cosθ; η, k) · R, where R
// is specular_reflectance; f() and pdf() are zero. One-sided like Mitsuba 3's conductor:
// seen from below the surface it is black.
//
// Parameters (as Mitsuba 3):
//   material              string  "none" (a 100 % mirror, η = 0, k = 1) or a metal with
//                                 measured data in data/spectra (Au, Ag, Cu, Al, Cr, Ni,
//                                 Pt, Ti, W: <name>-eta.csv and <name>-k.csv)
//   eta, k                texture (unbounded spectrum)  the complex index, instead of material
//   specular_reflectance  texture (reflectance, default 1)  multiplies the Fresnel term
//
// Reference: M. Born & E. Wolf, Principles of Optics, 7th ed., §14.2 (reflection at a
// metal); the Fresnel evaluation is in effigi/render/fresnel.hpp.
#include "conductor_ior.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/render/fresnel.hpp"

namespace effigi {
namespace {

class Conductor final : public Implements<IBSDF> {
public:
    static Schema schema() {
        Schema s("bsdf", "conductor", "Smooth conductor (metal mirror) with a spectral complex index of refraction.");
        s.cite("M. Born, E. Wolf, Principles of Optics, 7th ed., 1999, §14.2");
        declareConductorIOR(s);
        s.texture("specular_reflectance", 1.f, SpectrumKind::Reflectance,
                  "Factor on the Fresnel reflectance (not physical; for artistic control)")
            .range(0.0, 1.0);
        // effigi-conform: ordinary and extreme parameters (index-matched, dense and very absorbing).
        s.addConformance({"default", {}});
        s.addConformance({"gold", {{"material", std::string("Au")}}});
        s.addConformance({"eta 4, k 10", {{"eta", 4.0}, {"k", 10.0}}});
        s.addConformance({"eta 1.0001, k 0", {{"eta", 1.0001}, {"k", 0.0}}});
        return s;
    }

    explicit Conductor(const Properties& p)
        : m_reflectance(p.getTexture("specular_reflectance", SpectrumKind::Reflectance)) {
        ConductorIOR ior = readConductorIOR(p);
        m_eta = ior.eta;
        m_k = ior.k;
    }

    std::uint32_t flags() const override { return BSDFReflection | BSDFSpecular; }

    SampledSpectrum f(const SurfaceInteraction&, const Vector3f&, const Vector3f&, const SampledWavelengths&,
                      TransportMode) const override {
        return SampledSpectrum(0.f);
    }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float, const Point2f&,
                                     SampledWavelengths& lambda, TransportMode) const override {
        float cosTheta = wo.z;
        if (!(cosTheta > 0.f)) return std::nullopt;  // one-sided: black from behind
        BSDFSample bs;
        bs.wi = reflectLocal(wo);
        bs.pdf = 1.f;
        bs.flags = BSDFReflection | BSDFSpecular;
        SampledSpectrum F = fresnelConductor(cosTheta, m_eta->eval(si, lambda), m_k->eval(si, lambda));
        // The delta's weight: f·|cosθ|/pdf = F·R.
        bs.f = F * m_reflectance->eval(si, lambda) / cosTheta;
        return bs;
    }

    float pdf(const SurfaceInteraction&, const Vector3f&, const Vector3f&, const SampledWavelengths&,
              TransportMode) const override {
        return 0.f;
    }

    /// Reflectance at normal incidence: F(1) · R.
    SampledSpectrum albedo(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        return fresnelConductor(1.f, m_eta->eval(si, lambda), m_k->eval(si, lambda)) * m_reflectance->eval(si, lambda);
    }

private:
    Ref<ITexture> m_reflectance, m_eta, m_k;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Conductor)
