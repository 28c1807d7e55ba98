// bsdf "bad_pdf_bsdf" — DELIBERATELY WRONG test plugin: a Lambertian BRDF that samples
// directions cosine-weighted (density cos θ/π) while pdf() claims they are uniform over
// the hemisphere (1/2π).
//
// sample() reports pdf() for its samples, so f·cos/pdf is "consistent" with pdf() and
// the sample weight check cannot see the bug; pdf() still integrates to 1. The chi-square
// test of sample() against pdf() can: cos θ/π and 1/2π differ by a factor of 2 at the
// pole. So can the energy check at the reflectance's range end (1): the mean sampled
// weight ρ cos θ · 2 is 4/3 ρ while f() integrates to ρ (tests/plugins/run_plugin_tests.cmake).
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/math/warp_functions.hpp"

namespace {
using namespace effigi;

class BadPdfBsdf final : public Implements<IBSDF> {
public:
    static Schema schema() {
        Schema s("bsdf", "bad_pdf_bsdf", "Test plugin: samples cosine-weighted, pdf() says uniform hemisphere.");
        s.texture("reflectance", 0.5f, SpectrumKind::Reflectance, "Albedo ρ; f = ρ/π").range(0.0, 1.0);
        return s;
    }

    explicit BadPdfBsdf(const Properties& p) : m_reflectance(p.getTexture("reflectance", SpectrumKind::Reflectance)) {}

    std::uint32_t flags() const override { return BSDFReflection | BSDFDiffuse; }

    SampledSpectrum f(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                      const SampledWavelengths& lambda, TransportMode) const override {
        if (!(wo.z > 0.f && wi.z > 0.f)) return SampledSpectrum(0.f);
        return m_reflectance->eval(si, lambda) * InvPi;
    }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float, const Point2f& u,
                                     SampledWavelengths& lambda, TransportMode mode) const override {
        if (!(wo.z > 0.f)) return std::nullopt;
        BSDFSample bs;
        bs.wi = warp::squareToCosineHemisphere(u);  // density cos θ/π ...
        bs.pdf = pdf(si, wo, bs.wi, lambda, mode);   // ... reported as 1/2π: the bug
        if (!(bs.pdf > 0.f) || !(bs.wi.z > 0.f)) return std::nullopt;
        bs.f = f(si, wo, bs.wi, lambda, mode);
        bs.flags = BSDFReflection | BSDFDiffuse;
        return bs;
    }

    float pdf(const SurfaceInteraction&, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&,
              TransportMode) const override {
        return wo.z > 0.f && wi.z > 0.f ? warp::squareToUniformHemispherePdf(wi) : 0.f;
    }

private:
    Ref<ITexture> m_reflectance;
};

} // namespace

EFFIGI_EXPORT_COMPONENT(BadPdfBsdf)
