#pragma once
// The microfacet parameters shared by the rough BSDFs (roughconductor, roughdielectric),
// named and defaulted as in Mitsuba 3: `distribution` (beckmann | ggx), `alpha` or the
// pair `alpha_u` / `alpha_v` (roughness along the shading tangent and bitangent), and
// `sample_visible` (sample the visible normals rather than all of D). Where Mitsuba
// texturises the roughness (roughconductor, roughdielectric) the alphas may be textures:
// MicrofacetParams then builds the distribution per surface point.
#include "effigi/core/properties.hpp"
#include "effigi/core/schema.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/render/microfacet.hpp"

namespace effigi {

/// `textured`: alpha, alpha_u, alpha_v also accept a nested or referenced texture.
inline void declareMicrofacet(Schema& s, bool textured = false) {
    s.string("distribution", "beckmann", "Microfacet normal distribution: beckmann or ggx").oneOf({"beckmann", "ggx"});
    const char* alphaDoc = "Isotropic roughness α (beckmann: √2 × the RMS slope); values below 1e-4 act as 1e-4";
    if (textured)
        s.texture("alpha", 0.1f, SpectrumKind::Unbounded, std::string(alphaDoc) + "; float or texture").range(0.0, 4.0);
    else
        s.real("alpha", 0.1, alphaDoc).range(0.0, 4.0);
    ParamType type = textured ? ParamType::Texture : ParamType::Float;
    s.optional("alpha_u", type, "Anisotropic roughness along the tangent (with alpha_v, instead of alpha)")
        .range(0.0, 4.0);
    s.optional("alpha_v", type, "Anisotropic roughness along the bitangent (with alpha_u)").range(0.0, 4.0);
    s.boolean("sample_visible", true, "Sample the normals visible from the incident direction (lower variance)");
}

/// The names holding αu and αv ("alpha" twice when isotropic); errors for half an
/// anisotropic pair, or alpha given together with it (as Mitsuba).
inline std::pair<const char*, const char*> microfacetAlphaNames(const Properties& p) {
    bool hasU = p.has("alpha_u"), hasV = p.has("alpha_v");
    if (hasU != hasV)
        failAt(p.whereOf(hasU ? "alpha_u" : "alpha_v"), "{}: give both 'alpha_u' and 'alpha_v', or 'alpha'",
               p.describe());
    if (!hasU) return {"alpha", "alpha"};
    if (const Properties::Entry* e = p.find("alpha"); e && !e->fromDefault)
        failAt(e->where, "{}: give either 'alpha' or 'alpha_u' and 'alpha_v', not both", p.describe());
    return {"alpha_u", "alpha_v"};
}

inline MicrofacetType microfacetType(const Properties& p) {
    return p.getString("distribution") == "ggx" ? MicrofacetType::GGX : MicrofacetType::Beckmann;
}

/// The distribution constant parameters describe (declared with textured = false).
inline MicrofacetDistribution readMicrofacet(const Properties& p) {
    auto [u, v] = microfacetAlphaNames(p);
    return {microfacetType(p), p.getFloat(u), p.getFloat(v)};
}

/// The half vector of a reflection pair, both directions above the surface (the rough
/// reflectors: roughconductor, roughplastic); false unless both lie on h's front. In
/// double, where the sum of two nearly opposite unit vectors keeps its digits.
inline bool reflectionHalfVector(const Vector3f& wo, const Vector3f& wi, Vector3f& h) {
    if (!(wo.z > 0.f && wi.z > 0.f)) return false;
    Vector3d s = Vector3d(wo) + Vector3d(wi);
    double len = glm::length(s);
    if (!(len > 0.0)) return false;
    h = Vector3f(s / len);
    return h.z > 0.f && dot(wo, h) > 0.f && dot(wi, h) > 0.f;
}

/// Roughness that may vary over the surface (declared with textured = true). Constant
/// alphas — the usual case — are read once into a fixed distribution, so a lookup
/// costs one predictable branch and no texture call.
class MicrofacetParams {
public:
    explicit MicrofacetParams(const Properties& p)
        : m_type(microfacetType(p)), m_constant(m_type, 0.1f, 0.1f) {
        auto [u, v] = microfacetAlphaNames(p);
        Ref<ITexture> tu = p.getTexture(u, SpectrumKind::Unbounded), tv = p.getTexture(v, SpectrumKind::Unbounded);
        if (tu->isConstant() && tv->isConstant()) {
            SurfaceInteraction any;
            m_constant = MicrofacetDistribution(m_type, sanitize(tu->evalFloat(any)), sanitize(tv->evalFloat(any)));
        } else {
            m_alphaU = std::move(tu);
            m_alphaV = std::move(tv);
        }
    }

    MicrofacetDistribution at(const SurfaceInteraction& si) const {
        if (!m_alphaU) return m_constant;
        return {m_type, sanitize(m_alphaU->evalFloat(si)), sanitize(m_alphaV->evalFloat(si))};
    }
    bool isTextured() const { return m_alphaU != nullptr; }

private:
    /// A texel may hold anything: NaN or negative roughness reads as the smoothest.
    static float sanitize(float a) { return a > 0.f ? std::min(a, 1e4f) : 0.f; }

    MicrofacetType m_type;
    MicrofacetDistribution m_constant;
    Ref<ITexture> m_alphaU, m_alphaV;  // null when both are constant
};

} // namespace effigi
