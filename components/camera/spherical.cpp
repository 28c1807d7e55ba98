// camera "spherical" — a latitude-longitude panorama of the full sphere of directions
// (Mitsuba 0.6's `spherical` sensor, whose orientation it keeps).
//
// A film position (x, y) of a W × H film looks along the camera-space direction of
// azimuth φ = π − 2π x/W about +y and polar angle θ = π y/H from +y:
//   d = (sin φ sin θ, cos θ, cos φ sin θ).
// So the image centre looks along +z (forward), y = 0 is straight up (+y), y = H straight
// down, x = W/4 looks along +x (left, as in every Mitsuba camera), x = 3W/4 along −x
// (right) and both vertical edges x = 0, W look backwards (−z); the seam is behind.
// Every pixel spans the same Δφ Δθ, so pixels near the poles cover less solid angle
// (sin θ): the image is of radiance, each ray's weight is 1.
// Rays start at distance near_clip from the eye along their direction and run
// far_clip − near_clip (panorama.hpp: a depth plane cannot clip rays looking backwards).
//
// Parameters:
//   near_clip, far_clip      float (default 1e-2, 1e4)  clip distances along each ray
//   to_world                 transform  camera-to-world (lookat); rotation and translation only
//   film, sampler, medium    nested  default: hdrfilm and independent; medium optional
//
// ICameraImportance (ptracer, bdpt connect to it): film positions are uniform, so the
// density of a ray direction per unit solid angle is 1 / (2π² sin θ), which is also the
// camera's importance (it integrates to 1 over the sphere, and rays have weight 1).
// Reference: Mitsuba 0.6 documentation, §8.10 "Spherical camera (spherical)";
// the equirectangular projection, J. P. Snyder, Map Projections — A Working Manual (1987), §12.
#include "panorama.hpp"

namespace effigi {
namespace {

class SphericalCamera final : public camera::PanoramaCameraBase<ICameraImportance> {
public:
    static Schema schema() {
        Schema s("camera", "spherical",
                 "Latitude-longitude panorama over the full sphere (Mitsuba 0.6's `spherical`): x → azimuth, "
                 "y → polar angle; the image centre looks along +z.");
        s.cite("Mitsuba 0.6 documentation, Spherical camera; J. P. Snyder, Map Projections (1987), §12");
        camera::addPanoramaParams(s);
        // Conformance (conformance/camera_suite.cpp): the default, an off-centre lookat,
        // near_clip close to far_clip, and a huge clip range.
        const Transform view = camera::conformanceView();
        s.addConformance({"default", {}});
        s.addConformance({"lookat", {{"to_world", view}, {"near_clip", 0.05}, {"far_clip", 30.0}}});
        s.addConformance({"near close to far", {{"to_world", view}, {"near_clip", 1.0}, {"far_clip", 1.001}}});
        s.addConformance({"huge clip range", {{"near_clip", 1e-4}, {"far_clip", 1e7}}});
        return s;
    }

    explicit SphericalCamera(const Properties& p) : PanoramaCameraBase(p) {}

    Ray generateRay(const CameraSample& s, const SampledWavelengths&, SampledSpectrum& weight) const override {
        Point2f q = s.pFilm / m_size;
        weight = SampledSpectrum(1.f);
        return rayAlong(camera::azimuthPolar(Pi * (1.f - 2.f * q.x), Pi * q.y), s.time);
    }

    bool sampleDirection(const Point3f& ref, const Point2f&, CameraImportanceSample& out) const override {
        return connect(ref, out, project);
    }
    float pdfDirection(const Point3f&, const Vector3f& d) const override { return densityOf(d, project); }

private:
    /// The inverse of generateRay's map: θ = atan2(|(d.x, d.z)|, d.y), φ = atan2(d.x, d.z).
    /// (Not acos d.y: in float it loses θ within 3e-4 rad of the poles, where the density
    /// 1/sin θ then went to 0.)
    static camera::PanoramaProjection project(const Vector3f& d) {
        const float sinTheta = std::sqrt(d.x * d.x + d.z * d.z);
        const float theta = std::atan2(sinTheta, d.y), phi = std::atan2(d.x, d.z);
        if (!(sinTheta > 0.f)) return {};
        return {Point2f(0.5f * (1.f - phi / Pi), theta / Pi), 1.f / (2.f * Pi * Pi * sinTheta)};
    }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::SphericalCamera)
