#pragma once
// The diffuse (cosine-weighted) lobe of the BSDFs that have one (diffuse, orennayar,
// phong, the plastics, the principled BSDFs), drawn through a warp (issue 14, "warps in
// use"): by default the compiled-in code of warp `cosine_hemisphere` (Malley's method,
// PBRT 4th ed., §A.5.3), or a warp nested as <warp type="..."/> in the BSDF. The BSDF's
// f is unchanged by the choice, and its pdf() says the warp's density, so any warp whose
// support covers the upper hemisphere keeps the estimator unbiased.
#include "effigi/render/warp_choice.hpp"

#include <string>

namespace effigi {

using DiffuseWarp = WarpChoice<compiled_warp::CosineHemisphere>;

/// The schema entry of a diffuse lobe's nested warp; `lobe` says which lobe it samples.
inline void declareDiffuseWarp(Schema& s, const std::string& lobe) {
    DiffuseWarp::declare(s, "Direction sampler of " + lobe +
                                " (a warp onto the sphere of directions); default: the code of warp "
                                "`cosine_hemisphere` (cosine-weighted), compiled in");
}

/// pdf(wo, wi) of a one-sided reflector's diffuse lobe: the warp's density at wi when wo
/// and wi are both above the surface, else 0.
inline float oneSidedPdf(const DiffuseWarp& warp, const Vector3f& wo, const Vector3f& wi) {
    if (!(wo.z > 0.f && wi.z > 0.f)) return 0.f;
    return warp.pdf(wi);
}

/// A direction of the diffuse lobe for the BSDFs that give a sample for every u: the edge
/// of the square maps to the cosine warp's rim z = 0, of zero density, so a direction with
/// 0 <= z < 1e-7 is lifted to cos θ = 1e-7 (a null set: the distribution is unchanged).
/// A nested warp's direction below the surface is left as it is, for the caller to reject
/// (lifting it would pile the lower half of, e.g., a uniform sphere onto the rim).
inline Vector3f sampleRimLifted(const DiffuseWarp& warp, const Point2f& u) {
    Vector3f w = warp.sample(u);
    if (w.z >= 0.f && w.z < 1e-7f) w = normalize(Vector3f(w.x, w.y, 1e-7f));
    return w;
}

} // namespace effigi
