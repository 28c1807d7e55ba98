// The texture conformance suite (conformance/texture_suite.cpp) fails deliberately wrong
// textures by the right checks, and passes shipped ones. Each wrong texture breaks one
// promise of ITexture:
// - test_tex_bright: a reflectance declaring maxValue() = 1 that reads 1.2 on the strip
//   u > 0.9 -> "bounded";
// - test_tex_nan_edge: NaN on the edges u = 1 or v = 1 and outside [0, 1]² -> "finite"
//   and "non-finite uv" (±∞ is outside too);
// - test_tex_mean: mean() 20 % above the average it reads -> "mean";
// - test_tex_gradient: evalFloatGradient() twice the true gradient -> "gradient".
// "mean" is a z-test at family-wise α = 0.01 (Šidák); the 20 % fault is 100 standard
// errors of the 50 000-lookup average away. The other checks are deterministic.
#include "app_runner.hpp"
#include "conform_session.hpp"
#include "conformance/conformance.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/itexture.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <mutex>
#include <set>

using namespace effigi;
using effigi::test::sessionTable;

namespace {

enum class Fault { Bright, NanEdge, Mean, Gradient };

/// f(u, v) = 0.3 + 0.4 u v with u, v clamped to [0, 1] (NaN read as 0): smooth inside,
/// mean 0.4 over [0, 1]², within [0.3, 0.7] everywhere; or the faulty variant.
class FaultyTexture final : public Implements<ITexture> {
public:
    explicit FaultyTexture(Fault f) : m_fault(f) {}
    SampledSpectrum eval(const SurfaceInteraction& si, const SampledWavelengths&) const override {
        return SampledSpectrum(evalFloat(si));
    }
    static float clamp01(float x) { return x > 0.f ? (x < 1.f ? x : 1.f) : 0.f; }
    float evalFloat(const SurfaceInteraction& si) const override {
        const float u = clamp01(si.uv.x), v = clamp01(si.uv.y);
        if (m_fault == Fault::Bright) return si.uv.x > 0.9f ? 1.2f : 0.5f;
        const float ru = si.uv.x, rv = si.uv.y;
        if (m_fault == Fault::NanEdge && (ru >= 1.f || rv >= 1.f || ru < 0.f || rv < 0.f))
            return std::numeric_limits<float>::quiet_NaN();
        return 0.3f + 0.4f * u * v;
    }
    Vector2f evalFloatGradient(const SurfaceInteraction& si) const override {
        if (m_fault == Fault::Bright) return Vector2f(0.f);
        Vector2f g(0.4f * clamp01(si.uv.y), 0.4f * clamp01(si.uv.x));
        return m_fault == Fault::Gradient ? 2.f * g : g;
    }
    float maxValue() const override { return m_fault == Fault::Bright ? 1.f : 0.7f; }
    float mean() const override {
        if (m_fault == Fault::Bright) return 0.9f * 0.5f + 0.1f * 1.2f;
        return m_fault == Fault::Mean ? 1.2f * 0.4f : 0.4f;
    }

private:
    Fault m_fault;
};

void registerFaulty() {
    static std::once_flag once;
    std::call_once(once, [] {
        for (auto [name, fault] : {std::pair{"test_tex_bright", Fault::Bright}, std::pair{"test_tex_nan_edge", Fault::NanEdge},
                                   std::pair{"test_tex_mean", Fault::Mean}, std::pair{"test_tex_gradient", Fault::Gradient}}) {
            Schema s("texture", name, "wrong texture (tests/test_conformance_texture.cpp)");
            Registry::instance().add(ComponentInfo{
                s, [fault = fault](const Properties&) -> Ref<IComponent> { return std::make_shared<FaultyTexture>(fault); }, {}});
        }
    });
}

} // namespace

TEST_CASE("texture conformance: the suite fails wrong textures by the right checks", "[texture][conformance]") {
    registerFaulty();
    auto out = test::tempDir("conform-texture");
    auto failed = [&](const std::string& name) {
        conform::Session s = test::runQuickSuite("texture", name, out);
        INFO(sessionTable(s));
        CHECK(s.count(conform::Verdict::Pass) >= 4);
        return test::failedChecks(s);
    };
    using Set = std::set<std::string>;
    CHECK(failed("test_tex_bright") == Set{"bounded"});
    CHECK(failed("test_tex_nan_edge") == Set{"finite", "non-finite uv"});
    CHECK(failed("test_tex_mean") == Set{"mean"});
    CHECK(failed("test_tex_gradient") == Set{"gradient"});
    std::filesystem::remove_all(out);
}

TEST_CASE("texture conformance: the shipped textures pass", "[texture][conformance]") {
    // bitmap's configurations and the suite's probe mesh name tests/data relative to the
    // source tree.
    std::filesystem::current_path(EFFIGI_SOURCE_DIR);
    auto out = test::tempDir("conform-texture-ok");
    for (const char* name : {"bitmap", "checkerboard", "mesh_attribute", "rawconstant"}) {
        conform::Options o;
        o.tag = "texture";
        o.component = name;
        o.quick = true;
        o.outDir = out;
        conform::Session s(o);
        s.run();
        INFO(sessionTable(s));
        CHECK(s.count(conform::Verdict::Fail) == 0);
        CHECK(s.count(conform::Verdict::Pass) >= 6);
    }
    std::filesystem::remove_all(out);
}
