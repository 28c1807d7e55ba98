#pragma once
// What the projective cameras (perspective, thinlens, orthographic) share: their common
// parameters, the field of view from fov / fov_axis or a 35 mm focal length, the clip
// planes, and the map from a film position to camera space with Mitsuba's conventions
// (the camera looks along +z, +y is up, +x is LEFT, so image right is camera −x), and
// the state and accessors of every camera (CameraBase, also under the panoramic cameras of
// panorama.hpp) and of ProjectiveCamera.
// Reference: Mitsuba 3 documentation, "Perspective pinhole camera", "Perspective camera
// with a thin lens", "Orthographic camera"; PBRT 4th ed., §5.1–5.2.
#include "effigi/core/input.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/icamera_importance.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/imedium.hpp"
#include "effigi/interfaces/isampler.hpp"

#include <cmath>
#include <cstdlib>
#include <string>

namespace effigi::camera {

/// A nested component, or the default one created from an empty parameter list.
template <typename I> Ref<I> nestedOrDefault(const Properties& p, const std::string& name, const char* defaultType) {
    Ref<I> obj = p.get<I>(name);
    if (obj) return obj;
    Properties defaults(I::Tag, defaultType, p.where());
    obj = query<I>(Registry::instance().create(I::Tag, defaultType, defaults));
    if (!obj) failAt(p.where(), "{}: the default {} '{}' is not a {}", p.describe(), I::Tag, defaultType, I::Tag);
    return obj;
}

/// near_clip, far_clip, film, sampler, medium.
inline void addCommonParams(Schema& s, const char* nearDoc) {
    s.real("near_clip", 1e-2, nearDoc).atLeast(0.0).withUnit("scene units");
    s.real("far_clip", 1e4, "Far clip distance (> near_clip); camera rays end there").atLeast(0.0).withUnit("scene units");
    s.child("film", "film", "Film the image is accumulated on (default: hdrfilm)");
    s.child("sampler", "sampler", "Sample generator (default: independent)");
    s.child("medium", "medium", "Participating medium the camera is in (optional; volpath)");
    s.real("shutter_open", 0.0, "Time the shutter opens; rays are timed uniformly until shutter_close");
    s.real("shutter_close", 0.0, "Time the shutter closes (>= shutter_open; equal: no motion blur)");
}

/// fov (with a default, or none: then focal_length decides), fov_axis, focal_length.
inline void addFovParams(Schema& s, double defaultFov) {
    const char* doc = "Field of view along fov_axis, strictly between 0 and 180";
    if (defaultFov > 0.0) s.real("fov", defaultFov, doc).range(0.0, 180.0).withUnit("deg");
    else s.optional("fov", ParamType::Float, doc).range(0.0, 180.0).withUnit("deg");
    s.string("fov_axis", "x", "Film axis the fov applies to: x, y, diagonal, or the smaller/larger of x and y")
        .oneOf({"x", "y", "diagonal", "smaller", "larger"});
    s.optional("focal_length", ParamType::String,
               "35 mm film equivalent focal length such as \"50mm\" (alternative to fov; sets the diagonal fov)");
}

/// Clip distances, checked: 0 < near < far.
inline void readClip(const Properties& p, float& nearClip, float& farClip) {
    nearClip = p.getFloat("near_clip");
    farClip = p.getFloat("far_clip");
    if (!(nearClip > 0.f) || !std::isfinite(nearClip))
        failAt(p.whereOf("near_clip"), "{}: parameter 'near_clip' must be positive", p.describe());
    if (!(farClip > nearClip))
        failAt(p.whereOf("far_clip"), "{}: parameter 'far_clip' = {} must exceed near_clip = {}", p.describe(), farClip,
               nearClip);
}

/// Ray lengths are measured in camera units, so a scaled transform would change distances
/// (Mitsuba forbids it too). Mirrors are fine.
inline void requireRigid(const Properties& p, const Transform& toWorld) {
    if (!toWorld.isFinite()) failAt(p.whereOf("to_world"), "{}: 'to_world' has non-finite entries", p.describe());
    glm::mat3 linear(toWorld.matrix());
    for (int c = 0; c < 3; ++c)
        if (std::abs(length(linear[c]) - 1.f) > 1e-3f)
            failAt(p.whereOf("to_world"), "{}: 'to_world' must not scale (use lookat, rotate, translate)", p.describe());
}

/// The film's full size in pixels (a crop window only selects which part is rendered:
/// the renderer adds cropOffset() to pFilm).
inline Vector2f filmSize(const Properties& p, const IFilm& film) {
    Vector2i size = film.fullSize();
    if (size.x <= 0 || size.y <= 0) failAt(p.where(), "{}: the film has an empty size {}x{}", p.describe(), size.x, size.y);
    return Vector2f(size);
}

/// Half-extents of the image plane at unit distance, tan of the half field of view along
/// x and y, from fov + fov_axis or from focal_length (35 mm film: 36 x 24 mm, whose
/// diagonal the focal length's field of view spans, as in Mitsuba).
inline Vector2f imagePlaneHalfExtent(const Properties& p, Vector2f size) {
    float aspect = size.x / size.y;
    const Properties::Entry* fovEntry = p.find("fov");
    bool fovGiven = fovEntry && !fovEntry->fromDefault;
    float fov;
    std::string axis = p.getString("fov_axis");
    if (p.has("focal_length")) {
        if (fovGiven)
            failAt(p.whereOf("focal_length"), "{}: give either 'fov' or 'focal_length', not both", p.describe());
        std::string f = p.getString("focal_length");
        if (f.size() > 2 && f.compare(f.size() - 2, 2, "mm") == 0) f.resize(f.size() - 2);
        char* end = nullptr;
        double mm = std::strtod(f.c_str(), &end);
        if (f.empty() || *end != '\0' || !(mm > 0.0) || !std::isfinite(mm))
            failAt(p.whereOf("focal_length"), "{}: parameter 'focal_length' = '{}' must be a positive length like \"50mm\"",
                   p.describe(), excerpt(p.getString("focal_length")));
        fov = float(2.0 * std::atan(std::sqrt(36.0 * 36.0 + 24.0 * 24.0) / (2.0 * mm)) * 180.0 / double(Pi));
        axis = "diagonal";
    } else if (fovEntry) {
        fov = p.getFloat("fov");
    } else {
        fov = float(2.0 * std::atan(std::sqrt(36.0 * 36.0 + 24.0 * 24.0) / 100.0) * 180.0 / double(Pi));  // 50mm
        axis = "diagonal";
    }
    if (!(fov > 0.f && fov < 180.f))
        failAt(p.whereOf("fov"), "{}: parameter 'fov' = {} must lie strictly between 0 and 180 degrees", p.describe(), fov);
    if (axis == "smaller") axis = aspect > 1.f ? "y" : "x";
    if (axis == "larger") axis = aspect > 1.f ? "x" : "y";
    float t = std::tan(0.5f * degToRad(fov));
    if (axis == "x") return {t, t / aspect};
    if (axis == "y") return {t * aspect, t};
    float h = t / std::sqrt(1.f + aspect * aspect);  // diagonal: split in the ratio W : H
    return {h * aspect, h};
}

/// Camera-space point (x, y, 1) that the film position pFilm (pixels, x right, y down)
/// maps to on the plane z = 1, for image-plane half-extents `half` and a principal-point
/// offset in film sizes. Image right is camera −x and image top is +y, hence the flips.
inline Vector3f imagePlanePoint(const Point2f& pFilm, const Vector2f& size, const Vector2f& half,
                                const Vector2f& offset = Vector2f(0.f)) {
    Point2f q = pFilm / size + offset;
    return {(1.f - 2.f * q.x) * half.x, (1.f - 2.f * q.y) * half.y, 1.f};
}

/// The inverse of imagePlanePoint: the film position (pixels) of the camera-space plane
/// point (x, y) at z = 1. False when it falls outside the full film.
inline bool filmPosition(const Vector2f& plane, const Vector2f& size, const Vector2f& half, Point2f& pFilm,
                         const Vector2f& offset = Vector2f(0.f)) {
    Point2f q = 0.5f * (Vector2f(1.f) - plane / half) - offset;
    pFilm = q * size;
    return q.x >= 0.f && q.x <= 1.f && q.y >= 0.f && q.y <= 1.f;
}

/// The state every camera keeps (to_world, the nested film and sampler, the optional
/// medium, the clip distances, checked by readClip) and the ICamera accessors to it;
/// `Interfaces` are those the camera implements (ICamera, maybe ICameraImportance).
template <typename... Interfaces> class CameraBase : public Implements<Interfaces...> {
public:
    const Transform& toWorld() const override { return m_toWorld; }
    IFilm& film() const override { return *m_film; }
    ISampler& sampler() const override { return *m_sampler; }
    const IMedium* medium() const override { return m_medium.get(); }
    float shutterOpen() const override { return m_shutterOpen; }
    float shutterClose() const override { return m_shutterClose; }
    bool moves() const override { return m_motion.isAnimated(); }

protected:
    explicit CameraBase(const Properties& p)
        : m_motion(p.getAnimatedTransform("to_world")), m_toWorld(m_motion.first()),
          m_film(nestedOrDefault<IFilm>(p, "film", "hdrfilm")),
          m_sampler(nestedOrDefault<ISampler>(p, "sampler", "independent")), m_medium(p.get<IMedium>("medium")),
          m_shutterOpen(p.getFloat("shutter_open")), m_shutterClose(p.getFloat("shutter_close")) {
        readClip(p, m_near, m_far);
        if (m_shutterClose < m_shutterOpen)
            failAt(p.whereOf("shutter_close"), "{}: 'shutter_close' = {} is before 'shutter_open' = {}", p.describe(),
                   m_shutterClose, m_shutterOpen);
        // A moving camera carries its rays rigidly from the first pose to the pose at their
        // time, so ray lengths (the clip distances) must survive every pose.
        if (moves())
            for (const AnimatedTransform::Key& k : m_motion.keys()) requireRigid(p, k.transform);
        m_fromRest = m_toWorld.inverse();
    }

    /// The ray of the first pose, timed within the shutter interval (u in [0, 1)) and,
    /// for a moving camera, carried to the pose at that time.
    Ray timed(Ray ray, float u) const {
        ray.time = m_shutterOpen + u * (m_shutterClose - m_shutterOpen);
        if (!m_motion.isAnimated()) return ray;
        const Transform delta = m_motion.at(ray.time) * m_fromRest;
        ray.o = delta.point(ray.o);
        ray.d = normalize(delta.vector(ray.d));
        return ray;
    }

    AnimatedTransform m_motion;
    Transform m_toWorld;  ///< the first pose (the only one of a still camera)
    Transform m_fromRest;
    Ref<IFilm> m_film;
    Ref<ISampler> m_sampler;
    Ref<IMedium> m_medium;
    float m_near = 1e-2f, m_far = 1e4f;
    float m_shutterOpen = 0.f, m_shutterClose = 0.f;
};

/// Base of the projective cameras: CameraBase with the light tracers' connection.
/// Derived cameras check to_world their own way and add generateRay and
/// ICameraImportance::sampleDirection (the inverse of generateRay).
class ProjectiveCamera : public CameraBase<ICamera, ICameraImportance> {
protected:
    explicit ProjectiveCamera(const Properties& p) : CameraBase(p) {
        m_toLocal = m_toWorld.inverse();  // non-finite for a singular to_world, which derived cameras reject
    }

    Transform m_toLocal;
};

} // namespace effigi::camera
