#pragma once
// What the panoramic cameras (spherical, panoramic, fisheye) share: a central camera
// whose directions are not those of a plane through the image, so none of them is a
// ProjectiveCamera. They keep the projective cameras' parameters and checks
// (projection.hpp: film, sampler, medium, near_clip/far_clip, a rigid to_world) but clip
// by DISTANCE from the eye rather than by depth: a ray starts near_clip along its own
// direction and runs far_clip − near_clip, since a plane z = near cannot bound rays that
// look sideways or backwards (Mitsuba 0.6's spherical camera clips the same way).
// spherical and panoramic implement ICameraImportance (light paths connect to them: ptracer,
// bdpt); fisheye does not, and the light tracers refuse it with a one-line error.
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

/// What a panoramic camera's projection gives for a camera-space direction: the film
/// position as a fraction of the film, and the density per unit solid angle with which
/// generateRay produces the direction (film positions uniform).
struct PanoramaProjection {
    Point2f q{0.f};
    float pdf = 0.f;
};

/// Base of the panoramic cameras: CameraBase (ICamera, and ICameraImportance for those
/// that connect to light paths) with a rigid to_world, the film's size, and the ray along
/// a camera-space direction with the distance clipping above.
template <typename... Extra> class PanoramaCameraBase : public CameraBase<ICamera, Extra...> {
protected:
    explicit PanoramaCameraBase(const Properties& p) : CameraBase<ICamera, Extra...>(p) {
        requireRigid(p, this->m_toWorld);
        m_size = filmSize(p, *this->m_film);
        m_origin = this->m_toWorld.point(Point3f(0.f));
    }

    /// The world ray along the camera-space direction `local` (unit), clipped by distance,
    /// at the shutter fraction u.
    Ray rayAlong(const Vector3f& local, float u) const {
        Ray ray;
        ray.d = normalize(this->m_toWorld.vector(local));
        ray.o = m_origin + ray.d * this->m_near;
        ray.tMax = this->m_far - this->m_near;
        return this->timed(ray, u);
    }

    /// ICameraImportance::sampleDirection for a central camera: the eye is a point (pdf 1)
    /// and the importance toward ref is the ray density of its direction (integrating to 1
    /// over the full film, as ICameraImportance asks) over dist². `project` maps a unit
    /// camera-space direction to a PanoramaProjection (pdf 0: outside the film).
    template <typename Project>
    bool connect(const Point3f& ref, CameraImportanceSample& out, Project&& project) const {
        out = CameraImportanceSample{};
        const Vector3f local = Vector3f(this->m_fromRest.point(ref));
        const float dist = length(local);
        if (!(dist >= this->m_near && dist <= this->m_far)) return false;  // rayAlong's clip range
        const PanoramaProjection pr = project(local / dist);
        if (!(pr.pdf > 0.f) || !std::isfinite(pr.pdf)) return false;
        out.pFilm = Point2f(pr.q.x * m_size.x, pr.q.y * m_size.y);
        out.pCamera = m_origin;
        out.wi = normalize(m_origin - ref);
        out.dist = dist;
        out.weight = pr.pdf / (dist * dist);
        out.pdf = 1.f;
        return true;
    }

    /// ICameraImportance::pdfDirection by the same projection.
    template <typename Project> float densityOf(const Vector3f& d, Project&& project) const {
        const Vector3f local = this->m_fromRest.vector(d);
        const float l = length(local);
        return l > 0.f ? project(local / l).pdf : 0.f;
    }

    Vector2f m_size{1.f};
    Point3f m_origin{0.f};
};

using PanoramaCamera = PanoramaCameraBase<>;

} // namespace effigi::camera
