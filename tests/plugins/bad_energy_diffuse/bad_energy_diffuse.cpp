// bsdf "bad_energy_diffuse" — DELIBERATELY WRONG test plugin: a Lambertian BRDF that
// reflects 1.3 times what it receives, f = 1.3·ρ/π, so its directional albedo is 1.3·ρ.
//
// Everything else is consistent (cosine-weighted sampling whose pdf() matches, a
// reciprocal f), so effigi-conform must single out the energy check: with ρ = 0.9 and 1
// the albedo is 1.17 and 1.3, far above 1 (tests/plugins/run_plugin_tests.cmake).
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/math/warp_functions.hpp"

namespace {
using namespace effigi;

constexpr float Gain = 1.3f;  // the bug: an energy-conserving Lambertian has 1

class BadEnergyDiffuse final : public Implements<IBSDF> {
public:
    static Schema schema() {
        Schema s("bsdf", "bad_energy_diffuse", "Test plugin: a diffuse BRDF with albedo 1.3·ρ (gains energy).");
        s.texture("reflectance", 0.9f, SpectrumKind::Reflectance, "ρ; the BRDF is 1.3·ρ/π").range(0.0, 1.0);
        s.addConformance({"default", {}});
        s.addConformance({"white", {{"reflectance", 1.0}}});
        return s;
    }

    explicit BadEnergyDiffuse(const Properties& p) : m_reflectance(p.getTexture("reflectance", SpectrumKind::Reflectance)) {}

    std::uint32_t flags() const override { return BSDFReflection | BSDFDiffuse; }

    SampledSpectrum f(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                      const SampledWavelengths& lambda, TransportMode) const override {
        if (!(wo.z > 0.f && wi.z > 0.f)) return SampledSpectrum(0.f);
        return m_reflectance->eval(si, lambda) * (Gain * InvPi);
    }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float, const Point2f& u,
                                     SampledWavelengths& lambda, TransportMode mode) const override {
        if (!(wo.z > 0.f)) return std::nullopt;
        BSDFSample bs;
        bs.wi = warp::squareToCosineHemisphere(u);
        bs.pdf = warp::squareToCosineHemispherePdf(bs.wi);
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
    Ref<ITexture> m_reflectance;
};

} // namespace

EFFIGI_EXPORT_COMPONENT(BadEnergyDiffuse)
