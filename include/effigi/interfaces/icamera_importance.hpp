#pragma once
// ICameraImportance — an optional second interface of cameras that light-tracing
// renderers (ptracer) connect to: given a point in the scene, where on the film does it
// project, and how much importance does the camera emit toward it. Mitsuba's
// Sensor::sample_direction; pbrt-v4's Camera::SampleWi. A renderer asks for it with
// query<ICameraImportance>(camera) and reports an error when the camera lacks it.
//
// Normalisation: the importance W_e of a pinhole camera is a density over its image
// plane, integrating to 1 over the FULL film (IFilm::fullSize()): W_e = 1 / (A cos³θ) per
// unit solid angle, A the image-plane area at unit distance. A film of P pixels then
// measures pixel j as P · ∫ W_e L restricted to j, so a light path's splat is its
// throughput · weight · P / (number of light paths).
// Reference: Veach 1997, PhD thesis, §8.1 (importance); PBRT 4th ed., §5.4.
#include "effigi/core/component.hpp"
#include "effigi/math/vector.hpp"

namespace effigi {

/// A connection from a scene point to the camera.
struct CameraImportanceSample {
    Point2f pFilm{0.f};  ///< film position (pixels, full-film frame, as CameraSample::pFilm)
    Point3f pCamera{0.f}; ///< the point on the camera (lens) the connection ends at
    Vector3f wi{0.f};    ///< unit direction from the scene point toward pCamera
    float dist = 0.f;    ///< distance from the scene point to pCamera
    /// Importance arriving at the scene point divided by the sampling density: for a
    /// pinhole W_e(−wi) / dist² (pdf = 1, the camera position being a delta).
    float weight = 0.f;
    /// Density of choosing pCamera (1 for a pinhole; 0: no connection). Renderers use
    /// weight / pdf; a thin lens folds its uniform lens density into weight and gives 1.
    float pdf = 0.f;
    /// True for a camera whose importance is a delta in DIRECTION (orthographic): weight
    /// is then importance per unit area perpendicular to wi (no 1/dist² falloff), like a
    /// directional light's irradiance, and only points can connect to it, not directions
    /// (a direction sampled toward an infinite light never matches the camera's).
    bool deltaDirection = false;
};

class ICameraImportance : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("ICameraImportance");
    static constexpr const char* Tag = "camera";

    /// Connect `ref` to the camera with lens sample u. False (and pdf 0) if the point is
    /// outside the field of view or the clip range.
    virtual bool sampleDirection(const Point3f& ref, const Point2f& u, CameraImportanceSample& out) const = 0;

    /// Density per unit solid angle with which ICamera::generateRay, given that its ray
    /// passes through the point `lens` of the lens (world space), produces the world
    /// direction d (unit): 1 / (A cos³θ) for perspective and thin-lens cameras, 0 outside
    /// the field of view. Bidirectional renderers need it for multiple importance
    /// sampling. The default (0) says the camera has no such density (orthographic: its
    /// direction is a delta).
    virtual float pdfDirection(const Point3f& lens, const Vector3f& d) const {
        (void)lens;
        (void)d;
        return 0.f;
    }
};

} // namespace effigi
