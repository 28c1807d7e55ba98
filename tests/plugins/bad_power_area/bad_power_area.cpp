// emitter "bad_power_area" — DELIBERATELY WRONG test plugin: a diffuse area light whose
// power() integrates its radiance over the hemisphere without the cosine, 2π·A·L,
// where a Lambertian emitter's flux is ∫∫ L cos θ dω dA = π·A·L.
//
// Emission itself is right (eval, direct samples by the shape's solid-angle sampling,
// emission samples by area and cosine-weighted direction, all consistent), so only the
// power check can see the bug: power() is twice the flux that sampleEmission() carries,
// far outside the 25 % it allows, on both host shapes ("power on square", "power on
// sphere"; tests/plugins/run_plugin_tests.cmake).
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/spectrum.hpp"

namespace {
using namespace effigi;

class BadPowerArea final : public Implements<IEmitter> {
public:
    static Schema schema() {
        Schema s("emitter", "bad_power_area", "Test plugin: a diffuse area light whose power() is 2π·A·L, not π·A·L.");
        s.spectrum("radiance", 1.f, SpectrumKind::Illuminant, "Emitted radiance L, front side only")
            .atLeast(0.0)
            .withUnit("W m^-2 sr^-1");
        s.addConformance({"default", {}});
        return s;
    }

    explicit BadPowerArea(const Properties& p) : m_radiance(p.getSpectrum("radiance", SpectrumKind::Illuminant)) {}

    std::uint32_t flags() const override { return EmitterSurface; }
    void attach(const IShape* shape) override { m_shape = shape; }

    SampledSpectrum eval(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        return dot(si.n, si.wo) > 0.f ? m_radiance.sample(lambda) : SampledSpectrum(0.f);
    }

    EmitterSample sampleDirect(const Point3f& ref, const Point2f& u, const SampledWavelengths& lambda) const override {
        EmitterSample es;
        if (!m_shape) return es;
        DirectionSample ds = m_shape->sampleDirection(ref, u);
        es.p = ds.p;
        es.n = ds.n;
        es.wi = ds.wi;
        es.dist = ds.dist;
        if (!(ds.pdf > 0.f) || !std::isfinite(ds.pdf) || !(dot(ds.n, -ds.wi) > 0.f)) return es;  // back side: dark
        es.pdf = ds.pdf;
        es.L = m_radiance.sample(lambda);
        return es;
    }

    float pdfDirect(const Point3f& ref, const SurfaceInteraction& si) const override {
        return m_shape && dot(si.n, si.wo) > 0.f ? m_shape->pdfDirection(ref, si) : 0.f;
    }

    EmissionSample sampleEmission(const Point2f& uPos, const Point2f& uDir, const SampledWavelengths& lambda) const override {
        EmissionSample es;
        if (!m_shape) return es;
        PositionSample ps = m_shape->samplePosition(uPos);
        Vector3f local = warp::squareToCosineHemisphere(uDir);
        Vector3f d = Frame(ps.n).toWorld(local);
        es.ray = Ray{offsetRayOrigin(ps.p, ps.n, d), d, Infinity};
        es.n = ps.n;
        es.pdfPosition = ps.pdf;
        es.pdfDirection = warp::squareToCosineHemispherePdf(local);
        if (es.pdfPosition > 0.f && es.pdfDirection > 0.f) es.L = m_radiance.sample(lambda);
        return es;
    }

    // The bug: ∫ L dω over the hemisphere is 2π L; the flux needs ∫ L cos θ dω = π L.
    float power() const override { return m_shape ? 2.f * Pi * m_shape->area() * cie::luminance(m_radiance) : 0.f; }

private:
    Spectrum m_radiance;
    const IShape* m_shape = nullptr;
};

} // namespace

EFFIGI_EXPORT_COMPONENT(BadPowerArea)
