#pragma once
// The pass-through (BSDFNull) lobe shared by `null` and `mask`: light continues along
// −wo, as through an index-matched interface. It is reported as a delta transmission
// (BSDFNull | BSDFSpecular | BSDFTransmission, η = 1), so code that knows only deltas
// still handles it correctly; renderers that know BSDFNull do not count it as a bounce.
#include "effigi/interfaces/ibsdf.hpp"

namespace effigi {

/// The null lobe chosen with discrete probability `prob`, carrying the pass-through
/// weight `transmission` (so the sample's weight f·|cosθ|/pdf is transmission / prob).
/// None exactly at grazing, where a ray cannot cross the surface.
inline std::optional<BSDFSample> nullLobeSample(const Vector3f& wo, float prob, const SampledSpectrum& transmission) {
    if (wo.z == 0.f || !(prob > 0.f)) return std::nullopt;
    BSDFSample bs;
    bs.wi = -wo;
    bs.pdf = prob;
    bs.f = transmission / std::abs(wo.z);
    bs.flags = BSDFNull | BSDFSpecular | BSDFTransmission;
    bs.eta = 1.f;
    return bs;
}

} // namespace effigi
