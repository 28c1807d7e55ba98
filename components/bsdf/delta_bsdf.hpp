#pragma once
// Base of the BSDFs made of delta lobes only (null, dielectric, thindielectric, and test
// doubles in tests/test_mask_null.cpp and tests/test_dispersion.cpp): a delta
// lobe has no finite density in any direction, so f() and pdf() are zero everywhere and
// all scattering happens through sample() (PBRT 4th ed., §9.2: specular reflection and
// transmission).
#include "effigi/interfaces/ibsdf.hpp"

namespace effigi {

class DeltaBSDF : public Implements<IBSDF> {
public:
    SampledSpectrum f(const SurfaceInteraction&, const Vector3f&, const Vector3f&, const SampledWavelengths&,
                      TransportMode) const override {
        return SampledSpectrum(0.f);
    }

    float pdf(const SurfaceInteraction&, const Vector3f&, const Vector3f&, const SampledWavelengths&,
              TransportMode) const override {
        return 0.f;
    }
};

} // namespace effigi
