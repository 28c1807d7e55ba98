// pathgenerator "defensive" — BSDF sampling mixed with uniform directions.
//
// With probability `uniform` the walk continues in a uniformly distributed direction —
// over the sphere where the BSDF transmits, else over the hemisphere of wo — and otherwise
// by sampling the BSDF; the density of either draw is the mixture's,
//     p(wi) = (1 − ε)·p_bsdf(wi) + ε·p_uniform(wi),
// so f·|cos|/p stays below |cos|·f/(ε·p_uniform) wherever the BSDF's own sampling is poor
// (Hesterberg's defensive importance sampling). The price is ε of the walks spent on
// directions the BSDF would rarely choose. Delta lobes (mirrors, smooth glass, null
// surfaces) have no density to mix: they are reached only through the BSDF draw, with
// their discrete probability scaled by 1 − ε; a purely specular surface is always sampled
// by its BSDF, and on one with delta and non-delta lobes (smooth plastic) ε is at most ½,
// so the delta lobes stay reachable. The mixture density is also what the MIS weights of bdpt read at a vertex
// seen from the other subpath (PathContext::pdf), so every strategy stays consistent.
//
// Parameters: uniform (ε, the fraction of uniform draws, in [0, 1], default 0.1).
//
// Reference: T. Hesterberg, "Weighted average importance sampling and defensive mixture
// distributions", Technometrics 37(2), 1995; E. Veach, PhD thesis, 1997, §9.2.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ipathgenerator.hpp"
#include "effigi/math/warp_functions.hpp"

namespace effigi {
namespace {

class DefensivePathGenerator final : public Implements<IPathGenerator> {
public:
    static Schema schema() {
        Schema s("pathgenerator", "defensive",
                 "Subpaths that continue by BSDF sampling mixed with a fraction of uniform directions.");
        s.cite("T. Hesterberg, Weighted average importance sampling and defensive mixture distributions, "
               "Technometrics 37(2), 1995");
        s.real("uniform", 0.1, "Fraction of directions drawn uniformly (sphere or hemisphere)").range(0.0, 1.0);
        s.addConformance({"default", {}});
        s.addConformance({"uniform 0 (BSDF sampling)", {{"uniform", 0.0}}});
        s.addConformance({"uniform 1 (no BSDF sampling)", {{"uniform", 1.0}}});
        s.addConformance({"uniform 0.5", {{"uniform", 0.5}}});
        return s;
    }
    explicit DefensivePathGenerator(const Properties& p) : m_uniform(p.getFloat("uniform")) {}

    std::optional<BSDFSample> sampleDirection(const SurfaceInteraction& si, const Vector3f& wo, float uc,
                                              const Point2f& u, SampledWavelengths& lambda,
                                              TransportMode mode) const override {
        const IBSDF& bsdf = *si.bsdf;
        const float eps = fraction(bsdf);
        if (eps <= 0.f) return bsdf.sample(si, wo, uc, u, lambda, mode);
        if (uc < eps) {
            BSDFSample bs;
            bs.wi = sphere(bsdf) ? warp::squareToUniformSphere(u) : warp::squareToUniformHemisphere(u);
            if (!sphere(bsdf) && wo.z < 0.f) bs.wi.z = -bs.wi.z;
            bs.f = bsdf.f(si, wo, bs.wi, lambda, mode);
            bs.pdf = pdfDirection(si, wo, bs.wi, lambda, mode);
            bs.flags = (bsdf.flags() & (BSDFDiffuse | BSDFGlossy)) |
                       (bs.wi.z * wo.z > 0.f ? BSDFReflection : BSDFTransmission);
            return bs;
        }
        // The BSDF's draw on the rest of uc, rescaled to [0, 1).
        float ub = std::min((uc - eps) / (1.f - eps), OneMinusEpsilon);
        std::optional<BSDFSample> bs = bsdf.sample(si, wo, ub, u, lambda, mode);
        if (!bs) return bs;
        if (bs->isSpecular() || (bs->flags & BSDFNull)) bs->pdf *= 1.f - eps;
        else bs->pdf = pdfDirection(si, wo, bs->wi, lambda, mode);
        return bs;
    }

    float pdfDirection(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                       const SampledWavelengths& lambda, TransportMode mode) const override {
        const IBSDF& bsdf = *si.bsdf;
        const float pdf = bsdf.pdf(si, wo, wi, lambda, mode), eps = fraction(bsdf);
        if (eps <= 0.f) return pdf;
        const float uniform = sphere(bsdf) ? Inv4Pi : (wi.z * wo.z > 0.f ? Inv2Pi : 0.f);
        return (1.f - eps) * pdf + eps * uniform;
    }

private:
    /// ε at this surface: none where every lobe is a delta, at most ½ beside delta lobes.
    float fraction(const IBSDF& bsdf) const {
        if (bsdf.isPureSpecular()) return 0.f;
        return bsdf.flags() & (BSDFSpecular | BSDFNull) ? std::min(m_uniform, 0.5f) : m_uniform;
    }
    /// Uniform draws cover the sphere where the BSDF may transmit, else wo's hemisphere.
    static bool sphere(const IBSDF& bsdf) { return bsdf.flags() & BSDFTransmission; }

    float m_uniform;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::DefensivePathGenerator)
