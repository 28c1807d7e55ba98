#pragma once
// What the panoramic cameras (spherical, panoramic, fisheye) share: a central camera
// whose directions are not those of a plane through the image, so none of them is a
// ProjectiveCamera. They keep the projective cameras' parameters and checks
// (projection.hpp: film, sampler, medium, near_clip/far_clip, a rigid to_world) but clip
// by DISTANCE from the eye rather than by depth: a ray starts near_clip along its own
// direction and runs far_clip − near_clip, since a plane z = near cannot bound rays that
// look sideways or backwards (Mitsuba 0.6's spherical camera clips the same way).
// They do not implement ICameraImportance, so the light tracers (ptracer, bdpt) refuse
// them with a one-line error instead of connecting to them.
// Camera space is Mitsuba's: the camera looks along +z, +y is up, +x is LEFT.
#include "projection.hpp"

namespace effigi::camera {

/// The camera-space unit direction of azimuth phi about +y (phi = 0: +z, phi = π/2: +x,
/// which is image LEFT) and polar angle theta from +y (0: up, π: down).
inline Vector3f azimuthPolar(float phi, float theta) {
    float st = std::sin(theta);
    return {std::sin(phi) * st, std::cos(theta), std::cos(phi) * st};
}

/// The parameters every panoramic camera takes besides its field of view.
inline void addPanoramaParams(Schema& s) {
    s.transform("to_world", "Camera-to-world transform (lookat); rotation and translation only");
    addCommonParams(s, "Near clip distance (> 0, < far_clip); rays start this far from the eye");
}

/// A conformance view shared by the panoramic cameras' schemas: off-centre, looking down.
inline Transform conformanceView() {
    return Transform::lookAt({1.f, 2.f, 5.f}, {0.f, 0.5f, 0.f}, {0.f, 1.f, 0.f});
}

/// Base of the panoramic cameras: CameraBase (ICamera only) with a rigid to_world, the
/// film's size, and the ray along a camera-space direction with the distance clipping above.
class PanoramaCamera : public CameraBase<ICamera> {
protected:
    explicit PanoramaCamera(const Properties& p) : CameraBase(p) {
        requireRigid(p, m_toWorld);
        m_size = filmSize(p, *m_film);
        m_origin = m_toWorld.point(Point3f(0.f));
    }

    /// The world ray along the camera-space direction `local` (unit), clipped by distance,
    /// at the shutter fraction u.
    Ray rayAlong(const Vector3f& local, float u) const {
        Ray ray;
        ray.d = normalize(m_toWorld.vector(local));
        ray.o = m_origin + ray.d * m_near;
        ray.tMax = m_far - m_near;
        return timed(ray, u);
    }

    Vector2f m_size{1.f};
    Point3f m_origin{0.f};
};

} // namespace effigi::camera
