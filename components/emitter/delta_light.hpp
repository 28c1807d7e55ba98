#pragma once
// What the lights at a single point (point, spot, projector) share: a direct-lighting
// sample toward that point (or only its geometry, for a light with more to check), and
// the ray of an emission sample leaving it.
// Both are deterministic given the point, so a delta light's pdf is 1 (Veach 1997,
// sec. 8.1: the Dirac density cancels against the contribution).
#include "effigi/interfaces/iemitter.hpp"

#include <cmath>

namespace effigi::delta_light {

/// Fills es.p, es.dist, es.wi (unit, ref -> light) and es.n = -es.wi for a light at
/// `position` and returns the squared distance. Returns 0 with only es.p set (pdf stays
/// 0: no sample) when ref is at the light, where the direction is undefined, or when the
/// distance is not finite.
inline float sampleGeometry(const Point3f& ref, const Point3f& position, EmitterSample& es) {
    es.p = position;
    Vector3f d = position - ref;
    float dist2 = lengthSquared(d);
    if (!(dist2 > 0.f) || !std::isfinite(dist2)) return 0.f;
    es.dist = std::sqrt(dist2);
    es.wi = d / es.dist;
    es.n = -es.wi;
    return dist2;
}

/// The direct-lighting sample of a light at `position` seen from ref, for a light whose
/// intensity toward a unit world direction d (pointing away from the light) is
/// intensity(d): radiance intensity / distance², pdf 1, delta.
template <typename Intensity>
EmitterSample sampleDirect(const Point3f& ref, const Point3f& position, const Intensity& intensity) {
    EmitterSample es;
    const float dist2 = sampleGeometry(ref, position, es);
    if (dist2 == 0.f) return es;  // at the light: undefined, pdf 0
    es.pdf = 1.f;
    es.delta = true;
    es.L = intensity(-es.wi) / dist2;
    return es;
}

/// The emission sample leaving `position` along the unit world direction d; the position
/// is certain (pdfPosition 1), the direction has solid-angle density pdfDirection.
inline EmissionSample emissionSample(const Point3f& position, const Vector3f& d, const Normal3f& n,
                                     float pdfDirection, const SampledSpectrum& L) {
    EmissionSample es;
    es.ray = Ray{position, d, Infinity};
    es.n = n;
    es.pdfPosition = 1.f;
    es.pdfDirection = pdfDirection;
    es.L = L;
    return es;
}

} // namespace effigi::delta_light
