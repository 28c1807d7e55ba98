#pragma once
// ICamera — maps a film position (and lens, time) to a ray. Mitsuba's "sensor"; it owns
// the film and sampler declared inside it.
#include "effigi/core/component.hpp"
#include "effigi/math/transform.hpp"
#include "effigi/render/ray.hpp"
#include "effigi/spectral/wavelengths.hpp"

namespace effigi {

class IFilm;
class IMedium;
class ISampler;

struct CameraSample {
    Point2f pFilm{0.f};  ///< continuous film position in pixels
    Point2f pLens{0.5f};
    float time = 0.f;
};

class ICamera : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("ICamera");
    static constexpr const char* Tag = "camera";

    /// A world-space ray with a unit direction; weight multiplies its radiance
    /// (1 for ideal pinhole cameras).
    virtual Ray generateRay(const CameraSample& s, const SampledWavelengths& lambda,
                            SampledSpectrum& weight) const = 0;

    virtual const Transform& toWorld() const = 0;
    virtual IFilm& film() const = 0;
    virtual ISampler& sampler() const = 0;
    /// The participating medium the camera sits in (Mitsuba's nested `<medium>` of a
    /// sensor); null is vacuum.
    virtual const IMedium* medium() const { return nullptr; }
};

} // namespace effigi
