// The emitter conformance suite (conformance/emitter_suite.cpp) fails deliberately
// broken emitters by the right checks, and passes the shipped ones' ordinary case.
// The suite's statistical checks are seeded (Options::seed) and decided at the
// family-wise significance α = 0.01 with Šidák's correction; the faults below are large
// (a factor 2, a skewed warp, a 1/d law), so they fail with p far below any level.
#include "conform_session.hpp"
#include "conformance/conformance.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/math/warp_functions.hpp"

#include "app_runner.hpp"

#include <catch2/catch.hpp>
#include <fmt/format.h>

#include <mutex>
#include <set>

using namespace effigi;
using effigi::test::sessionTable;
using effigi::test::verdictOf;

namespace {

/// An isotropic point light of intensity 1 at the origin. HalfPdf: sampleEmission()
/// reports twice the density it samples with. InverseDistance: sampleDirect() falls off
/// as 1/d instead of 1/d².
class TestPoint final : public Implements<IEmitter> {
public:
    enum class Fault { HalfPdf, InverseDistance };
    explicit TestPoint(Fault f) : m_fault(f) {}
    std::uint32_t flags() const override { return EmitterDeltaPosition; }
    EmitterSample sampleDirect(const Point3f& ref, const Point2f&, const SampledWavelengths&) const override {
        EmitterSample es;
        Vector3f d = Point3f(0.f) - ref;
        float dist = length(d);
        if (!(dist > 0.f) || !std::isfinite(dist)) return es;
        es.dist = dist;
        es.wi = d / dist;
        es.n = -es.wi;
        es.pdf = 1.f;
        es.delta = true;
        es.L = SampledSpectrum(m_fault == Fault::InverseDistance ? 1.f / dist : 1.f / (dist * dist));
        return es;
    }
    EmissionSample sampleEmission(const Point2f&, const Point2f& u, const SampledWavelengths&) const override {
        EmissionSample es;
        Vector3f d = warp::squareToUniformSphere(u);
        es.ray = Ray{Point3f(0.f), d, Infinity};
        es.n = Normal3f(d);
        es.pdfPosition = 1.f;
        es.pdfDirection = warp::squareToUniformSpherePdf(d) * (m_fault == Fault::HalfPdf ? 2.f : 1.f);
        es.L = SampledSpectrum(1.f);
        return es;
    }
    float power() const override { return 4.f * Pi; }

private:
    Fault m_fault;
};

/// A diffuse area light of radiance 1 whose sampleDirect() skews the shape's sampling
/// (u.x → u.x²) while reporting the shape's unskewed density.
class TestSkewedArea final : public Implements<IEmitter> {
public:
    std::uint32_t flags() const override { return EmitterSurface; }
    void attach(const IShape* shape) override { m_shape = shape; }
    SampledSpectrum eval(const SurfaceInteraction& si, const SampledWavelengths&) const override {
        return SampledSpectrum(dot(si.n, si.wo) > 0.f ? 1.f : 0.f);
    }
    EmitterSample sampleDirect(const Point3f& ref, const Point2f& u, const SampledWavelengths&) const override {
        EmitterSample es;
        DirectionSample ds = m_shape->sampleDirection(ref, Point2f(u.x * u.x, u.y));
        es.p = ds.p;
        es.n = ds.n;
        es.wi = ds.wi;
        es.dist = ds.dist;
        if (!(ds.pdf > 0.f) || !(dot(ds.n, -ds.wi) > 0.f)) return es;
        es.pdf = ds.pdf;
        es.L = SampledSpectrum(1.f);
        return es;
    }
    float pdfDirect(const Point3f& ref, const SurfaceInteraction& si) const override {
        return dot(si.n, si.wo) > 0.f ? m_shape->pdfDirection(ref, si) : 0.f;
    }
    EmissionSample sampleEmission(const Point2f& uPos, const Point2f& uDir, const SampledWavelengths&) const override {
        EmissionSample es;
        PositionSample ps = m_shape->samplePosition(uPos);
        Vector3f local = warp::squareToCosineHemisphere(uDir);
        Vector3f d = Frame(ps.n).toWorld(local);
        es.ray = Ray{offsetRayOrigin(ps.p, ps.n, d), d, Infinity};
        es.n = ps.n;
        es.pdfPosition = ps.pdf;
        es.pdfDirection = warp::squareToCosineHemispherePdf(local);
        if (es.pdfPosition > 0.f && es.pdfDirection > 0.f) es.L = SampledSpectrum(1.f);
        return es;
    }
    float power() const override { return m_shape ? Pi * m_shape->area() : 0.f; }

private:
    const IShape* m_shape = nullptr;
};

void registerFaulty() {
    static std::once_flag once;
    std::call_once(once, [] {
        auto add = [](const char* name, std::function<Ref<IComponent>()> make) {
            Schema s("emitter", name, "test emitter (tests/test_conformance_emitter.cpp)");
            Registry::instance().add(ComponentInfo{s, [make](const Properties&) { return make(); }, {}});
        };
        add("test_half_pdf_point", [] { return std::make_shared<TestPoint>(TestPoint::Fault::HalfPdf); });
        add("test_inverse_distance_point", [] { return std::make_shared<TestPoint>(TestPoint::Fault::InverseDistance); });
        add("test_skewed_area", [] { return std::make_shared<TestSkewedArea>(); });
    });
}

} // namespace

TEST_CASE("emitters: the conformance suite fails wrong emitters by the right checks", "[emitter][conformance]") {
    registerFaulty();
    auto out = test::tempDir("conform-emitter");
    auto run = [&](const std::string& name) { return test::runQuickSuite("emitter", name, out); };
    using conform::Verdict;
    {
        conform::Session s = run("test_half_pdf_point");
        INFO(sessionTable(s));
        CHECK(test::failedChecks(s) == std::set<std::string>{"power"});
    }
    {
        conform::Session s = run("test_inverse_distance_point");
        INFO(sessionTable(s));
        CHECK(test::failedChecks(s) == std::set<std::string>{"inverse-square"});
    }
    {
        conform::Session s = run("test_skewed_area");
        INFO(sessionTable(s));
        CHECK(verdictOf(s, "test_skewed_area", "chi-square sampleDirect on square") == Verdict::Fail);
        CHECK(verdictOf(s, "test_skewed_area", "chi-square sampleDirect on sphere") == Verdict::Fail);
        // Its samples' values and densities agree with eval() and pdfDirect(): only the
        // distribution is wrong.
        CHECK(verdictOf(s, "test_skewed_area", "sample value on square") == Verdict::Pass);
        CHECK(verdictOf(s, "test_skewed_area", "power on square") == Verdict::Pass);
        for (const std::string& c : test::failedChecks(s)) CHECK(c.rfind("chi-square sampleDirect", 0) == 0);
    }
    std::filesystem::remove_all(out);
}

TEST_CASE("emitters: the conformance suite passes the shipped lights' default cases", "[emitter][conformance]") {
    for (const char* name : {"area", "point", "spot", "constant"}) {
        conform::Options o;
        o.tag = "emitter";
        o.component = name;
        o.quick = true;
        o.outDir = test::tempDir("conform-emitter-ok");
        conform::Session s(o);
        for (const conform::Job& job : s.plan())
            if (job.config.name == "default") s.runJob(job);
        s.finish();
        INFO(sessionTable(s));
        CHECK(s.count(conform::Verdict::Fail) == 0);
        CHECK(s.count(conform::Verdict::Pass) >= 4);
        std::filesystem::remove_all(o.outDir);
    }
}
