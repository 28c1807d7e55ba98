// camera "bad_project_camera" — DELIBERATELY WRONG test plugin: a pinhole camera whose
// projection (ICameraImportance::sampleDirection, what light tracers connect to) forgets
// that film y grows downward while camera y points up, so a point seen by the top rows of
// the image is reported on the bottom rows: the projection is generateRay's inverse
// mirrored about the film's middle row.
//
// generateRay is right (Mitsuba's perspective camera with fov along x: unit rays from the
// near plane to the far plane), and the importance and the connection's direction,
// distance, weight and pdf depend only on where the point is, not on the film position
// reported, so they are right too. effigi-conform must single out "projection inverts
// generateRay" (tests/plugins/run_plugin_tests.cmake).
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/icamera_importance.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/isampler.hpp"

#include <cmath>

namespace {
using namespace effigi;

template <typename I> Ref<I> nestedOrDefault(const Properties& p, const char* name, const char* type) {
    if (Ref<I> obj = p.get<I>(name)) return obj;
    Properties defaults(I::Tag, type, p.where());
    return query<I>(Registry::instance().create(I::Tag, type, defaults));
}

class BadProjectCamera final : public Implements<ICamera, ICameraImportance> {
public:
    static Schema schema() {
        Schema s("camera", "bad_project_camera", "Test plugin: a pinhole camera whose projection mirrors film y.");
        s.real("fov", 50.0, "Field of view along x").range(0.0, 180.0).withUnit("deg");
        s.real("near_clip", 1e-2, "Near clip distance").atLeast(0.0);
        s.real("far_clip", 1e4, "Far clip distance").atLeast(0.0);
        s.transform("to_world", "Camera-to-world transform (rigid)");
        s.child("film", "film", "Film (default: hdrfilm)");
        s.child("sampler", "sampler", "Sampler (default: independent)");
        s.addConformance({"default", {}});
        const Transform view = Transform::lookAt({1.f, 2.f, 5.f}, {0.f, 0.5f, 0.f}, {0.f, 1.f, 0.f});
        s.addConformance({"lookat fov 60", {{"to_world", view}, {"fov", 60.0}, {"near_clip", 0.05}, {"far_clip", 30.0}}});
        return s;
    }

    explicit BadProjectCamera(const Properties& p)
        : m_toWorld(p.getTransform("to_world")), m_toLocal(m_toWorld.inverse()),
          m_film(nestedOrDefault<IFilm>(p, "film", "hdrfilm")),
          m_sampler(nestedOrDefault<ISampler>(p, "sampler", "independent")),
          m_near(p.getFloat("near_clip")), m_far(p.getFloat("far_clip")) {
        if (!(p.getFloat("fov") > 0.f && p.getFloat("fov") < 180.f))
            failAt(p.whereOf("fov"), "{}: 'fov' must lie strictly between 0 and 180", p.describe());
        if (!(m_near > 0.f && m_far > m_near))
            failAt(p.whereOf("far_clip"), "{}: need 0 < near_clip < far_clip", p.describe());
        m_size = Vector2f(m_film->fullSize());
        float t = std::tan(0.5f * degToRad(p.getFloat("fov")));
        m_half = Vector2f(t, t * m_size.y / m_size.x);
        m_origin = m_toWorld.point(Point3f(0.f));
    }

    Ray generateRay(const CameraSample& s, const SampledWavelengths&, SampledSpectrum& weight) const override {
        // Film x right, y down; camera +x is image left and +y image up (Mitsuba).
        Point2f q = s.pFilm / m_size;
        Vector3f local = normalize(Vector3f((1.f - 2.f * q.x) * m_half.x, (1.f - 2.f * q.y) * m_half.y, 1.f));
        Ray ray;
        ray.d = normalize(m_toWorld.vector(local));
        ray.o = m_origin + ray.d * (m_near / local.z);
        ray.tMax = (m_far - m_near) / local.z;
        weight = SampledSpectrum(1.f);
        return ray;
    }

    bool sampleDirection(const Point3f& ref, const Point2f&, CameraImportanceSample& out) const override {
        out = CameraImportanceSample{};
        Point3f local = m_toLocal.point(ref);
        if (!(local.z >= m_near && local.z <= m_far)) return false;
        Vector2f plane(local.x / local.z, local.y / local.z);
        // The bug: generateRay's inverse is q.y = (1 − y/half.y)/2; the sign of y is lost.
        Point2f q(0.5f * (1.f - plane.x / m_half.x), 0.5f * (1.f + plane.y / m_half.y));
        if (!(q.x >= 0.f && q.x <= 1.f && q.y >= 0.f && q.y <= 1.f)) return false;
        float dist = length(Vector3f(local)), cosTheta = local.z / dist;
        out.pFilm = q * m_size;
        out.pCamera = m_origin;
        out.wi = (m_origin - ref) / dist;
        out.dist = dist;
        // Importance uniform over the image plane z = 1 of area 4·half.x·half.y, per solid angle.
        out.weight = 1.f / (4.f * m_half.x * m_half.y * cosTheta * cosTheta * cosTheta * dist * dist);
        out.pdf = 1.f;
        return std::isfinite(out.weight);
    }

    const Transform& toWorld() const override { return m_toWorld; }
    IFilm& film() const override { return *m_film; }
    ISampler& sampler() const override { return *m_sampler; }

private:
    Transform m_toWorld, m_toLocal;
    Ref<IFilm> m_film;
    Ref<ISampler> m_sampler;
    float m_near, m_far;
    Vector2f m_size{1.f}, m_half{1.f};
    Point3f m_origin{0.f};
};

} // namespace

EFFIGI_EXPORT_COMPONENT(BadProjectCamera)
