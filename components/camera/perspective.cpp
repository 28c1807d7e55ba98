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
//   fov                      float (deg, default 39.3077, in (0, 180))  field of view along fov_axis
//   fov_axis                 string (x, y, diagonal, smaller, larger; default x)
//   near_clip, far_clip      float (default 1e-2, 1e4)  clip distances; rays end at far_clip.
//                            Rays start at the pinhole itself (near_clip is validated only).
//   to_world                 transform  camera-to-world (use lookat); no scaling
//   principal_point_offset_x/_y  float (default 0)  image-plane shift, fraction of the film size
//   film, sampler            nested  default: hdrfilm and independent
//
// Reference: M. Pharr, W. Jakob, G. Humphreys, Physically Based Rendering, 4th ed., §5.2.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/isampler.hpp"

namespace effigi {
namespace {

/// A nested component, or the default one created from an empty parameter list.
template <typename I> Ref<I> nestedOrDefault(const Properties& p, const std::string& name, const char* defaultType) {
    Ref<I> obj = p.get<I>(name);
    if (obj) return obj;
    Properties defaults(I::Tag, defaultType, p.where());
    obj = query<I>(Registry::instance().create(I::Tag, defaultType, defaults));
    if (!obj) failAt(p.where(), "{}: the default {} '{}' is not a {}", p.describe(), I::Tag, defaultType, I::Tag);
    return obj;
}

class PerspectiveCamera final : public Implements<ICamera> {
public:
    static Schema schema() {
        Schema s("camera", "perspective", "Pinhole camera with a perspective projection (Mitsuba's `perspective`).");
        s.cite("M. Pharr, W. Jakob, G. Humphreys, Physically Based Rendering, 4th ed., §5.2");
        s.real("fov", 39.3077, "Field of view along fov_axis, strictly between 0 and 180").range(0.0, 180.0).withUnit("deg");
        s.string("fov_axis", "x", "Film axis the fov applies to: x, y, diagonal, or the smaller/larger of x and y")
            .oneOf({"x", "y", "diagonal", "smaller", "larger"});
        s.real("near_clip", 1e-2, "Near clip distance (> 0, < far_clip); rays start at the pinhole").atLeast(0.0).withUnit("scene units");
        s.real("far_clip", 1e4, "Far clip distance (> near_clip); camera rays end there").atLeast(0.0).withUnit("scene units");
        s.transform("to_world", "Camera-to-world transform (lookat); rotation and translation only");
        s.real("principal_point_offset_x", 0.0, "Horizontal shift of the image centre, as a fraction of the film width")
            .withUnit("film widths");
        s.real("principal_point_offset_y", 0.0, "Vertical shift of the image centre, as a fraction of the film height")
            .withUnit("film heights");
        s.child("film", "film", "Film the image is accumulated on (default: hdrfilm)");
        s.child("sampler", "sampler", "Sample generator (default: independent)");
        return s;
    }

    explicit PerspectiveCamera(const Properties& p)
        : m_toWorld(p.getTransform("to_world")),
          m_film(nestedOrDefault<IFilm>(p, "film", "hdrfilm")),
          m_sampler(nestedOrDefault<ISampler>(p, "sampler", "independent")) {
        float fov = p.getFloat("fov");
        if (!(fov > 0.f && fov < 180.f))
            failAt(p.whereOf("fov"), "{}: parameter 'fov' = {} must lie strictly between 0 and 180 degrees",
                   p.describe(), fov);
        m_near = p.getFloat("near_clip");
        m_far = p.getFloat("far_clip");
        if (!(m_near > 0.f))
            failAt(p.whereOf("near_clip"), "{}: parameter 'near_clip' must be positive", p.describe());
        if (!(m_far > m_near))
            failAt(p.whereOf("far_clip"), "{}: parameter 'far_clip' = {} must exceed near_clip = {}", p.describe(),
                   m_far, m_near);
        if (!m_toWorld.isFinite())
            failAt(p.whereOf("to_world"), "{}: 'to_world' has non-finite entries", p.describe());
        // tMax = far/cos θ is measured in camera units; a scaled transform would change
        // distances (Mitsuba forbids it too). Mirrors are fine.
        glm::mat3 linear(m_toWorld.matrix());
        for (int c = 0; c < 3; ++c)
            if (std::abs(length(linear[c]) - 1.f) > 1e-3f)
                failAt(p.whereOf("to_world"), "{}: 'to_world' must not scale (use lookat, rotate, translate)",
                       p.describe());
        m_offset = Vector2f(p.getFloat("principal_point_offset_x"), p.getFloat("principal_point_offset_y"));

        // The projection covers the whole film; a crop window only selects which part of
        // it is rendered (the renderer adds cropOffset() to pFilm).
        Vector2i size = m_film->fullSize();
        if (size.x <= 0 || size.y <= 0)
            failAt(p.where(), "{}: the film has an empty size {}x{}", p.describe(), size.x, size.y);
        m_filmSize = Vector2f(size);
        float aspect = m_filmSize.x / m_filmSize.y;

        std::string axis = p.getString("fov_axis");
        if (axis == "smaller") axis = aspect > 1.f ? "y" : "x";
        if (axis == "larger") axis = aspect > 1.f ? "x" : "y";
        float t = std::tan(0.5f * degToRad(fov));
        // Half-extents of the image plane at unit distance.
        if (axis == "x") {
            m_tanHalf = Vector2f(t, t / aspect);
        } else if (axis == "y") {
            m_tanHalf = Vector2f(t * aspect, t);
        } else {  // diagonal: t is the half-diagonal, split in the ratio W : H
            float h = t / std::sqrt(1.f + aspect * aspect);
            m_tanHalf = Vector2f(h * aspect, h);
        }
        m_origin = m_toWorld.point(Point3f(0.f));
    }

    Ray generateRay(const CameraSample& s, const SampledWavelengths&, SampledSpectrum& weight) const override {
        // Film position -> [0,1]² (x right, y down) -> image plane. Image right is camera
        // −x and image top is camera +y, hence the flips.
        Point2f q = s.pFilm / m_filmSize + m_offset;
        Vector3f local((1.f - 2.f * q.x) * m_tanHalf.x, (1.f - 2.f * q.y) * m_tanHalf.y, 1.f);
        local = normalize(local);
        // Rays start on the near plane and end on the far plane (Mitsuba's clipping).
        Ray ray;
        ray.d = normalize(m_toWorld.vector(local));
        ray.o = m_origin + ray.d * (m_near / local.z);
        ray.tMax = (m_far - m_near) / local.z;
        weight = SampledSpectrum(1.f);
        return ray;
    }

    const Transform& toWorld() const override { return m_toWorld; }
    IFilm& film() const override { return *m_film; }
    ISampler& sampler() const override { return *m_sampler; }

private:
    Transform m_toWorld;
    Ref<IFilm> m_film;
    Ref<ISampler> m_sampler;
    float m_near = 1e-2f, m_far = 1e4f;
    Vector2f m_offset{0.f}, m_filmSize{1.f}, m_tanHalf{1.f};
    Point3f m_origin{0.f};
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::PerspectiveCamera)
