// camera "perspective" — an ideal pinhole camera (Mitsuba's `perspective` sensor).
//
// Every ray starts at the camera's origin and passes through a point of an image plane
// at unit distance. Camera space follows Mitsuba: the camera looks along +z, +y is up
// and +x is LEFT (that is what `lookat` builds), so the right edge of the image looks
// along −x. The field of view applies to one film axis (fov_axis); the other follows
// from the aspect ratio W/H of the film. An optional principal-point offset shifts the
// image plane sideways (off-axis projection) in units of the film size.
//
// Parameters:
//   fov                      float (deg, in (0, 180))  field of view along fov_axis; neither fov nor
//                            focal_length: a 50mm lens (diagonal fov 46.8°), as in Mitsuba 3
//   fov_axis                 string (x, y, diagonal, smaller, larger; default x)
//   focal_length             string ("50mm": 35 mm equivalent, sets the diagonal fov; not with fov)
//   near_clip, far_clip      float (default 1e-2, 1e4)  clip distances: rays start on the near
//                            plane and end on the far plane.
//   to_world                 transform  camera-to-world (use lookat); no scaling
//   principal_point_offset_x/_y  float (default 0)  image-plane shift, fraction of the film size
//   film, sampler            nested  default: hdrfilm and independent
//
// The projection is shared with thinlens and orthographic (projection.hpp). The camera
// also implements ICameraImportance, so light tracers (ptracer) can connect to it.
// Reference: M. Pharr, W. Jakob, G. Humphreys, Physically Based Rendering, 4th ed., §5.2.
#include "projection.hpp"

#include "effigi/interfaces/icamera_importance.hpp"

namespace effigi {
namespace {

class PerspectiveCamera final : public camera::ProjectiveCamera {
public:
    static Schema schema() {
        Schema s("camera", "perspective", "Pinhole camera with a perspective projection (Mitsuba's `perspective`).");
        s.cite("M. Pharr, W. Jakob, G. Humphreys, Physically Based Rendering, 4th ed., §5.2");
        camera::addFovParams(s, 0.0);  // none: 50mm (diagonal), as Mitsuba 3
        s.transform("to_world", "Camera-to-world transform (lookat); rotation and translation only");
        s.real("principal_point_offset_x", 0.0, "Horizontal shift of the image centre, as a fraction of the film width")
            .withUnit("film widths");
        s.real("principal_point_offset_y", 0.0, "Vertical shift of the image centre, as a fraction of the film height")
            .withUnit("film heights");
        camera::addCommonParams(s, "Near clip distance (> 0, < far_clip); rays start on the near plane");
        // Mitsuba's sensors take these too; a pinhole camera of a static scene has no use for them.
        s.ignored("focus_distance", "a pinhole camera keeps everything in focus (thinlens uses it)");
        // Conformance (conformance/camera_suite.cpp): the default 50mm lens, an off-centre
        // lookat, the fov near both ends of (0, 180), near_clip close to far_clip, an
        // off-axis (principal point) projection with fov along y, and a focal length.
        const Transform view = Transform::lookAt({1.f, 2.f, 5.f}, {0.f, 0.5f, 0.f}, {0.f, 1.f, 0.f});
        s.addConformance({"default", {}});
        s.addConformance({"lookat fov 60", {{"to_world", view}, {"fov", 60.0}, {"near_clip", 0.05}, {"far_clip", 30.0}}});
        s.addConformance({"tiny fov", {{"to_world", view}, {"fov", 1e-2}}});
        s.addConformance({"huge fov", {{"to_world", view}, {"fov", 179.0}, {"near_clip", 1e-3}}});
        s.addConformance({"near close to far", {{"to_world", view}, {"fov", 45.0}, {"near_clip", 1.0}, {"far_clip", 1.001}}});
        s.addConformance({"off-axis fov_axis y", {{"fov", 70.0}, {"fov_axis", std::string("y")},
                                                  {"principal_point_offset_x", 0.2}, {"principal_point_offset_y", -0.1}}});
        s.addConformance({"focal length 20mm", {{"focal_length", std::string("20mm")}, {"far_clip", 1e6}}});
        return s;
    }

    explicit PerspectiveCamera(const Properties& p) : ProjectiveCamera(p) {
        camera::requireRigid(p, m_toWorld);
        m_offset = Vector2f(p.getFloat("principal_point_offset_x"), p.getFloat("principal_point_offset_y"));
        m_filmSize = camera::filmSize(p, *m_film);
        m_tanHalf = camera::imagePlaneHalfExtent(p, m_filmSize);
        m_origin = m_toWorld.point(Point3f(0.f));
        m_area = 4.f * m_tanHalf.x * m_tanHalf.y;
    }

    Ray generateRay(const CameraSample& s, const SampledWavelengths&, SampledSpectrum& weight) const override {
        // Film position -> [0,1]² (x right, y down) -> image plane. Image right is camera
        // −x and image top is camera +y, hence the flips.
        Vector3f local = normalize(camera::imagePlanePoint(s.pFilm, m_filmSize, m_tanHalf, m_offset));
        // Rays start on the near plane and end on the far plane (Mitsuba's clipping).
        Ray ray;
        ray.d = normalize(m_toWorld.vector(local));
        ray.o = m_origin + ray.d * (m_near / local.z);
        ray.tMax = (m_far - m_near) / local.z;
        weight = SampledSpectrum(1.f);
        return timed(ray, s.time);
    }

    /// The inverse of generateRay's map (ICameraImportance): project ref onto the image
    /// plane. Importance is uniform over the image plane z = 1 of area A, which as a
    /// density per solid angle is 1 / (A cos³θ) (Veach 1997, §8.1; Mitsuba's importance()).
    bool sampleDirection(const Point3f& ref, const Point2f&, CameraImportanceSample& out) const override {
        out = CameraImportanceSample{};
        Point3f local = m_toLocal.point(ref);
        if (!(local.z >= m_near && local.z <= m_far)) return false;  // Mitsuba's clip test
        Vector2f plane(local.x / local.z, local.y / local.z);
        if (!camera::filmPosition(plane, m_filmSize, m_tanHalf, out.pFilm, m_offset)) return false;
        float dist = length(Vector3f(local));
        float cosTheta = local.z / dist;
        out.pCamera = m_origin;
        out.wi = (m_origin - ref) / dist;
        out.dist = dist;
        out.weight = 1.f / (m_area * cosTheta * cosTheta * cosTheta * dist * dist);
        out.pdf = 1.f;
        return std::isfinite(out.weight);
    }

    /// generateRay's density of directions: uniform over the image plane, 1 / (A cos³θ).
    float pdfDirection(const Point3f&, const Vector3f& d) const override {
        Vector3f local = m_toLocal.vector(d);
        float len = length(local);
        if (!(local.z > 0.f) || !(len > 0.f)) return 0.f;
        Point2f pFilm;
        if (!camera::filmPosition(Vector2f(local.x / local.z, local.y / local.z), m_filmSize, m_tanHalf, pFilm,
                                  m_offset))
            return 0.f;
        float cosTheta = local.z / len;
        return 1.f / (m_area * cosTheta * cosTheta * cosTheta);
    }

private:
    float m_area = 4.f;  // of the image plane z = 1
    Vector2f m_offset{0.f}, m_filmSize{1.f}, m_tanHalf{1.f};
    Point3f m_origin{0.f};
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::PerspectiveCamera)
