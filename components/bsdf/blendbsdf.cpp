// bsdf "blendbsdf" — a linear blend of two BSDFs (Mitsuba 3's blendbsdf):
//
//   f = (1 − w) f₀ + w f₁,   w = weight(x) in [0, 1] (a float or a texture)
//
// Sampling picks BSDF 1 with probability w and BSDF 0 with 1 − w (the random number uc
// is rescaled and reused), then reports the mixture: for a sample in a smooth lobe, f and
// pdf are the blend's f() and pdf() (both nested densities, weighted), as Mitsuba does;
// for a delta sample, f and pdf are the chosen BSDF's scaled by its weight and its
// selection probability, so the sample weight is that BSDF's own.
//
// Parameters (as Mitsuba 3):
//   weight   texture (float in [0, 1], required)  0: only the first BSDF, 1: only the second
//   two nested bsdf (the first, then the second)
//
// Reference: Mitsuba 3 documentation, "Blended material (blendbsdf)"; Veach 1997, §9.2
// (one-sample model of a mixture).
#include "nested_bsdf.hpp"

#include "effigi/interfaces/itexture.hpp"

namespace effigi {
namespace {

class BlendBSDF final : public Implements<IBSDF> {
public:
    static Schema schema() {
        Schema s("bsdf", "blendbsdf", "Linear blend of two BSDFs by a weight (float or texture).");
        s.cite("Mitsuba 3 documentation, Blended material (blendbsdf)");
        s.optional("weight", ParamType::Texture, "Blend weight w: 0 gives the first BSDF, 1 the second (required)")
            .range(0.0, 1.0)
            .isRequired();
        s.child("bsdf", "bsdf_0", "The first nested BSDF (weight 1 − w)").isRequired();
        s.child("bsdf", "bsdf_1", "The second nested BSDF (weight w)").isRequired();
        auto diffuse = nestedBSDF("diffuse", {{"reflectance", 0.9}});
        auto rough = nestedBSDF("roughconductor", {{"distribution", std::string("ggx")}, {"alpha", 0.3}});
        auto glass = nestedBSDF("dielectric");
        auto plastic = nestedBSDF("roughplastic", {{"alpha", 0.2}});
        auto add = [&](const std::string& name, double w, const auto& a, const auto& b) {
            if (a && b) s.addConformance({name, {{"weight", w}, {"bsdf_0", *a}, {"bsdf_1", *b}}});
        };
        add("diffuse + roughconductor 0.3", 0.3, diffuse, rough);
        add("weight 0", 0.0, diffuse, rough);
        add("weight 1", 1.0, diffuse, rough);
        add("diffuse + dielectric 0.5", 0.5, diffuse, glass);
        add("roughplastic + roughconductor 0.7", 0.7, plastic, rough);
        return s;
    }

    explicit BlendBSDF(const Properties& p)
        : m_weight(p.getTexture("weight", SpectrumKind::Reflectance)), m_bsdf{p.get<IBSDF>("bsdf_0"), p.get<IBSDF>("bsdf_1")} {
        // A constant weight of 0 or 1 selects one BSDF: only its lobes are present.
        m_flags = m_bsdf[0]->flags() | m_bsdf[1]->flags();
        if (m_weight->isConstant()) {
            float w = m_weight->evalFloat(SurfaceInteraction{});
            if (w <= 0.f) m_flags = m_bsdf[0]->flags();
            else if (w >= 1.f) m_flags = m_bsdf[1]->flags();
        }
    }

    std::uint32_t flags() const override { return m_flags; }

    SampledSpectrum f(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                      const SampledWavelengths& lambda, TransportMode mode) const override {
        float w = weight(si);
        SampledSpectrum out(0.f);
        if (w < 1.f) out += m_bsdf[0]->f(si, wo, wi, lambda, mode) * (1.f - w);
        if (w > 0.f) out += m_bsdf[1]->f(si, wo, wi, lambda, mode) * w;
        return out;
    }

    float pdf(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths& lambda,
              TransportMode mode) const override {
        float w = weight(si), out = 0.f;
        if (w < 1.f) out += m_bsdf[0]->pdf(si, wo, wi, lambda, mode) * (1.f - w);
        if (w > 0.f) out += m_bsdf[1]->pdf(si, wo, wi, lambda, mode) * w;
        return out;
    }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float uc, const Point2f& u,
                                     SampledWavelengths& lambda, TransportMode mode) const override {
        float w = weight(si);
        // BSDF 1 on [0, w), BSDF 0 on [w, 1); uc rescaled to [0, 1) within the part.
        int k = uc < w ? 1 : 0;
        float prob = k ? w : 1.f - w;
        float ucK = std::min(k ? uc / w : (uc - w) / (1.f - w), OneMinusEpsilon);
        std::optional<BSDFSample> bs = m_bsdf[k]->sample(si, wo, ucK, u, lambda, mode);
        if (!bs || !(bs->pdf > 0.f)) return std::nullopt;
        if (bs->isSpecular()) {
            bs->f *= prob;
            bs->pdf *= prob;
            return bs;
        }
        bs->f = f(si, wo, bs->wi, lambda, mode);
        bs->pdf = pdf(si, wo, bs->wi, lambda, mode);
        return bs;
    }

    SampledSpectrum albedo(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        float w = weight(si);
        return m_bsdf[0]->albedo(si, lambda) * (1.f - w) + m_bsdf[1]->albedo(si, lambda) * w;
    }

    SampledSpectrum evalNullTransmission(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        float w = weight(si);
        return m_bsdf[0]->evalNullTransmission(si, lambda) * (1.f - w) + m_bsdf[1]->evalNullTransmission(si, lambda) * w;
    }

private:
    float weight(const SurfaceInteraction& si) const { return std::clamp(m_weight->evalFloat(si), 0.f, 1.f); }

    Ref<ITexture> m_weight;
    Ref<IBSDF> m_bsdf[2];
    std::uint32_t m_flags = 0;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::BlendBSDF)
