// camera "thinlens" — a perspective camera with a thin lens of finite aperture
// (Mitsuba's `thinlens` sensor): depth of field.
//
// A film position selects a point on the plane in focus, at focus_distance along the
// viewing axis; the ray leaves a point sampled uniformly on the aperture disk (radius
// aperture_radius, in the plane z = 0 of the camera) toward it. Everything at the focus
// distance is therefore sharp and the rest is blurred by the circle of confusion. With
// aperture_radius 0 it is the pinhole camera. Camera space and the field of view follow
// Mitsuba (projection.hpp, shared with perspective): +z forward, +y up, +x left.
//
// The lens point is drawn through a warp (issue 14, effigi/render/warp_choice.hpp): by
// default the compiled-in code of warp `square_to_disk` (uniform on the unit disk, scaled
// by the radius). A nested `warp` (any warp onto the plane whose bounds cover the unit
// disk) replaces it in generateRay() and sampleDirection(); the aperture stays the disk,
// so a ray's weight becomes (1/π) / pdf(p) for the warp's point p inside the unit disk
// (uniform importance over the aperture, divided by the sampling density) and 0 outside
// it. Any warp covering the disk is thus unbiased; the default's weight is exactly 1.
//
// Parameters:
//   aperture_radius          float (scene units, >= 0; required, as in Mitsuba)  lens radius
//   focus_distance           float (scene units, > 0; default far_clip)  distance of the plane in focus
//   fov / fov_axis           float (deg, in (0, 180)) / string (x, y, diagonal, smaller, larger)
//   focal_length             string ("50mm", 35 mm equivalent; the default when fov is absent)
//   near_clip, far_clip      float (default 1e-2, 1e4)  rays run between these planes
//   to_world                 transform  camera-to-world (use lookat); no scaling
//   film, sampler            nested  default: hdrfilm and independent
//   warp                     nested warp (optional)  lens point sampler; default uniform on the disk
//
// Light tracers (ptracer) connect to it through ICameraImportance: the lens sample picks
// a point on the aperture and the scene point projects through it, via the plane in
// focus, to the film. The importance is uniform over the aperture and, from each lens
// point, over the image plane: W_e = 1 / (π r² · A cos⁴θ) (pbrt-v4's
// ThinLens/PerspectiveCamera::We, Mitsuba's thinlens importance()).
//
// Reference: M. Pharr, W. Jakob, G. Humphreys, Physically Based Rendering, 4th ed.,
// §5.2.3 (the thin lens model); R. L. Cook, T. Porter, L. Carpenter, "Distributed Ray
// Tracing", SIGGRAPH 1984; Mitsuba 3 documentation, "Perspective camera with a thin lens".
#include "projection.hpp"

#include "effigi/render/warp_choice.hpp"

