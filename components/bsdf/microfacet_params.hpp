#pragma once
// The microfacet parameters shared by the rough BSDFs (roughconductor, roughdielectric),
// named and defaulted as in Mitsuba 3: `distribution` (beckmann | ggx), `alpha` or the
// pair `alpha_u` / `alpha_v` (roughness along the shading tangent and bitangent), and
// `sample_visible` (sample the visible normals rather than all of D).
#include "effigi/core/properties.hpp"
#include "effigi/core/schema.hpp"
#include "effigi/render/microfacet.hpp"

namespace effigi {

inline void declareMicrofacet(Schema& s) {
    s.string("distribution", "beckmann", "Microfacet normal distribution: beckmann or ggx").oneOf({"beckmann", "ggx"});
    s.real("alpha", 0.1, "Isotropic roughness α (beckmann: √2 × the RMS slope); values below 1e-4 act as 1e-4")
        .range(0.0, 4.0);
    s.optional("alpha_u", ParamType::Float, "Anisotropic roughness along the tangent (with alpha_v, instead of alpha)")
        .range(0.0, 4.0);
    s.optional("alpha_v", ParamType::Float, "Anisotropic roughness along the bitangent (with alpha_u)").range(0.0, 4.0);
    s.boolean("sample_visible", true, "Sample the normals visible from the incident direction (lower variance)");
}

/// The distribution the parameters describe; errors for half an anisotropic pair, or
/// alpha given together with it (as Mitsuba).
inline MicrofacetDistribution readMicrofacet(const Properties& p) {
    MicrofacetType type = p.getString("distribution") == "ggx" ? MicrofacetType::GGX : MicrofacetType::Beckmann;
    bool hasU = p.has("alpha_u"), hasV = p.has("alpha_v");
    if (hasU != hasV)
        failAt(p.whereOf(hasU ? "alpha_u" : "alpha_v"), "{}: give both 'alpha_u' and 'alpha_v', or 'alpha'",
               p.describe());
    if (!hasU) return {type, p.getFloat("alpha"), p.getFloat("alpha")};
    if (const Properties::Entry* e = p.find("alpha"); e && !e->fromDefault)
        failAt(e->where, "{}: give either 'alpha' or 'alpha_u' and 'alpha_v', not both", p.describe());
    return {type, p.getFloat("alpha_u"), p.getFloat("alpha_v")};
}

} // namespace effigi
