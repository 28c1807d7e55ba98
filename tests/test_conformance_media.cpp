// The phase and medium conformance suites (conformance/phase_suite.cpp,
// conformance/medium_suite.cpp) fail deliberately wrong components by the right checks,
// and pass the shipped ones. Each wrong phase function is Henyey–Greenstein broken in one
// promise of IPhaseFunction:
// - test_phase_skewed: sample() draws from g = 0.6 while eval() and pdf() say g = 0.5
//   (its pdf and weight are those of pdf()/eval() at the drawn direction, so only the
//   distribution is wrong) -> "chi-square" (every wo); the defensive-mixture estimate of
//   ∫p is then biased too -> "normalisation";
// - test_phase_heavy: eval() is 1.1 p (pdf right, weight = eval/pdf) -> "normalisation";
// - test_phase_oneway: g = 0.35 + 0.25 wo.z, normalised for every wo but not reciprocal
//   -> "reciprocity";
// - test_phase_pdf: sample() reports 1.5 × the pdf of its direction -> "sample";
// - test_phase_nan: eval() is NaN at exactly wi = −wo -> "finite";
// - test_phase_negative: eval() is −1e-3 at exactly wi = wo -> "non-negative".
// Wrong media: test_medium_low_majorant (σt = 2, majorant 1: delta and ratio tracking
// then estimate exp(−d)) -> "majorant", "delta tracking", "ratio tracking";
// test_medium_albedo (σs = 1.2 σt, σa = −0.2 σt) -> "albedo".
// The statistical checks run at the suite's family-wise α = 0.01 (Šidák); the faults are
// tens of standard errors large in quick mode.
#include "app_runner.hpp"
#include "conform_session.hpp"

#include "conformance/conformance.hpp"
#include "effigi/interfaces/imedium.hpp"
#include "effigi/math/frame.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <mutex>
#include <set>

using namespace effigi;
using effigi::test::sessionTable;

namespace {

enum class PhaseFault { Skewed, Heavy, OneWay, Pdf, NaN, Negative };

/// Henyey–Greenstein by the textbook formulas (|g| ≤ 0.6 here), broken as told.
class FaultyPhase final : public Implements<IPhaseFunction> {
public:
    explicit FaultyPhase(PhaseFault f) : m_fault(f) {}
    SampledSpectrum eval(const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&) const override {
        if (m_fault == PhaseFault::NaN && wi == -wo) return SampledSpectrum(std::numeric_limits<float>::quiet_NaN());
        if (m_fault == PhaseFault::Negative && wi == wo) return SampledSpectrum(-1e-3f);
        return SampledSpectrum(float(hg(wo, wi, gFor(wo)) * (m_fault == PhaseFault::Heavy ? 1.1 : 1.0)));
    }
    std::optional<PhaseSample> sample(const Vector3f& wo, const Point2f& u, const SampledWavelengths& l) const override {
        const double g = m_fault == PhaseFault::Skewed ? 0.6 : gFor(wo), xi = u.x;
        const double s = (1.0 - g * g) / (1.0 - g + 2.0 * g * xi);
        const double mu = std::clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
        const double r = std::sqrt(std::max(0.0, 1.0 - mu * mu)), phi = 2.0 * Pi * u.y;
        const Frame f(normalize(-wo));
        const Vector3f wi = normalize(f.toWorld(Vector3f(float(r * std::cos(phi)), float(r * std::sin(phi)), float(mu))));
        const float pdf = this->pdf(wo, wi, l);
        return PhaseSample{wi, m_fault == PhaseFault::Pdf ? 1.5f * pdf : pdf, eval(wo, wi, l) / pdf};
    }
    float pdf(const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&) const override {
        return float(hg(wo, wi, gFor(wo)));
    }

private:
    double gFor(const Vector3f& wo) const { return m_fault == PhaseFault::OneWay ? 0.35 + 0.25 * double(wo.z) : 0.5; }
    static double hg(const Vector3f& wo, const Vector3f& wi, double g) {
        const double c = dot(Vector3d(wo), Vector3d(wi));
        return (1.0 - g * g) / (4.0 * Pi * std::pow(1.0 + g * g + 2.0 * g * c, 1.5));
    }
    PhaseFault m_fault;
};

enum class MediumFault { LowMajorant, Albedo };

class FaultyMedium final : public Implements<IMedium> {
public:
    explicit FaultyMedium(MediumFault f) : m_fault(f) {
        Properties p("phase", "isotropic");
        m_phase = query<IPhaseFunction>(Registry::instance().create("phase", "isotropic", p));
    }
    const IPhaseFunction& phase() const override { return *m_phase; }
    bool isHomogeneous() const override { return true; }
    MediumProperties at(const Point3f&, const SampledWavelengths&) const override {
        MediumProperties mp;
        mp.sigmaS = SampledSpectrum(m_fault == MediumFault::Albedo ? 2.4f : 1.5f);
        mp.sigmaA = SampledSpectrum(m_fault == MediumFault::Albedo ? -0.4f : 0.5f);
        return mp;
    }
    MajorantSegment majorant(const Ray&, float tMin, float tMax, const SampledWavelengths&) const override {
        return {tMin, tMax, SampledSpectrum(m_fault == MediumFault::LowMajorant ? 1.f : 2.f)};
    }

private:
    MediumFault m_fault;
    Ref<IPhaseFunction> m_phase;
};

void registerFaulty() {
    static std::once_flag once;
    std::call_once(once, [] {
        for (auto [name, fault] : {std::pair{"test_phase_skewed", PhaseFault::Skewed},
                                   std::pair{"test_phase_heavy", PhaseFault::Heavy},
                                   std::pair{"test_phase_oneway", PhaseFault::OneWay},
                                   std::pair{"test_phase_pdf", PhaseFault::Pdf}, std::pair{"test_phase_nan", PhaseFault::NaN},
                                   std::pair{"test_phase_negative", PhaseFault::Negative}}) {
            Schema s("phase", name, "wrong phase function (tests/test_conformance_media.cpp)");
            Registry::instance().add(ComponentInfo{
                s, [fault = fault](const Properties&) -> Ref<IComponent> { return std::make_shared<FaultyPhase>(fault); }, {}});
        }
        for (auto [name, fault] : {std::pair{"test_medium_low_majorant", MediumFault::LowMajorant},
                                   std::pair{"test_medium_albedo", MediumFault::Albedo}}) {
            Schema s("medium", name, "wrong medium (tests/test_conformance_media.cpp)");
            Registry::instance().add(ComponentInfo{
                s, [fault = fault](const Properties&) -> Ref<IComponent> { return std::make_shared<FaultyMedium>(fault); }, {}});
        }
    });
}

/// The failed checks, every "chi-square wo = ..." row counted as "chi-square".
std::set<std::string> failed(const std::string& tag, const std::string& name, const std::filesystem::path& out) {
    conform::Session s = test::runQuickSuite(tag, name, out);
    INFO(sessionTable(s));
    CHECK(s.count(conform::Verdict::Pass) >= 4);
    std::set<std::string> checks;
    for (const std::string& c : test::failedChecks(s)) checks.insert(c.starts_with("chi-square") ? "chi-square" : c);
    return checks;
}

} // namespace

