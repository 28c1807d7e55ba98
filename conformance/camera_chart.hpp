#pragma once
// Camera suite: the camera under test with one film (CameraSetup) and its helpers, and
// charts of camera-space directions for the importance checks. Projective
// cameras see only ahead (z > 0) and are charted gnomonically, (x/z, y/z); panoramic
// cameras (spherical, a 360° cylinder) see to the side and behind, so their directions
// are charted on the sphere: x = atan2(d.x, d.z) (azimuth about +y), y = acos d.y (polar
// angle from +y), dω = sin y dx dy, with the seam behind the camera, where their films
// wrap. (Not the equal-area y = d.y: a latitude-longitude film's density per unit of it is
// 1/sin θ, singular at the poles, which cell quadrature cannot integrate.)
#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/icamera_importance.hpp"
#include "effigi/interfaces/ifilm.hpp"

#include <glm/glm.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace effigi::conform {

/// Whether some ray of the camera looks sideways or back (camera-space z ≤ 0), from a
/// 17 × 17 grid of film positions, edges included.
inline bool seesAround(const ICamera& cam) {
    const Vector2f full(cam.film().fullSize());
    const glm::dmat4 toLocal = glm::inverse(glm::dmat4(cam.toWorld().matrix()));
    for (int i = 0; i <= 16; ++i)
        for (int j = 0; j <= 16; ++j) {
            SampledSpectrum w;
            const Ray r = cam.generateRay({Point2f(full.x * float(i) / 16.f, full.y * float(j) / 16.f), Point2f(0.5f), 0.f},
                                          SampledWavelengths::sampleUniform(0.37f), w);
            if ((toLocal * glm::dvec4(glm::dvec3(r.d), 0.0)).z <= 0.0) return true;
        }
    return false;
}

/// The sphere chart of a camera-space direction (need not be unit).
inline void sphereChart(glm::dvec3 d, double& x, double& y) {
    d = glm::normalize(d);
    x = std::atan2(d.x, d.z);
    y = std::acos(std::clamp(d.y, -1.0, 1.0));
}

/// The unit camera-space direction at sphere-chart coordinates (x, y).
inline glm::dvec3 sphereDirection(double x, double y) {
    return {std::sin(y) * std::sin(x), std::cos(y), std::sin(y) * std::cos(x)};
}


inline constexpr double U = 0x1p-24;  // float unit roundoff

/// A camera under test with one film, and its transforms in double.
struct CameraSetup {
    std::string label;  // the film it runs with
    Ref<ICamera> cam;
    const ICameraImportance* imp = nullptr;
    Vector2f full{1.f};
    glm::dmat4 toWorld{1.0}, toLocal{1.0};
    glm::dvec3 eye{0.0};  // camera origin in world space
    bool around = false;  // rays look sideways or back: sphere chart, film may wrap (camera_chart.hpp)
};

inline glm::dvec3 local(const CameraSetup& s, const Point3f& p) { return glm::dvec3(s.toLocal * glm::dvec4(glm::dvec3(p), 1.0)); }
inline glm::dvec3 localDir(const CameraSetup& s, const Vector3f& d) { return glm::dvec3(s.toLocal * glm::dvec4(glm::dvec3(d), 0.0)); }
inline Point3f world(const CameraSetup& s, const glm::dvec3& p) { return Point3f(glm::dvec3(s.toWorld * glm::dvec4(p, 1.0))); }

inline Ray rayAt(const CameraSetup& s, Point2f film, Point2f lens, SampledSpectrum& w) {
    CameraSample cs;
    cs.pFilm = film;
    cs.pLens = lens;
    return s.cam->generateRay(cs, SampledWavelengths::sampleUniform(0.37f), w);
}

inline std::string str(Point2f p) { return fmt::format("({:.7g}, {:.7g})", p.x, p.y); }

} // namespace effigi::conform
