#pragma once
// Events (EFFIGI's IEvent): value types that renderers keep in an array and find again
// through an IEventStore (effigi/interfaces/ieventstore.hpp), which indexes their
// positions. A photon map is a std::vector<Photon> plus a store over photon positions.
#include "effigi/math/vector.hpp"
#include "effigi/spectral/wavelengths.hpp"

#include <array>
#include <cstdint>

namespace effigi {

/// A photon left on a surface by a light path (Jensen 2001, ch. 5). Spectral: it carries
/// the four wavelengths its path was traced at and its power at each, divided by that
/// wavelength's sampling pdf (so each slot alone estimates the spectral power density at
/// its wavelength, as a camera path's slots do); a slot whose pdf is 0 (secondary
/// wavelengths terminated at a dispersive interface) holds 0 and the hero slot carries
/// the factor 4 (SampledWavelengths::terminateSecondary).
struct Photon {
    Point3f p{0.f};                           ///< where it landed
    Vector3f wi{0.f};                         ///< unit direction back toward where it came from
    Normal3f n{0.f};                          ///< geometric normal of the surface it landed on
    std::array<float, NSpectrumSamples> lambda{};  ///< nm
    SampledSpectrum power;                    ///< W nm⁻¹ per slot (power / wavelength pdf)
    std::uint16_t depth = 0;                  ///< segments from the light (1: direct)
    std::uint16_t flags = 0;                  ///< PhotonCaustic: only specular bounces since the light
};

enum PhotonFlags : std::uint16_t { PhotonCaustic = 1 };

} // namespace effigi
