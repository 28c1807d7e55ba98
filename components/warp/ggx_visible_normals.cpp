// warp "ggx_visible_normals" — GGX microfacet normals visible from a direction.
//
// Samples m with density D_wi(m) = G1(wi) max(0, wi·m) D(m) / cosθi per unit solid
// angle (the distribution of visible normals), where D is the anisotropic GGX normal
// distribution and G1 Smith's masking term. Rough BSDFs reflect or refract about such an
// m; sampling visible normals never wastes samples on back-facing microfacets. The map
// is a bijection from the square onto the visible normals, so it is invertible.
//
// Parameters:
//   alpha     float (default 0.3, in [1e-4, 4])     roughness αx (and αy unless alpha_v)
//   alpha_v   float (optional, in [1e-4, 4])        roughness αy: anisotropic GGX
//   incident  vector (default (0.5, 0, 0.866))      wi, normalised; must have z > 0
//
// Reference: E. Heitz, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4),
// 2018; B. Walter et al., "Microfacet Models for Refraction through Rough Surfaces",
// EGSR 2007. Math in effigi/render/microfacet.hpp (shared with the rough BSDFs).
#include "visible_normals.hpp"

namespace effigi {
namespace {

class GGXVisibleNormals final : public VisibleNormalsWarp {
public:
    static Schema schema() {
        Schema s("warp", "ggx_visible_normals",
                 "GGX microfacet normals visible from a direction wi (Heitz 2018); density G1 (wi·m) D / cosθi.");
        s.cite("E. Heitz, Sampling the GGX Distribution of Visible Normals, JCGT 7(4), 2018");
        declareVisibleNormalsParameters(s, "GGX");
        return s;
    }

    explicit GGXVisibleNormals(const Properties& p) : VisibleNormalsWarp(MicrofacetType::GGX, p) {}
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::GGXVisibleNormals)
