// The renderer conformance suite (conformance/renderer_suite.cpp) fails wrong renderers by
// the right checks and passes honest ones. Two test renderers, each in configurations that
// break one promise:
// - test_render_path wraps `path` sample by sample (ISampleRenderer, renderSampled):
//   "honest" passes everything; "scaled" multiplies every sample by 1.05 -> the scenes
//   fail (t ≈ 8 to 12 at this seed); "short" drops the last bounce (renders max_depth − 1 while declaring
//   max_depth 3) -> the enclosures fail, the furnace sphere and the sky plane (one bounce
//   is all their light) pass; "overconfident" reports a quarter of its variance -> the
//   "error bar" checks fail, the values pass.
// - test_render_radiosity wraps `radiosity` with Jacobi cut short at 3 sweeps: "honest"
//   reports the solver's (large) error bound and passes; "lying" claims a bound of 0 for
//   the same image and fails "within bound".
// The shipped renderers pass the suite (tested by the ctest effigi-conform-quick).
#include "conform_session.hpp"
#include "conformance/conformance.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/render/radiosity_solution.hpp"
#include "effigi/render/tile_renderer.hpp"
#include "temp_files.hpp"

#include <catch2/catch.hpp>

#include <mutex>

using namespace effigi;
using effigi::test::sessionTable;

namespace {

class TestPath final : public Implements<IRenderer, ISampleRenderer> {
public:
    explicit TestPath(const Properties& p)
        : m_scale(float(p.getFloat("scale"))), m_varianceScale(float(p.getFloat("variance_scale"))) {
        std::int64_t depth = p.getInt("max_depth");
        if (p.getBool("drop_last") && depth > 1) --depth;
        Properties q("renderer", "path");
        q.set("max_depth", depth);
        m_inner = query<ISampleRenderer>(Registry::instance().create("renderer", "path", q));
        m_integrator = defaultIntegrator();
    }
    RenderStats render(const Scene& scene, const RenderControl& control) override {
        return renderSampled(scene, control, *m_integrator, *this, m_variance);
    }
    bool varianceEstimate(std::vector<float>& v) const override {
        if (!m_variance.get(v)) return false;
        for (float& x : v) x *= m_varianceScale;
        return true;
    }
    SampledSpectrum sampleRadiance(const Scene& scene, const Ray& ray, SampledWavelengths& lambda, ISampler& sampler,
                                   float* channels) const override {
        return m_inner->sampleRadiance(scene, ray, lambda, sampler, channels) * m_scale;
    }

private:
    float m_scale, m_varianceScale;
    Ref<ISampleRenderer> m_inner;
    Ref<IIntegrator> m_integrator;
    PixelVariance m_variance;
};

class TestRadiosity final : public Implements<IRenderer, IRadiosityReport> {
public:
    explicit TestRadiosity(const Properties& p) : m_lie(p.getBool("lie")) {
        Properties s("solver", "jacobi");
        s.set("max_iterations", std::int64_t(3));
        Properties q("renderer", "radiosity");
        q.set("solver", ComponentValue{"solver", Registry::instance().create("solver", "jacobi", s)});
        if (Ref<IComponent> mesh = p.get<IComponent>("mesh")) q.set("mesh", ComponentValue{"mesh", mesh});
        m_inner = Registry::instance().create("renderer", "radiosity", q);
    }
    RenderStats render(const Scene& scene, const RenderControl& control) override {
        return query<IRenderer>(m_inner)->render(scene, control);
    }
    const SolverReport& solverReport() const override {
        m_report = query<IRadiosityReport>(m_inner)->solverReport();
        if (m_lie) m_report.errorBound = 0.0;
        return m_report;
    }

private:
    bool m_lie;
    Ref<IComponent> m_inner;
    mutable SolverReport m_report;
};

void registerFaulty() {
    static std::once_flag once;
    std::call_once(once, [] {
        Schema s("renderer", "test_render_path", "wrong path tracers (tests/test_conformance_renderer.cpp)");
        s.integer("max_depth", -1, "longest path").atLeast(-1);
        s.real("scale", 1.0, "factor on every sample");
        s.boolean("drop_last", false, "render max_depth − 1");
        s.real("variance_scale", 1.0, "factor on the reported variance");
        s.addConformance({"honest", {}});
        s.addConformance({"scaled", {{"scale", 1.05}}});
        s.addConformance({"short", {{"max_depth", std::int64_t(3)}, {"drop_last", true}}});
        s.addConformance({"overconfident", {{"variance_scale", 0.25}}});
        Registry::instance().add(ComponentInfo{
            s, [](const Properties& p) -> Ref<IComponent> { return std::make_shared<TestPath>(p); }, {}});

        Schema r("renderer", "test_render_radiosity",
                 "radiosity with a lying error bound (tests/test_conformance_renderer.cpp)");
        r.boolean("lie", false, "report an error bound of 0");
        r.child("mesh", "mesh", "elements");
        r.addConformance({"honest", {}});
        r.addConformance({"lying", {{"lie", true}}});
        Registry::instance().add(ComponentInfo{
            r, [](const Properties& p) -> Ref<IComponent> { return std::make_shared<TestRadiosity>(p); }, {}});
    });
}

/// The verdict of `check` on configuration `config` (there must be exactly one row).
conform::Verdict verdict(const conform::Session& s, const std::string& config, const std::string& check) {
    std::vector<const conform::Row*> rows;
    for (const conform::Row& r : s.rows())
        if (r.config == config && r.check == check) rows.push_back(&r);
    INFO(config << " / " << check);
    REQUIRE(rows.size() == 1);
    return rows[0]->verdict;
}

} // namespace