namespace effigi {
namespace {

class ThinLensCamera final : public camera::ProjectiveCamera {
public:
    static Schema schema() {
        Schema s("camera", "thinlens", "Perspective camera with a thin lens: depth of field (Mitsuba's `thinlens`).");
        s.cite("R. L. Cook, T. Porter, L. Carpenter, Distributed Ray Tracing, SIGGRAPH 1984; PBRT 4th ed., §5.2.3");
        s.optional("aperture_radius", ParamType::Float, "Radius of the lens aperture (>= 0; 0 is a pinhole)")
            .isRequired()
            .atLeast(0.0)
            .withUnit("scene units");
        s.optional("focus_distance", ParamType::Float, "Distance from the lens to the plane in focus (default: far_clip)")
            .atLeast(0.0)
            .withUnit("scene units");
        camera::addFovParams(s, 0.0);
        s.transform("to_world", "Camera-to-world transform (lookat); rotation and translation only");
        camera::addCommonParams(s, "Near clip distance (> 0, < far_clip); rays start on the near plane");
        LensWarp::declare(s, "Lens point sampler (a warp onto the plane covering the unit disk, scaled by "
                             "aperture_radius); default: the code of warp `square_to_disk`, compiled in");
        // Conformance (conformance/camera_suite.cpp): an ordinary lens, an aperture of 0 and
        // near 0, a wide aperture focused close, the fov near both ends of (0, 180), and
        // near_clip close to far_clip around the focus distance.
        const Transform view = Transform::lookAt({1.f, 2.f, 5.f}, {0.f, 0.5f, 0.f}, {0.f, 1.f, 0.f});
        s.addConformance({"default", {{"to_world", view}, {"aperture_radius", 0.1}, {"focus_distance", 5.0}, {"fov", 40.0}}});
        s.addConformance({"aperture 0", {{"to_world", view}, {"aperture_radius", 0.0}, {"fov", 40.0}}});
        s.addConformance({"aperture 1e-6", {{"to_world", view}, {"aperture_radius", 1e-6}, {"focus_distance", 3.0}}});
        s.addConformance({"wide aperture, close focus", {{"to_world", view}, {"aperture_radius", 2.0}, {"focus_distance", 0.5},
                                                         {"fov", 50.0}, {"near_clip", 0.05}, {"far_clip", 100.0}}});
        s.addConformance({"tiny fov", {{"aperture_radius", 0.05}, {"focus_distance", 10.0}, {"fov", 1e-2}}});
        s.addConformance({"huge fov", {{"aperture_radius", 0.05}, {"focus_distance", 2.0}, {"fov", 179.0}}});
        s.addConformance({"near close to far", {{"to_world", view}, {"aperture_radius", 0.3}, {"focus_distance", 4.0},
                                                {"fov", 30.0}, {"near_clip", 4.0}, {"far_clip", 4.004}}});
        return s;
    }

    explicit ThinLensCamera(const Properties& p) : ProjectiveCamera(p) {
        camera::requireRigid(p, m_toWorld);
        m_aperture = p.getFloat("aperture_radius");
        if (!(m_aperture >= 0.f) || !std::isfinite(m_aperture))
            failAt(p.whereOf("aperture_radius"), "{}: parameter 'aperture_radius' must be >= 0, got {}", p.describe(),
                   m_aperture);
        m_focus = p.has("focus_distance") ? p.getFloat("focus_distance") : m_far;
        if (!(m_focus > 0.f) || !std::isfinite(m_focus))
            failAt(p.whereOf("focus_distance"), "{}: parameter 'focus_distance' must be positive, got {}", p.describe(),
                   m_focus);
        m_filmSize = camera::filmSize(p, *m_film);
        m_tanHalf = camera::imagePlaneHalfExtent(p, m_filmSize);
        m_area = 4.f * m_tanHalf.x * m_tanHalf.y;
        m_lens = LensWarp(p);
        if (const IWarp* w = m_lens.nestedWarp()) {
            WarpDomain dom = w->domain();
            if (!(dom.lower.x <= -1.f && dom.lower.y <= -1.f && dom.upper.x >= 1.f && dom.upper.y >= 1.f))
                failAt(p.whereOf("warp"), "{}: the nested warp '{}' (parameter 'warp') does not cover the unit disk "
                       "of the lens: its points lie in [{}, {}] x [{}, {}]", p.describe(), w->typeName(),
                       dom.lower.x, dom.upper.x, dom.lower.y, dom.upper.y);
        }
    }

    Ray generateRay(const CameraSample& s, const SampledWavelengths&, SampledSpectrum& weight) const override {
        // The point in focus for this film position, then a lens point toward it.
        Vector3f focus = m_focus * camera::imagePlanePoint(s.pFilm, m_filmSize, m_tanHalf);
        float lensWeight;
        Vector3f lensPoint = sampleLens(s.pLens, lensWeight);
        Vector3f d = normalize(focus - lensPoint);
        // Clip to the slab near <= z <= far of camera space, as Mitsuba does (d.z > 0:
        // the focus point lies in front of the lens).
        float invZ = 1.f / d.z;
        Ray ray;
        ray.d = normalize(m_toWorld.vector(d));
        ray.o = m_toWorld.point(Point3f(lensPoint + d * (m_near * invZ)));
        ray.tMax = (m_far - m_near) * invZ;
        weight = SampledSpectrum(lensWeight);
        return timed(ray, s.time);
    }

