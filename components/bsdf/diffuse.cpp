// bsdf "diffuse" — ideal diffuse (Lambertian) reflection.
//
// Models a surface that scatters incident light equally into every direction of the
// hemisphere above it: f(wo, wi) = ρ/π for wo and wi on the side of the shading
// normal, zero otherwise. Like Mitsuba 3's `diffuse` it is ONE-SIDED: seen from below
// the surface is black (wrap it in `twosided` to reflect on both sides).
//
// Sampling: directions are drawn through a warp (issue 14, "warps in use"; the choice is
// effigi/render/warp_choice.hpp, the lobe's helpers components/bsdf/cosine_lobe.hpp).
// - Default: the compile-time cosine warp, i.e. exactly the code the warp component
//   `cosine_hemisphere` wraps (warp::squareToCosineHemisphere and its pdf, Malley's
//   method), so f·cos/pdf = ρ exactly; tests/test_warps_in_use.cpp checks bit-exact
//   equality with the component for many u.
// - A nested `warp` (any IWarp with a Sphere domain, e.g. `uniform_hemisphere` or a
//   plugin) replaces it: wi = warp.sample(u), pdf = warp.pdf(wi) in sample() and pdf().
//   f is unchanged, so any warp whose support covers the upper hemisphere gives an
//   unbiased (only noisier or less noisy) estimator. A direction with z ≤ 0 or a
//   non-positive / non-finite density is no sample (zero contribution, never NaN).
//
// Parameters:
//   reflectance  texture (reflectance spectrum, default 0.5)  albedo ρ in [0, 1]
//   warp         nested warp (optional)  the direction sampler; default cosine-weighted
//
// Reference: J. H. Lambert, Photometria (1760); pbrt-v4 §9.2 for the sampling.
#include "cosine_lobe.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/itexture.hpp"

namespace effigi {
namespace {

class Diffuse final : public Implements<IBSDF> {
public:
    static Schema schema() {
        Schema s("bsdf", "diffuse", "Ideal diffuse (Lambertian) reflection, one-sided.");
        s.cite("J. H. Lambert, Photometria, 1760");
        s.texture("reflectance", 0.5f, SpectrumKind::Reflectance,
                  "Albedo ρ (spectrum or texture); f = ρ/π above the surface")
            .range(0.0, 1.0);
        declareDiffuseWarp(s, "the reflection");
        s.addConformance({"default", {}});
        s.addConformance({"black", {{"reflectance", 0.0}}});
        s.addConformance({"white", {{"reflectance", 1.0}}});
        s.addConformance({"saturated rgb", {{"reflectance", RGBValue{{0.98f, 0.02f, 0.01f}}}}});
        // No configuration with a nested warp here: it would be made with the schema and
        // load a warp module whenever diffuse's schema is asked for (test_registry requires
        // that to load diffuse alone). tests/test_warps_in_use.cpp checks nested warps.
        return s;
    }

    explicit Diffuse(const Properties& p)
        : m_reflectance(p.getTexture("reflectance", SpectrumKind::Reflectance)), m_warp(p) {}

    std::uint32_t flags() const override { return BSDFReflection | BSDFDiffuse; }

    SampledSpectrum f(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                      const SampledWavelengths& lambda, TransportMode) const override {
        if (!(wo.z > 0.f && wi.z > 0.f)) return SampledSpectrum(0.f);
        return m_reflectance->eval(si, lambda) * InvPi;
    }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float, const Point2f& u,
                                     SampledWavelengths& lambda, TransportMode) const override {
        if (!(wo.z > 0.f)) return std::nullopt;
        Vector3f wi = m_warp.sample(u);
        float pdf = m_warp.pdf(wi);
        // Below or on the surface f = 0 (the rim of the disk maps to wi.z = 0, whose cosine
        // density is zero): no usable sample, never a NaN.
        if (!(wi.z > 0.f) || !(pdf > 0.f)) return std::nullopt;
        BSDFSample bs;
        bs.f = m_reflectance->eval(si, lambda) * InvPi;
        bs.wi = wi;
        bs.pdf = pdf;
        bs.flags = BSDFReflection | BSDFDiffuse;
        return bs;
    }

    float pdf(const SurfaceInteraction&, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&,
              TransportMode) const override {
        return oneSidedPdf(m_warp, wo, wi);
    }

    /// The hemispherical reflectance of a Lambertian surface is ρ for every wo.
    SampledSpectrum albedo(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        return m_reflectance->eval(si, lambda);
    }

private:
    Ref<ITexture> m_reflectance;
    DiffuseWarp m_warp;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Diffuse)
