// camera "orthographic" — a parallel projection (Mitsuba's `orthographic` sensor).
//
// Every ray travels along the camera's +z axis; the film covers the rectangle
// [-1, 1] x [-1/a, 1/a] (a = width / height) of the camera's near plane, so to_world's
// scale sets the size of the viewed region (scale x=10 y=10 views 20 units across).
// Camera space follows Mitsuba, as for perspective (projection.hpp): +y up, +x LEFT.
// Rays start on the near plane z = near_clip (in camera units, scaled by to_world like
// everything else) and run a length far_clip − near_clip.
//
// Parameters:
//   near_clip, far_clip      float (default 1e-2, 1e4)  clip distances
//   to_world                 transform  camera-to-world; lookat plus a scale for the extent
//   film, sampler            nested  default: hdrfilm and independent
//
// Light tracers (ptracer) connect to it through ICameraImportance: a scene point projects
// along the viewing axis onto the near plane. The importance is a delta in direction and
// uniform over the film rectangle, so the connection carries 1 / (film area seen across
// the viewing direction), with no 1/dist² falloff — the camera counterpart of a
// directional light (Mitsuba 3's orthographic sample_direction; Veach 1997, §8.1).
// Directions toward infinite lights cannot connect to it (probability zero).
//
// Reference: Mitsuba 3 documentation, "Orthographic camera (orthographic)";
// M. Pharr, W. Jakob, G. Humphreys, Physically Based Rendering, 4th ed., §5.1.
#include "projection.hpp"

namespace effigi {
namespace {

class OrthographicCamera final : public camera::ProjectiveCamera {
public:
    static Schema schema() {
        Schema s("camera", "orthographic", "Orthographic (parallel) projection camera (Mitsuba's `orthographic`).");
        s.cite("Mitsuba 3 documentation, Orthographic camera; PBRT 4th ed., §5.1");
        s.transform("to_world", "Camera-to-world transform; its x/y scale sets the half-width of the view");
        camera::addCommonParams(s, "Near clip distance (> 0, < far_clip); rays start on this plane");
        // Conformance (conformance/camera_suite.cpp): the unit view, a lookat scaled unevenly
        // (z too: the clip range is measured in world length), tiny and huge views, and
        // near_clip close to far_clip. The tiny view (2e-3 across) sits at the origin and
        // ends at 10: floats far from it could not tell its pixels apart.
        const Transform view = Transform::lookAt({1.f, 2.f, 5.f}, {0.f, 0.5f, 0.f}, {0.f, 1.f, 0.f});
        s.addConformance({"default", {}});
        s.addConformance({"lookat scaled 3×2×1.5", {{"to_world", view * Transform::scale({3.f, 2.f, 1.5f})},
                                                    {"near_clip", 0.5}, {"far_clip", 20.0}}});
        s.addConformance({"tiny view", {{"to_world", Transform::scale({1e-3f, 1e-3f, 1.f})}, {"far_clip", 10.0}}});
        s.addConformance({"huge view", {{"to_world", view * Transform::scale({1e3f, 1e3f, 1.f})}}});
        s.addConformance({"near close to far", {{"to_world", view}, {"near_clip", 2.0}, {"far_clip", 2.002}}});
        return s;
    }

    explicit OrthographicCamera(const Properties& p) : ProjectiveCamera(p) {
        if (!m_toWorld.isFinite())
            failAt(p.whereOf("to_world"), "{}: 'to_world' has non-finite entries", p.describe());
        // The viewing direction and the film rectangle must not collapse.
        glm::mat3 linear(m_toWorld.matrix());
        float det = glm::determinant(linear);
        Vector3f dir = m_toWorld.vector(Vector3f(0.f, 0.f, 1.f));
        if (!(std::abs(det) > 0.f) || !std::isfinite(det) || !(length(dir) > 0.f))
            failAt(p.whereOf("to_world"), "{}: 'to_world' must be invertible (it maps the film to a plane)", p.describe());
        m_dir = normalize(dir);
        m_zScale = length(dir);
        m_filmSize = camera::filmSize(p, *m_film);
        m_half = Vector2f(1.f, m_filmSize.y / m_filmSize.x);  // Mitsuba: x spans [-1, 1]
        // World area of the film rectangle projected across the viewing direction (to_world
        // may scale and shear it): the importance is spread uniformly over it.
        Vector3f n = cross(m_toWorld.vector(Vector3f(1.f, 0.f, 0.f)), m_toWorld.vector(Vector3f(0.f, 1.f, 0.f)));
        m_area = 4.f * m_half.x * m_half.y * std::abs(dot(n, m_dir));
        if (!(m_area > 0.f) || !std::isfinite(m_area))
            failAt(p.whereOf("to_world"), "{}: 'to_world' maps the film to a degenerate rectangle", p.describe());
    }

    Ray generateRay(const CameraSample& s, const SampledWavelengths&, SampledSpectrum& weight) const override {
        // The same film -> plane map as the perspective camera, on the near plane and
        // without the division by depth.
        Vector3f local = camera::imagePlanePoint(s.pFilm, m_filmSize, m_half);
        local.z = m_near;
        Ray ray;
        ray.o = m_toWorld.point(Point3f(local));
        ray.d = m_dir;
        ray.tMax = m_far - m_near;
        weight = SampledSpectrum(1.f);
        return timed(ray, s.time);
    }

    /// The inverse of generateRay: project ref along the viewing axis onto the near plane.
    /// The importance is δ(ω − d) / area per unit area perpendicular to d, so the
    /// connection's weight is 1 / area (deltaDirection; Veach 1997, §8.1).
    bool sampleDirection(const Point3f& ref, const Point2f&, CameraImportanceSample& out) const override {
        out = CameraImportanceSample{};
        Point3f local = m_toLocal.point(ref);
        // generateRay's rays run a world length far − near from the near plane.
        float dist = (local.z - m_near) * m_zScale;
        if (!(dist >= 0.f && dist <= m_far - m_near)) return false;
        if (!camera::filmPosition(Vector2f(local.x, local.y), m_filmSize, m_half, out.pFilm)) return false;
        out.pCamera = m_toWorld.point(Point3f(local.x, local.y, m_near));
        out.wi = -m_dir;
        out.dist = dist;
        out.weight = 1.f / m_area;
        out.pdf = 1.f;
        out.deltaDirection = true;
        return true;
    }

private:
    Vector2f m_filmSize{1.f}, m_half{1.f};
    Vector3f m_dir{0.f, 0.f, 1.f};
    float m_zScale = 1.f, m_area = 1.f;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::OrthographicCamera)