TEST_CASE("renderer conformance: the suite fails wrong renderers by the right checks", "[renderer][conformance]") {
    registerFaulty();
    test::ScratchDir out("conform-renderer");
    using conform::Verdict;
    {
        // One session over the four configurations: its Šidák level (family-wise 0.01)
        // covers all their tests; the faults are far beyond it.
        conform::Session s = test::runQuickSuite("renderer", "test_render_path", out.dir());
        INFO(sessionTable(s));
        for (const conform::Row& r : s.rows())
            if (r.config == "honest") CHECK(r.verdict != Verdict::Fail);
        // (The white furnace box, noisier, fails too at this seed, with less margin: t ≈ 5.)
        for (const char* scene : {"furnace sphere", "sky plane", "enclosure ρ = 0.5"})
            CHECK(verdict(s, "scaled", scene) == Verdict::Fail);
        CHECK(verdict(s, "short", "enclosure ρ = 0.5") == Verdict::Fail);
        CHECK(verdict(s, "short", "enclosure ρ = 0.99") == Verdict::Fail);
        CHECK(verdict(s, "short", "furnace sphere") == Verdict::Pass);
        CHECK(verdict(s, "short", "sky plane") == Verdict::Pass);
        CHECK(verdict(s, "short", "white furnace box") == Verdict::Skip);  // finite depth: no closed form
        CHECK(verdict(s, "overconfident", "error bar sky plane") == Verdict::Fail);
        CHECK(verdict(s, "overconfident", "error bar enclosure ρ = 0.5") == Verdict::Fail);
        CHECK(verdict(s, "overconfident", "sky plane") == Verdict::Pass);
        CHECK(verdict(s, "overconfident", "enclosure ρ = 0.5") == Verdict::Pass);
    }
    {
        conform::Session s = test::runQuickSuite("renderer", "test_render_radiosity", out.dir());
        INFO(sessionTable(s));
        CHECK(verdict(s, "honest", "within bound enclosure ρ = 0.5") == Verdict::Pass);
        CHECK(verdict(s, "honest", "within bound enclosure ρ = 0.99") == Verdict::Pass);
        CHECK(verdict(s, "lying", "within bound enclosure ρ = 0.5") == Verdict::Fail);
        CHECK(verdict(s, "lying", "within bound enclosure ρ = 0.99") == Verdict::Fail);
        CHECK(verdict(s, "lying", "furnace sphere") == Verdict::Skip);  // environment light
    }
}
