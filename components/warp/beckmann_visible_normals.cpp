// warp "beckmann_visible_normals" — Beckmann microfacet normals visible from a direction.
//
// Samples m with density D_wi(m) = G1(wi) max(0, wi·m) D(m) / cosθi per unit solid angle
// (the distribution of visible normals), where D is the anisotropic Beckmann distribution
// and G1 Smith's masking term; roughconductor and roughdielectric sample their Beckmann
// lobes with it. The map inverts the CDFs of the visible slopes in the stretched (α = 1)
// configuration: the slope along the incident azimuth by Newton's method on its CDF
// (cosθ erfc(−x) + sinθ e^{−x²}/√π)/2, the transverse slope as a Gaussian. It is a
// bijection from the square onto the visible normals, so it is invertible.
//
// Parameters:
//   alpha     float (default 0.3, in [1e-4, 4])     roughness αx (and αy unless alpha_v)
//   alpha_v   float (optional, in [1e-4, 4])        roughness αy: anisotropic Beckmann
//   incident  vector (default (0.5, 0, 0.866))      wi, normalised; must have z > 0
//
// Reference: E. Heitz, E. d'Eon, "Importance Sampling Microfacet-Based BSDFs using the
// Distribution of Visible Normals", EGSR 2014; B. Walter et al., "Microfacet Models for
// Refraction through Rough Surfaces", EGSR 2007. Math in effigi/render/microfacet.hpp.
#include "visible_normals.hpp"

namespace effigi {
namespace {

class BeckmannVisibleNormals final : public VisibleNormalsWarp {
public:
    static Schema schema() {
        Schema s("warp", "beckmann_visible_normals",
                 "Beckmann microfacet normals visible from a direction wi; density G1 (wi·m) D / cosθi.");
        s.cite("E. Heitz, E. d'Eon, Importance Sampling Microfacet-Based BSDFs using the Distribution of Visible "
               "Normals, EGSR 2014");
        declareVisibleNormalsParameters(s, "Beckmann");
        return s;
    }

    explicit BeckmannVisibleNormals(const Properties& p) : VisibleNormalsWarp(MicrofacetType::Beckmann, p) {}
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::BeckmannVisibleNormals)
