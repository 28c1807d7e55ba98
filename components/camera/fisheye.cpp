// camera "fisheye" — an equidistant fisheye lens: the distance of an image point from the
// image centre is proportional to the angle θ of its direction from the viewing axis.
//
// The image circle is inscribed in the film's shorter side and spans the field of view
// `fov` (up to 360°) across its diameter. A film position (x, y) of a W × H film, with
// m = min(W, H), has the plane coordinates (image right is camera −x, image top +y)
//   a = (W/2 − x) / (m/2),  b = (H/2 − y) / (m/2),  ρ = √(a² + b²),
// and looks along θ = ρ · fov/2 from +z, in the azimuth of (a, b):
//   d = (sin θ · a/ρ, sin θ · b/ρ, cos θ)        (the centre, ρ = 0, looks along +z).
// Film positions outside the circle (ρ > 1) see nothing: their rays (θ clamped to 180°)
// carry weight 0, so the corners of the image stay black. Inside, weight 1.
// Equidistant (r = f θ) rather than gnomonic (r = f tan θ) so that fields of view of
// 180° and beyond, up to the full sphere, keep a finite image (Kannala & Brandt 2006).
// Rays start at distance near_clip from the eye along their direction and run
// far_clip − near_clip (panorama.hpp).
//
// Parameters:
//   fov                      float (deg, in (0, 360], default 180)  field of view across the circle
//   near_clip, far_clip      float (default 1e-2, 1e4)  clip distances along each ray
//   to_world                 transform  camera-to-world (lookat); rotation and translation only
//   film, sampler, medium    nested  default: hdrfilm and independent; medium optional
//
// No ICameraImportance: ptracer and bdpt refuse this camera with a one-line error.
// Reference: J. Kannala, S. S. Brandt, "A generic camera model and calibration method for
// conventional, wide-angle, and fish-eye lenses", IEEE TPAMI 28(8), 2006.
#include "panorama.hpp"

namespace effigi {
namespace {

class FisheyeCamera final : public camera::PanoramaCamera {
public:
    static Schema schema() {
        Schema s("camera", "fisheye",
                 "Equidistant fisheye (r ∝ θ): a circular image of up to 360° inscribed in the film's shorter side.");
        s.cite("J. Kannala, S. S. Brandt, A generic camera model ... for fish-eye lenses, IEEE TPAMI 28(8), 2006");
        s.real("fov", 180.0, "Field of view across the image circle, in (0, 360]").range(0.0, 360.0).withUnit("deg");
        camera::addPanoramaParams(s);
        // Conformance (conformance/camera_suite.cpp): the default 180°, an off-centre
        // lookat, a tiny and the full field of view, near_clip close to far_clip.
        const Transform view = camera::conformanceView();
        s.addConformance({"default", {}});
        s.addConformance({"lookat fov 100", {{"to_world", view}, {"fov", 100.0}, {"far_clip", 30.0}}});
        s.addConformance({"tiny fov", {{"to_world", view}, {"fov", 1e-2}}});
        s.addConformance({"full sphere", {{"fov", 360.0}, {"near_clip", 1e-3}}});
        s.addConformance({"near close to far", {{"to_world", view}, {"near_clip", 1.0}, {"far_clip", 1.001}}});
        return s;
    }

    explicit FisheyeCamera(const Properties& p) : PanoramaCameraBase(p) {
        float fov = p.getFloat("fov");
        if (!(fov > 0.f && fov <= 360.f))
            failAt(p.whereOf("fov"), "{}: parameter 'fov' = {} must lie in (0, 360] degrees", p.describe(), fov);
        m_halfFov = 0.5f * degToRad(fov);
        m_radius = 0.5f * std::min(m_size.x, m_size.y);
    }

    Ray generateRay(const CameraSample& s, const SampledWavelengths&, SampledSpectrum& weight) const override {
        float a = (0.5f * m_size.x - s.pFilm.x) / m_radius, b = (0.5f * m_size.y - s.pFilm.y) / m_radius;
        float rho = std::sqrt(a * a + b * b);
        weight = SampledSpectrum(rho <= 1.f ? 1.f : 0.f);
        if (!(rho > 0.f)) return rayAlong(Vector3f(0.f, 0.f, 1.f), s.time);
        float theta = std::min(rho * m_halfFov, Pi), st = std::sin(theta) / rho;
        return rayAlong(normalize(Vector3f(st * a, st * b, std::cos(theta))), s.time);
    }

private:
    float m_halfFov = 0.5f * Pi, m_radius = 1.f;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::FisheyeCamera)
