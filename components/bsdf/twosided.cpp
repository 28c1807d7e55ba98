// bsdf "twosided" — makes a one-sided BSDF reflect on both sides of the surface.
//
// The one-sided BSDFs (diffuse, conductor, roughconductor, as in Mitsuba 3) are black
// seen from below the shading normal. twosided applies its nested BSDF on the front and,
// in a frame mirrored through the surface (z → −z), on the back: for wo and wi both below
// the surface f(wo, wi) = f_back(wo', wi') with w' = (wx, wy, −wz); sample() and pdf()
// likewise, the sampled direction mirrored back. A second nested BSDF, if given, is used
// on the back instead of the first (Mitsuba's two-material form). Directions on opposite
// sides get nothing: the nested BSDFs must be reflection-only, since a transmitted
// direction would be mirrored to the wrong side (Mitsuba refuses them too).
//
// Parameters (as Mitsuba 3): one or two nested bsdf (front, then back).
//
// Reference: Mitsuba 3 documentation, "Two-sided BRDF adapter (twosided)" (the scene
// grammar); the mirroring is the reciprocity-preserving reflection of the local frame.
#include "nested_bsdf.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"

namespace effigi {
namespace {

/// The direction in the frame mirrored through the surface.
Vector3f mirrored(const Vector3f& w) { return {w.x, w.y, -w.z}; }

class TwoSided final : public Implements<IBSDF> {
public:
    static Schema schema() {
        Schema s("bsdf", "twosided", "Two-sided adapter: a reflection-only BSDF on both sides of the surface.");
        s.cite("Mitsuba 3 documentation, Two-sided BRDF adapter (twosided)");
        s.child("bsdf", "bsdf", "The nested BSDF (front, and back unless a second is given)").isRequired();
        s.child("bsdf", "bsdf_back", "A second nested BSDF, for the back (the second unnamed <bsdf>)");
        // effigi-conform: ordinary nested BSDFs, two materials, a nested delta lobe.
        auto diffuse = nestedBSDF("diffuse");
        auto rough = nestedBSDF("roughconductor", {{"distribution", std::string("ggx")}, {"alpha", 0.3},
                                                   {"material", std::string("Au")}});
        auto mirror = nestedBSDF("conductor");
        if (diffuse) s.addConformance({"diffuse", {{"bsdf", *diffuse}}});
        if (rough) s.addConformance({"roughconductor", {{"bsdf", *rough}}});
        if (diffuse && rough) s.addConformance({"diffuse front, roughconductor back", {{"bsdf", *diffuse}, {"bsdf_back", *rough}}});
        if (mirror) s.addConformance({"conductor", {{"bsdf", *mirror}}});
        return s;
    }

    explicit TwoSided(const Properties& p) : m_front(p.get<IBSDF>("bsdf")), m_back(p.get<IBSDF>("bsdf_back")) {
        if (!m_back) m_back = m_front;
        for (const char* name : {"bsdf", "bsdf_back"}) {
            Ref<IBSDF> b = p.get<IBSDF>(name);
            if (b && (b->flags() & BSDFTransmission))
                failAt(p.whereOf(name), "{}: the nested '{}' transmits light; twosided takes reflection-only BSDFs",
                       p.describe(), b->typeName());
        }
    }

    std::uint32_t flags() const override { return m_front->flags() | m_back->flags(); }

    SampledSpectrum f(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                      const SampledWavelengths& lambda, TransportMode mode) const override {
        if (wo.z > 0.f && wi.z > 0.f) return m_front->f(si, wo, wi, lambda, mode);
        if (wo.z < 0.f && wi.z < 0.f) return m_back->f(si, mirrored(wo), mirrored(wi), lambda, mode);
        return SampledSpectrum(0.f);
    }

    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float uc, const Point2f& u,
                                     SampledWavelengths& lambda, TransportMode mode) const override {
        if (!(wo.z < 0.f)) return m_front->sample(si, wo, uc, u, lambda, mode);
        std::optional<BSDFSample> bs = m_back->sample(si, mirrored(wo), uc, u, lambda, mode);
        if (bs) bs->wi = mirrored(bs->wi);
        return bs;
    }

    float pdf(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths& lambda,
              TransportMode mode) const override {
        if (wo.z > 0.f && wi.z > 0.f) return m_front->pdf(si, wo, wi, lambda, mode);
        if (wo.z < 0.f && wi.z < 0.f) return m_back->pdf(si, mirrored(wo), mirrored(wi), lambda, mode);
        return 0.f;
    }

    /// Seen from the normal: the front's albedo.
    SampledSpectrum albedo(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        return m_front->albedo(si, lambda);
    }

private:
    Ref<IBSDF> m_front, m_back;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::TwoSided)
