// bsdf "diffuse" from a plugin — test fixture with the name of a built-in component.
// A correct Lambertian (f = ρ/π, cosine-weighted sampling); its schema's doc line says
// where it comes from, so a test can see which of the two `effigi info` describes
// (tests/plugins/run_plugin_tests.cmake).
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/math/warp_functions.hpp"

namespace {
using namespace effigi;

class ShadowDiffuse final : public Implements<IBSDF> {
public:
    static Schema schema() {
        Schema s("bsdf", "diffuse", "Plugin replacing the built-in diffuse (test fixture).");
        s.real("reflectance", 0.5, "Albedo ρ").range(0.0, 1.0);
        return s;
    }
    explicit ShadowDiffuse(const Properties& p) : m_rho(p.getFloat("reflectance")) {}

    std::uint32_t flags() const override { return BSDFReflection | BSDFDiffuse; }
    SampledSpectrum f(const SurfaceInteraction&, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&,
                      TransportMode) const override {
        return SampledSpectrum(wo.z > 0.f && wi.z > 0.f ? m_rho * InvPi : 0.f);
    }
    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float, const Point2f& u,
                                     SampledWavelengths& lambda, TransportMode mode) const override {
        BSDFSample bs;
        bs.wi = warp::squareToCosineHemisphere(u);
        bs.pdf = pdf(si, wo, bs.wi, lambda, mode);
        if (!(bs.pdf > 0.f)) return std::nullopt;
        bs.f = f(si, wo, bs.wi, lambda, mode);
        bs.flags = BSDFReflection | BSDFDiffuse;
        return bs;
    }
    float pdf(const SurfaceInteraction&, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&,
              TransportMode) const override {
        return wo.z > 0.f && wi.z > 0.f ? warp::squareToCosineHemispherePdf(wi) : 0.f;
    }

private:
    float m_rho;
};

} // namespace

EFFIGI_EXPORT_COMPONENT(ShadowDiffuse)