    /// The inverse of generateRay for the lens point of sample u: the ray from that lens
    /// point through ref meets the plane in focus at the point that names the film
    /// position. Importance over the lens density: W_e cosθ / dist² · π r² =
    /// 1 / (A cos³θ dist²), the aperture area cancelling (so aperture 0 is the pinhole).
    bool sampleDirection(const Point3f& ref, const Point2f& u, CameraImportanceSample& out) const override {
        out = CameraImportanceSample{};
        Point3f local = m_toLocal.point(ref);
        if (!(local.z >= m_near && local.z <= m_far)) return false;  // generateRay's clip slab
        float lensWeight;
        Vector3f lensPoint = sampleLens(u, lensWeight);
        if (!(lensWeight > 0.f)) return false;  // a nested warp's point off the lens
        Vector3f d = Vector3f(local) - lensPoint;  // d.z = local.z > 0
        // Where the line meets z = focus, divided by focus: on the image plane z = 1.
        Vector2f plane = Vector2f(lensPoint.x, lensPoint.y) / m_focus + Vector2f(d.x, d.y) / d.z;
        if (!camera::filmPosition(plane, m_filmSize, m_tanHalf, out.pFilm)) return false;
        float dist = length(d);
        float cosTheta = d.z / dist;
        out.pCamera = m_toWorld.point(Point3f(lensPoint));
        out.wi = normalize(m_toWorld.vector(-d));
        out.dist = dist;
        // The lens density 1 / (π r²) is folded into weight (pdf 1), as ptracer divides by pdf.
        out.weight = 1.f / (m_area * cosTheta * cosTheta * cosTheta * dist * dist);
        if (m_lens.nested()) out.weight *= lensWeight;
        out.pdf = 1.f;
        if (!std::isfinite(out.weight)) {
            out = CameraImportanceSample{};
            return false;
        }
        return true;
    }

    /// Given the lens point, a direction is as likely as its point on the plane of focus,
    /// uniform over that plane's window: 1 / (A cos³θ), as for a pinhole.
    float pdfDirection(const Point3f& lens, const Vector3f& d) const override {
        Vector3f local = m_toLocal.vector(d);
        float len = length(local);
        if (!(local.z > 0.f) || !(len > 0.f)) return 0.f;
        Point3f lensLocal = m_toLocal.point(lens);
        // Where the ray meets the plane of focus, divided by the focus distance: on z = 1.
        Vector3f focus = Vector3f(lensLocal.x, lensLocal.y, 0.f) + local * (m_focus / local.z);
        Point2f pFilm;
        if (!camera::filmPosition(Vector2f(focus.x, focus.y) / m_focus, m_filmSize, m_tanHalf, pFilm)) return 0.f;
        float cosTheta = local.z / len;
        return 1.f / (m_area * cosTheta * cosTheta * cosTheta);
    }

private:
    using LensWarp = WarpChoice<compiled_warp::SquareToDisk>;

    /// The lens point (camera space, z = 0) for u and its weight: uniform importance over
    /// the aperture over the warp's density, 1/(π pdf(p)) for p in the unit disk, else 0;
    /// exactly 1 for the default, which is uniform on the disk.
    Vector3f sampleLens(const Point2f& u, float& weight) const {
        Vector3f p = m_lens.sample(u);
        weight = 1.f;
        if (m_lens.nested()) {
            float pdf = m_lens.pdf(p);
            weight = p.x * p.x + p.y * p.y <= 1.f && pdf > 0.f ? InvPi / pdf : 0.f;
        }
        return {m_aperture * p.x, m_aperture * p.y, 0.f};
    }

    LensWarp m_lens;
    float m_aperture = 0.f, m_focus = 1e4f, m_area = 4.f;
    Vector2f m_filmSize{1.f}, m_tanHalf{1.f};
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::ThinLensCamera)
