// bsdf "mask" — an opacity mask over a BSDF (Mitsuba 3's mask): where the opacity α is 1
// the surface is the nested BSDF, where it is 0 it is invisible (cut-out leaves, fences),
// in between a blend of the two:
//
//   f = α f_nested,   and a pass-through (BSDFNull) lobe of weight 1 − α along −wo.
//
// Sampling takes the nested BSDF with probability α (uc rescaled and reused), else the
// pass-through with 1 − α and weight 1. evalNullTransmission() = 1 − α is what a shadow
// ray keeps when it crosses the surface (renderer/path).
//
// Parameters (as Mitsuba 3):
//   opacity  texture (float in [0, 1], default 0.5)  1: opaque, 0: fully transparent
//   one nested bsdf
//
// Reference: Mitsuba 3 documentation, "Opacity mask (mask)".
#include "nested_bsdf.hpp"
#include "null_lobe.hpp"

#include "effigi/interfaces/itexture.hpp"

namespace effigi {
namespace {

class Mask final : public Implements<IBSDF> {
public:
    static Schema schema() {
        Schema s("bsdf", "mask", "Opacity mask: the nested BSDF where opaque, a pass-through (null) lobe elsewhere.");
        s.cite("Mitsuba 3 documentation, Opacity mask (mask)");
        s.texture("opacity", 0.5f, SpectrumKind::Reflectance, "Opacity α: 1 is the nested BSDF, 0 is invisible")
            .range(0.0, 1.0);
        s.child("bsdf", "bsdf", "The nested BSDF (the opaque part)").isRequired();
        auto diffuse = nestedBSDF("diffuse", {{"reflectance", 0.8}});
        auto rough = nestedBSDF("roughplastic", {{"distribution", std::string("ggx")}, {"alpha", 0.3}});
        auto glass = nestedBSDF("dielectric");
        auto add = [&](const std::string& name, double a, const auto& b) {
            if (b) s.addConformance({name, {{"opacity", a}, {"bsdf", *b}}});
        };
        add("diffuse 0.5", 0.5, diffuse);
        add("diffuse opacity 0", 0.0, diffuse);
        add("diffuse opacity 1", 1.0, diffuse);
        add("roughplastic 0.3", 0.3, rough);
        add("dielectric 0.6", 0.6, glass);
        return s;
    }

    explicit Mask(const Properties& p)
        : m_opacity(p.getTexture("opacity", SpectrumKind::Reflectance)), m_bsdf(p.get<IBSDF>("bsdf")) {
        // A constant opacity of 1 (or 0) leaves out the pass-through (or the nested)
        // lobes: a renderer then sees an opaque surface (or a pure null one).
        m_flags = m_bsdf->flags() | BSDFNull;
        if (m_opacity->isConstant()) {
            float a = m_opacity->evalFloat(SurfaceInteraction{});
            if (a >= 1.f) m_flags = m_bsdf->flags();
            else if (a <= 0.f) m_flags = BSDFNull;
        }
    }

    std::uint32_t flags() const override { return m_flags; }

    SampledSpectrum f(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                      const SampledWavelengths& lambda, TransportMode mode) const override {
        float a = opacity(si);
        return a > 0.f ? m_bsdf->f(si, wo, wi, lambda, mode) * a : SampledSpectrum(0.f);
    }

    float pdf(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths& lambda,
              TransportMode mode) const override {
        float a = opacity(si);
        return a > 0.f ? m_bsdf->pdf(si, wo, wi, lambda, mode) * a : 0.f;
    }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float uc, const Point2f& u,
                                     SampledWavelengths& lambda, TransportMode mode) const override {
        float a = opacity(si);
        if (!(uc < a)) return nullLobeSample(wo, 1.f - a, SampledSpectrum(1.f - a));
        std::optional<BSDFSample> bs = m_bsdf->sample(si, wo, std::min(uc / a, OneMinusEpsilon), u, lambda, mode);
        if (!bs || !(bs->pdf > 0.f)) return std::nullopt;
        // Scaling f and pdf alike keeps the nested sample's weight; for a smooth lobe
        // both then equal this BSDF's f() and pdf().
        bs->f *= a;
        bs->pdf *= a;
        return bs;
    }

    SampledSpectrum albedo(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        return m_bsdf->albedo(si, lambda) * opacity(si);
    }

    SampledSpectrum evalNullTransmission(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        float a = opacity(si);
        return m_bsdf->evalNullTransmission(si, lambda) * a + SampledSpectrum(1.f - a);
    }

private:
    float opacity(const SurfaceInteraction& si) const { return std::clamp(m_opacity->evalFloat(si), 0.f, 1.f); }

    Ref<ITexture> m_opacity;
    Ref<IBSDF> m_bsdf;
    std::uint32_t m_flags = 0;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::Mask)
