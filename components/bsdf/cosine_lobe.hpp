#pragma once
// The density of the one-sided diffuse BSDFs (diffuse, orennayar): cosine-weighted
// sampling of the upper hemisphere (Malley's method, PBRT 4th ed., §A.5.3), and nothing
// unless both directions are above the surface.
#include "effigi/math/warp_functions.hpp"

namespace effigi {

/// pdf(wo, wi) of cosine-weighted hemisphere sampling for a one-sided reflector: cos θi / π
/// when wo and wi are both above the surface, else 0.
inline float oneSidedCosinePdf(const Vector3f& wo, const Vector3f& wi) {
    if (!(wo.z > 0.f && wi.z > 0.f)) return 0.f;
    return warp::squareToCosineHemispherePdf(wi);
}

} // namespace effigi
