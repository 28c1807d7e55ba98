// emitter "bad_falloff_point" — DELIBERATELY WRONG test plugin: an isotropic point light
// whose direct-lighting samples fall off as I/d instead of I/d² (the distance is divided
// once where the law asks for its square).
//
// Everything else is right: a delta sample with pdf 1 and a unit direction, emission
// samples leaving the light uniformly over the sphere with intensity I, power() = 4π I.
// Values stay finite at any distance, so effigi-conform must single out the
// inverse-square check: along an emitted ray L·d² is I·d, which differs from I by a
// factor 100 already at d = 1e-2 (tests/plugins/run_plugin_tests.cmake).
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/math/warp_functions.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/spectrum.hpp"

#include <cmath>

namespace {
using namespace effigi;

class BadFalloffPoint final : public Implements<IEmitter> {
public:
    static Schema schema() {
        Schema s("emitter", "bad_falloff_point", "Test plugin: a point light whose radiance falls off as 1/d, not 1/d².");
        s.point("position", Point3f(0.f), "Where the light is");
        s.spectrum("intensity", 1.f, SpectrumKind::Illuminant, "Radiant intensity I").atLeast(0.0).withUnit("W sr^-1");
        s.addConformance({"default", {}});
        s.addConformance({"offset", {{"position", PointValue{Point3f(3.f, -2.f, 1.f)}}}});
        return s;
    }

    explicit BadFalloffPoint(const Properties& p)
        : m_position(p.getPoint("position")), m_intensity(p.getSpectrum("intensity", SpectrumKind::Illuminant)) {}

    std::uint32_t flags() const override { return EmitterDeltaPosition; }

    EmitterSample sampleDirect(const Point3f& ref, const Point2f&, const SampledWavelengths& lambda) const override {
        EmitterSample es;
        es.p = m_position;
        Vector3f d = m_position - ref;
        float dist = length(d);
        if (!(dist > 0.f) || !std::isfinite(dist)) return es;  // at the light: no sample
        es.dist = dist;
        es.wi = d / dist;
        es.n = -es.wi;
        es.pdf = 1.f;
        es.delta = true;
        es.L = m_intensity.sample(lambda) / dist;  // the bug: I / d² is right
        return es;
    }

    EmissionSample sampleEmission(const Point2f&, const Point2f& uDir, const SampledWavelengths& lambda) const override {
        EmissionSample es;
        Vector3f d = warp::squareToUniformSphere(uDir);
        es.ray = Ray{m_position, d, Infinity};
        es.n = Normal3f(d);
        es.pdfPosition = 1.f;
        es.pdfDirection = warp::squareToUniformSpherePdf(d);
        es.L = m_intensity.sample(lambda);
        return es;
    }

    float power() const override { return 4.f * Pi * cie::luminance(m_intensity); }

private:
    Point3f m_position;
    Spectrum m_intensity;
};

} // namespace

EFFIGI_EXPORT_COMPONENT(BadFalloffPoint)
