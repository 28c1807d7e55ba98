#pragma once
// IEmitter — where light comes from. Surface emitters are attached to a shape (any
// shape); infinite ones surround the scene. Direct-lighting sampling works toward a
// reference point; emission sampling starts rays at the light (light tracing, photons).
#include "effigi/core/component.hpp"
#include "effigi/math/bbox.hpp"
#include "effigi/render/interaction.hpp"
#include "effigi/spectral/wavelengths.hpp"

#include <cstdint>

namespace effigi {

class IShape;

enum EmitterFlags : std::uint32_t {
    EmitterDeltaPosition = 1u << 0,   ///< point-like (point, spot)
    EmitterDeltaDirection = 1u << 1,  ///< one direction (directional)
    EmitterSurface = 1u << 2,         ///< attached to a shape
    EmitterInfinite = 1u << 3,        ///< at infinity (environment)
};

/// A light sample as seen from a reference point.
struct EmitterSample {
    Point3f p{0.f};
    Normal3f n{0.f};
    Vector3f wi{0.f};     ///< unit direction from the reference point toward the light
    float dist = Infinity;
    float pdf = 0.f;      ///< solid angle (delta emitters: 1, with `delta` set)
    bool delta = false;
    SampledSpectrum L;    ///< radiance (or intensity/d² for delta lights) arriving
};

/// A ray leaving the light, for light tracing and photon emission.
struct EmissionSample {
    Ray ray;
    Normal3f n{0.f};
    float pdfPosition = 0.f, pdfDirection = 0.f;
    SampledSpectrum L;  ///< emitted radiance along the ray (intensity for delta positions)
};

class IEmitter : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IEmitter");
    static constexpr const char* Tag = "emitter";

    virtual std::uint32_t flags() const = 0;
    bool isInfinite() const { return flags() & EmitterInfinite; }
    bool isDelta() const { return flags() & (EmitterDeltaPosition | EmitterDeltaDirection); }

    /// Called once for an emitter nested in a shape. Default: not attachable.
    virtual void attach(const IShape* shape);
    /// Called once the scene is assembled (infinite lights need its bounds).
    virtual void preprocess(const BBox3f& sceneBounds) { (void)sceneBounds; }

    virtual EmitterSample sampleDirect(const Point3f& ref, const Point2f& u,
                                       const SampledWavelengths& lambda) const = 0;
    /// Solid-angle density of sampleDirect(ref) producing the surface point si.
    virtual float pdfDirect(const Point3f& ref, const SurfaceInteraction& si) const;
    /// Radiance leaving surface point si toward si.wo (surface emitters).
    virtual SampledSpectrum eval(const SurfaceInteraction& si, const SampledWavelengths& lambda) const;

    /// Radiance arriving along an escaped ray of direction d (infinite emitters).
    virtual SampledSpectrum evalEnvironment(const Vector3f& d, const SampledWavelengths& lambda) const;
    /// Solid-angle density of sampleDirect choosing direction d (infinite emitters).
    virtual float pdfEnvironment(const Point3f& ref, const Vector3f& d) const;

    virtual EmissionSample sampleEmission(const Point2f& uPos, const Point2f& uDir,
                                          const SampledWavelengths& lambda) const = 0;
    /// The densities with which sampleEmission() produces a ray leaving the point p (normal
    /// n, on the light) along the unit direction d: pdfPosition per unit area (1 for a delta
    /// position) and pdfDirection per solid angle. Bidirectional renderers need them for
    /// multiple importance sampling. False (both 0) where the emitter does not provide
    /// them: the default, and infinite emitters, whose rays start at infinity.
    virtual bool pdfEmission(const Point3f& p, const Normal3f& n, const Vector3f& d, float& pdfPosition,
                             float& pdfDirection) const;

    /// Approximate emitted power (luminance-weighted), for choosing among lights.
    virtual float power() const = 0;
};

} // namespace effigi
