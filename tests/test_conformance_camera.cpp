// The camera conformance suite (conformance/camera_suite.cpp) fails wrong cameras by the
// right checks. Each test camera wraps a real perspective camera and breaks one promise:
// - test_cam_shifted: its connection (ICameraImportance) reports film positions one
//   pixel to the right of the ray it inverts -> "projection inverts generateRay";
// - test_cam_heavy: its importance is 1.5 times too large -> "importance chi-square"
//   and "importance integral";
// - test_cam_unclipped: its rays start at the eye and run to far_clip, ignoring
//   near_clip -> "clip range".
// The shipped cameras pass the suite (tested by the ctest effigi-conform-quick).
#include "conform_session.hpp"
#include "conformance/conformance.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/icamera_importance.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "temp_files.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <mutex>

using namespace effigi;
using effigi::test::sessionTable;
using effigi::test::verdictOf;

namespace {

enum class Fault { Shifted, Heavy, Unclipped };

class FaultyCamera final : public Implements<ICamera, ICameraImportance> {
public:
    FaultyCamera(Fault f, Ref<ICamera> inner) : m_fault(f), m_inner(std::move(inner)) {
        m_imp = query<ICameraImportance>(m_inner.get());
    }
    Ray generateRay(const CameraSample& s, const SampledWavelengths& l, SampledSpectrum& w) const override {
        Ray r = m_inner->generateRay(s, l, w);
        if (m_fault == Fault::Unclipped) {
            Point3f eye = m_inner->toWorld().point(Point3f(0.f));
            float back = length(r.o - eye);
            r.o = eye;
            r.tMax += back;
        }
        return r;
    }
    bool sampleDirection(const Point3f& ref, const Point2f& u, CameraImportanceSample& out) const override {
        bool ok = m_imp->sampleDirection(ref, u, out);
        if (m_fault == Fault::Shifted) out.pFilm.x += 1.f;
        if (m_fault == Fault::Heavy) out.weight *= 1.5f;
        return ok;
    }
    const Transform& toWorld() const override { return m_inner->toWorld(); }
    IFilm& film() const override { return m_inner->film(); }
    ISampler& sampler() const override { return m_inner->sampler(); }

private:
    Fault m_fault;
    Ref<ICamera> m_inner;
    const ICameraImportance* m_imp = nullptr;
};

void registerFaulty() {
    static std::once_flag once;
    std::call_once(once, [] {
        for (auto [name, fault] : {std::pair{"test_cam_shifted", Fault::Shifted}, std::pair{"test_cam_heavy", Fault::Heavy},
                                   std::pair{"test_cam_unclipped", Fault::Unclipped}}) {
            Schema s("camera", name, "wrong camera (tests/test_conformance_camera.cpp)");
            s.real("fov", 50.0, "field of view along x").range(0.0, 180.0);
            s.real("near_clip", 0.1, "near clip").atLeast(0.0);
            s.real("far_clip", 100.0, "far clip").atLeast(0.0);
            s.child("film", "film", "film");
            s.addConformance({"default", {}});
            Registry::instance().add(ComponentInfo{
                s,
                [fault = fault](const Properties& p) -> Ref<IComponent> {
                    Properties q("camera", "perspective");
                    q.set("to_world", Transform::lookAt({1.f, 2.f, 5.f}, {0.f, 0.5f, 0.f}, {0.f, 1.f, 0.f}));
                    for (const char* k : {"fov", "near_clip", "far_clip"}) q.set(k, double(p.getFloat(k)));
                    if (Ref<IFilm> f = p.get<IFilm>("film")) q.set("film", ComponentValue{"film", f});
                    Ref<ICamera> inner = query<ICamera>(Registry::instance().create("camera", "perspective", q));
                    return std::make_shared<FaultyCamera>(fault, inner);
                },
                {}});
        }
    });
}

} // namespace

TEST_CASE("camera conformance: the suite fails wrong cameras by the right checks", "[camera][conformance]") {
    registerFaulty();
    test::ScratchDir out("conform-camera");
    // Each run holds one camera's statistical tests only, so the Šidák level is about
    // 0.01 per test; the faults are large enough to fail at far smaller levels.
    auto run = [&](const std::string& name) {
        conform::Options o;
        o.tag = "camera";
        o.component = name;
        o.quick = true;
        o.outDir = out.dir();
        conform::Session s(o);
        s.run();
        return s;
    };
    using conform::Verdict;
    {
        conform::Session s = run("test_cam_shifted");
        INFO(sessionTable(s));
        CHECK(verdictOf(s, "test_cam_shifted", "projection inverts generateRay") == Verdict::Fail);
        CHECK(verdictOf(s, "test_cam_shifted", "film maps into image") == Verdict::Pass);
        CHECK(verdictOf(s, "test_cam_shifted", "clip range") == Verdict::Pass);
        CHECK(verdictOf(s, "test_cam_shifted", "importance integral") == Verdict::Pass);
    }
    {
        conform::Session s = run("test_cam_heavy");
        INFO(sessionTable(s));
        CHECK(verdictOf(s, "test_cam_heavy", "importance chi-square") == Verdict::Fail);
        CHECK(verdictOf(s, "test_cam_heavy", "importance integral") == Verdict::Fail);
        CHECK(verdictOf(s, "test_cam_heavy", "projection inverts generateRay") == Verdict::Pass);
        CHECK(verdictOf(s, "test_cam_heavy", "connection geometry") == Verdict::Pass);
    }
    {
        conform::Session s = run("test_cam_unclipped");
        INFO(sessionTable(s));
        CHECK(verdictOf(s, "test_cam_unclipped", "clip range") == Verdict::Fail);
        CHECK(verdictOf(s, "test_cam_unclipped", "film maps into image") == Verdict::Pass);
    }
}