TEST_CASE("phase conformance: the suite fails wrong phase functions by the right checks", "[media][conformance]") {
    registerFaulty();
    auto out = test::tempDir("conform-phase");
    using Set = std::set<std::string>;
    CHECK(failed("phase", "test_phase_skewed", out) == Set{"chi-square", "normalisation"});
    CHECK(failed("phase", "test_phase_heavy", out) == Set{"normalisation"});
    CHECK(failed("phase", "test_phase_oneway", out) == Set{"reciprocity"});
    CHECK(failed("phase", "test_phase_pdf", out) == Set{"sample"});
    CHECK(failed("phase", "test_phase_nan", out) == Set{"finite"});
    CHECK(failed("phase", "test_phase_negative", out) == Set{"non-negative"});
    std::filesystem::remove_all(out);
}

TEST_CASE("medium conformance: the suite fails wrong media by the right checks", "[media][conformance]") {
    registerFaulty();
    auto out = test::tempDir("conform-medium");
    using Set = std::set<std::string>;
    CHECK(failed("medium", "test_medium_low_majorant", out) == Set{"majorant", "delta tracking", "ratio tracking"});
    CHECK(failed("medium", "test_medium_albedo", out) == Set{"albedo"});
    std::filesystem::remove_all(out);
}

TEST_CASE("phase and medium conformance: the shipped components pass", "[media][conformance]") {
    auto out = test::tempDir("conform-media-ok");
    for (auto [tag, name] : {std::pair{"phase", "isotropic"}, std::pair{"phase", "hg"}, std::pair{"phase", "rayleigh"},
                             std::pair{"medium", "homogeneous"}}) {
        conform::Session s = test::runQuickSuite(tag, name, out);
        INFO(sessionTable(s));
        CHECK(s.count(conform::Verdict::Fail) == 0);
        CHECK(s.count(conform::Verdict::Pass) >= 8);
    }
    std::filesystem::remove_all(out);
}
