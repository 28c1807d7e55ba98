#pragma once
// Components for tests/test_conformance.cpp, registered directly with the process-wide
// registry under test_* names: deliberately wrong ones (each breaks one promise by a
// large factor) and a correct stratified sampler.
#include "conformance_samplers.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/iintegrator.hpp"
#include "effigi/interfaces/iwarp.hpp"
#include "effigi/math/warp_functions.hpp"

#include <cmath>
#include <mutex>

namespace effigi::conformtest {

/// Lambertian reflection with cosine sampling; the knobs break it in one way each.
class TestLambert : public Implements<IBSDF> {
public:
    struct Faults {
        float albedo = 0.5f;
        bool uniformPdf = false;      // sample()/pdf() claim 1/2π while sampling cosθ/π
        float sampleFScale = 1.f;     // sample() returns f × this
        bool nonReciprocal = false;   // f depends on wo
        bool nanAtGrazing = false;    // 0/0 below cosθo = 1e-5
    };
    explicit TestLambert(Faults f) : m(f) {}
    std::uint32_t flags() const override { return BSDFReflection | BSDFDiffuse; }
    SampledSpectrum f(const SurfaceInteraction&, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&,
                      TransportMode) const override {
        if (!(wo.z > 0.f && wi.z > 0.f)) return SampledSpectrum(0.f);
        float v = m.albedo * InvPi;
        if (m.nonReciprocal) v *= 0.2f + 0.8f * wo.z;
        if (m.nanAtGrazing) v *= std::sqrt(wo.z - 1e-5f) / std::sqrt(wo.z - 1e-5f);
        return SampledSpectrum(v);
    }
    std::optional<BSDFSample> sample(const SurfaceInteraction& si, const Vector3f& wo, float, const Point2f& u,
                                     SampledWavelengths& l, TransportMode mode) const override {
        if (!(wo.z > 0.f)) return std::nullopt;
        BSDFSample bs;
        bs.wi = warp::squareToCosineHemisphere(u);
        bs.pdf = pdf(si, wo, bs.wi, l, mode);
        if (!(bs.pdf > 0.f)) return std::nullopt;
        bs.f = f(si, wo, bs.wi, l, mode) * m.sampleFScale;
        bs.flags = flags();
        return bs;
    }
    float pdf(const SurfaceInteraction&, const Vector3f& wo, const Vector3f& wi, const SampledWavelengths&,
              TransportMode) const override {
        if (!(wo.z > 0.f && wi.z > 0.f)) return 0.f;
        return m.uniformPdf ? Inv2Pi : warp::squareToCosineHemispherePdf(wi);
    }

private:
    Faults m;
};

/// Claims a delta reflection but sends light back where it came from.
class TestBadMirror final : public Implements<IBSDF> {
public:
    std::uint32_t flags() const override { return BSDFReflection | BSDFSpecular; }
    SampledSpectrum f(const SurfaceInteraction&, const Vector3f&, const Vector3f&, const SampledWavelengths&,
                      TransportMode) const override {
        return SampledSpectrum(0.f);
    }
    std::optional<BSDFSample> sample(const SurfaceInteraction&, const Vector3f& wo, float, const Point2f&,
                                     SampledWavelengths&, TransportMode) const override {
        if (!(wo.z > 0.f)) return std::nullopt;
        BSDFSample bs;
        bs.wi = wo;  // should be (−x, −y, z)
        bs.pdf = 1.f;
        bs.f = SampledSpectrum(0.9f / wo.z);
        bs.flags = flags();
        return bs;
    }
    float pdf(const SurfaceInteraction&, const Vector3f&, const Vector3f&, const SampledWavelengths&,
              TransportMode) const override {
        return 0.f;
    }
};

/// Uniform points on the unit disk; optionally a pdf twice too large or a swapped inverse.
class TestDisk final : public Implements<IWarp> {
public:
    TestDisk(float pdfScale, bool swapInverse) : m_scale(pdfScale), m_swap(swapInverse) {}
    WarpDomain domain() const override { return {WarpDomain::Kind::Plane, Point2f(-1.f), Point2f(1.f), "unit disk"}; }
    Vector3f sample(const Point2f& u) const override {
        Point2f p = warp::squareToUniformDiskConcentric(u);
        return {p.x, p.y, 0.f};
    }
    float pdf(const Vector3f& p) const override { return m_scale * warp::squareToUniformDiskPdf({p.x, p.y}); }
    bool hasInverse() const override { return true; }
    Point2f inverse(const Vector3f& p) const override {
        Point2f u = warp::uniformDiskToSquareConcentric({p.x, p.y});
        return m_swap ? Point2f(u.y, u.x) : u;
    }

private:
    float m_scale;
    bool m_swap;
};

/// The mean integrator's estimate with a fault: variance / 4 (error bar half as wide) or
/// the mean scaled by 1.02 (biased).
class TestIntegrator final : public Implements<IIntegrator> {
public:
    TestIntegrator(double varianceScale, double meanScale) : m_var(varianceScale), m_mean(meanScale) {
        Properties p("integrator", "mean");
        m_inner = query<IIntegrator>(Registry::instance().create("integrator", "mean", p));
    }
    using IIntegrator::integrate;
    Estimate integrate(IFunction& f, ISampler& s, std::uint64_t first, std::uint64_t count) const override {
        Estimate e = m_inner->integrate(f, s, first, count);
        for (int c = 0; c < e.channels; ++c) {
            e.variance[std::size_t(c)] *= m_var;
            e.mean[std::size_t(c)] *= m_mean;
        }
        return e;
    }

private:
    Ref<IIntegrator> m_inner;
    double m_var, m_mean;
};

/// f(x) = x on [0,1), declaring ∫ = 0.55 instead of 0.5.
class TestWrongIntegral final : public Implements<IFunction> {
public:
    int dimension() const override { return 1; }
    void eval(ISampler& u, std::span<double> out) override { out[0] = u.get1D(); }
    std::optional<std::vector<double>> integral() const override { return std::vector<double>{0.55}; }
};

template <typename Make> void addComponent(const std::string& tag, const std::string& name, Make make) {
    Schema s(tag, name, "test component (tests/conformance_helpers.hpp)");
    if (tag == "sampler") {
        s.integer("sample_count", 16, "Samples per pixel").atLeast(1);
        s.integer("seed", 0, "Seed");
    }
    Registry::instance().add(ComponentInfo{s, [make](const Properties& p) -> Ref<IComponent> { return make(p); }, {}});
}

inline void registerTestComponents() {
    static std::once_flag once;
    std::call_once(once, [] {
        using F = TestLambert::Faults;
        auto lambert = [](F f) { return [f](const Properties&) { return std::make_shared<TestLambert>(f); }; };
        addComponent("bsdf", "test_energy_gain", lambert(F{1.3f, false, 1.f, false, false}));
        addComponent("bsdf", "test_wrong_pdf", lambert(F{0.5f, true, 1.f, false, false}));
        addComponent("bsdf", "test_wrong_weight", lambert(F{0.5f, false, 1.5f, false, false}));
        addComponent("bsdf", "test_nonreciprocal", lambert(F{0.8f, false, 1.f, true, false}));
        addComponent("bsdf", "test_grazing_nan", lambert(F{0.5f, false, 1.f, false, true}));
        addComponent("bsdf", "test_bad_mirror", [](const Properties&) { return std::make_shared<TestBadMirror>(); });
        addComponent("warp", "test_double_pdf", [](const Properties&) { return std::make_shared<TestDisk>(2.f, false); });
        addComponent("warp", "test_bad_inverse", [](const Properties&) { return std::make_shared<TestDisk>(1.f, true); });
        addComponent("integrator", "test_overconfident",
                     [](const Properties&) { return std::make_shared<TestIntegrator>(0.25, 1.0); });
        addComponent("integrator", "test_biased",
                     [](const Properties&) { return std::make_shared<TestIntegrator>(1.0, 1.02); });
        addComponent("function", "test_wrong_integral",
                     [](const Properties&) { return std::make_shared<TestWrongIntegral>(); });
        addComponent("sampler", "test_jittered", [](const Properties& p) {
            return std::make_shared<TestJittered>(int(p.getInt("sample_count")), std::uint64_t(p.getInt("seed")));
        });
        addComponent("sampler", "test_claims_too_much", [](const Properties& p) {
            return std::make_shared<TestRandom>(int(p.getInt("sample_count")), TestRandom::ClaimsTooMuch);
        });
        addComponent("sampler", "test_correlated", [](const Properties& p) {
            return std::make_shared<TestRandom>(int(p.getInt("sample_count")), TestRandom::Correlated);
        });
        addComponent("sampler", "test_returns_one", [](const Properties& p) {
            return std::make_shared<TestRandom>(int(p.getInt("sample_count")), TestRandom::ReturnsOne);
        });
    });
}

} // namespace effigi::conformtest
