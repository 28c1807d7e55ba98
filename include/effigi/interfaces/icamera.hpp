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
    float time = 0.f;    ///< in [0, 1): the fraction of the shutter interval
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

    /// The shutter interval (Mitsuba's shutter_open, shutter_close): a ray's time is
    /// open + s.time · (close − open). Renderers draw s.time only when close > open.
    virtual float shutterOpen() const { return 0.f; }
    virtual float shutterClose() const { return 0.f; }
    bool hasShutterInterval() const { return shutterClose() > shutterOpen(); }
    /// True when to_world is an <animation> that moves the camera (its rays then follow
    /// the pose at their time; toWorld() is the first pose).
    virtual bool moves() const { return false; }
};

} // namespace effigi
