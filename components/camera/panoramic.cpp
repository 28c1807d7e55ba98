// camera "panoramic" — a cylindrical panorama: a horizontal sweep of up to 360° around
// the camera's +y axis, and a perspective (central) projection onto the cylinder
// vertically.
//
// A film position (x, y) of a W × H film, q = (x/W, y/H), looks along the camera-space
// direction through the point (sin α, h, cos α) of the unit cylinder about +y, with
//   α = hfov · (½ − q.x)            (azimuth from +z; positive toward +x, image LEFT)
//   h = tan(vfov / 2) · (1 − 2 q.y)  (height on the cylinder; y = 0 is the top)
// normalised. The image centre looks along +z; with hfov = 360° x = W/4 looks along +x
// (left) and x = 3W/4 along −x (right), as spherical's azimuth. The vertical map is the
// cylinder's own central projection (h = tan of the elevation), not linear in angle:
// vertical world lines stay straight and every column is a pinhole camera's, which is what
// a cylindrical panorama stitched from photographs holds (Szeliski & Shum 1997); it needs
// vfov < 180° (the tangent diverges). Rays have weight 1 (an image of radiance).
// Rays start at distance near_clip from the eye along their direction and run
// far_clip − near_clip (panorama.hpp).
//
// Parameters:
//   hfov                     float (deg, in (0, 360], default 360)  horizontal field of view
//   vfov                     float (deg, in (0, 180), default 90)   vertical field of view
//   near_clip, far_clip      float (default 1e-2, 1e4)  clip distances along each ray
//   to_world                 transform  camera-to-world (lookat); rotation and translation only
//   film, sampler, medium    nested  default: hdrfilm and independent; medium optional
//
// ICameraImportance (ptracer, bdpt connect to it): the ray density of a direction per unit
// solid angle (see project()), which is also the importance.
// Reference: R. Szeliski, H.-Y. Shum, "Creating full view panoramic image mosaics and
// environment maps", SIGGRAPH 1997; R. Szeliski, Computer Vision (2nd ed.), §8.2.6.
#include "panorama.hpp"

namespace effigi {
namespace {

class PanoramicCamera final : public camera::PanoramaCameraBase<ICameraImportance> {
public:
    static Schema schema() {
        Schema s("camera", "panoramic",
                 "Cylindrical panorama: hfov (up to 360°) around +y, a central (tan) projection vertically.");
        s.cite("R. Szeliski, H.-Y. Shum, Creating full view panoramic image mosaics, SIGGRAPH 1997");
        s.real("hfov", 360.0, "Horizontal field of view, in (0, 360]").range(0.0, 360.0).withUnit("deg");
        s.real("vfov", 90.0, "Vertical field of view, strictly between 0 and 180 (tan mapping)")
            .range(0.0, 180.0)
            .withUnit("deg");
        camera::addPanoramaParams(s);
        // Conformance (conformance/camera_suite.cpp): the default full circle, an off-centre
        // lookat, tiny and extreme fields of view, near_clip close to far_clip.
        const Transform view = camera::conformanceView();
        s.addConformance({"default", {}});
        s.addConformance({"lookat 120 x 60", {{"to_world", view}, {"hfov", 120.0}, {"vfov", 60.0}, {"far_clip", 30.0}}});
        s.addConformance({"tiny fov", {{"to_world", view}, {"hfov", 1e-2}, {"vfov", 1e-2}}});
        s.addConformance({"full circle vfov 179", {{"hfov", 360.0}, {"vfov", 179.0}, {"near_clip", 1e-3}}});
        s.addConformance({"near close to far", {{"to_world", view}, {"near_clip", 1.0}, {"far_clip", 1.001}}});
        return s;
    }

    explicit PanoramicCamera(const Properties& p) : PanoramaCameraBase(p) {
        float hfov = p.getFloat("hfov"), vfov = p.getFloat("vfov");
        if (!(hfov > 0.f && hfov <= 360.f))
            failAt(p.whereOf("hfov"), "{}: parameter 'hfov' = {} must lie in (0, 360] degrees", p.describe(), hfov);
        if (!(vfov > 0.f && vfov < 180.f))
            failAt(p.whereOf("vfov"), "{}: parameter 'vfov' = {} must lie strictly between 0 and 180 degrees",
                   p.describe(), vfov);
        m_hfov = degToRad(hfov);
        m_tanHalf = std::tan(0.5f * degToRad(vfov));
    }

    Ray generateRay(const CameraSample& s, const SampledWavelengths&, SampledSpectrum& weight) const override {
        Point2f q = s.pFilm / m_size;
        float alpha = m_hfov * (0.5f - q.x), h = m_tanHalf * (1.f - 2.f * q.y);
        weight = SampledSpectrum(1.f);
        return rayAlong(normalize(Vector3f(std::sin(alpha), h, std::cos(alpha))), s.time);
    }

    bool sampleDirection(const Point3f& ref, const Point2f&, CameraImportanceSample& out) const override {
        return connect(ref, out, [this](const Vector3f& d) { return project(d); });
    }
    float pdfDirection(const Point3f&, const Vector3f& d) const override {
        return densityOf(d, [this](const Vector3f& w) { return project(w); });
    }

private:
    /// The inverse of generateRay's map: α = atan2(d.x, d.z), h = d.y / |(d.x, d.z)|.
    /// Film positions are uniform in (α, h), and a patch dα dh subtends (1 + h²)^(−3/2) sr,
    /// so the density per solid angle is (1 + h²)^(3/2) / (hfov · 2 tan(vfov/2)).
    camera::PanoramaProjection project(const Vector3f& d) const {
        const float horizontal = std::sqrt(d.x * d.x + d.z * d.z);
        if (!(horizontal > 0.f)) return {};
        const float alpha = std::atan2(d.x, d.z), h = d.y / horizontal;
        const Point2f q(0.5f - alpha / m_hfov, 0.5f * (1.f - h / m_tanHalf));
        if (!(q.x >= 0.f && q.x <= 1.f && q.y >= 0.f && q.y <= 1.f)) return {};
        return {q, std::pow(1.f + h * h, 1.5f) / (m_hfov * 2.f * m_tanHalf)};
    }

    float m_hfov = 2.f * Pi, m_tanHalf = 1.f;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::PanoramicCamera)
