// Emitter suite, emission side: sampleEmission()'s samples, the flux they carry against
// power() (and, for lights at infinity, against their radiance), and the inverse-square
// law of point-like lights. See emitter_suite.cpp for the suite as a whole.
#include "conformance/emitter_common.hpp"
#include "conformance/histogram.hpp"
#include "effigi/spectral/cie.hpp"

#include <fmt/format.h>

namespace effigi::conform::emitter {

namespace {

/// Lights at infinity: the flux sampleEmission() carries through the scene's cross-section
/// must be π r² ∫ Y(evalEnvironment) dω, estimated here from uniform directions (light
/// tracing is unbiased only then). Two-sided z-test of the two independent estimates.
void checkEnvironmentFlux(Target& t, const Setup& s, double emitted, double emittedSe) {
    PCG32 rng = t.rng("emission flux");
    const std::uint64_t n = t.count(400000, 40000);
    MeanVar radiance;
    for (std::uint64_t i = 0; i < n; ++i) {
        SampledWavelengths l = SampledWavelengths::sampleVisible(rng.nextFloat());
        Vector3f d = sphericalDirection(2.0 * Pi * rng.nextFloat(), 2.0 * rng.nextFloat() - 1.0);
        radiance.add(double(cie::toY(s.emitter->evalEnvironment(d, l), l)));
    }
    const double r = SceneBounds.boundingRadius(), k = Pi * r * r * 4.0 * Pi;
    const double ref = k * radiance.mean, refSe = k * radiance.stderror();
    const double se = std::sqrt(emittedSe * emittedSe + refSe * refSe);
    const double gap = std::max(0.0, std::abs(emitted - ref) - 1e-3 * ref);  // 1e-3: float rounding
    const double p = !std::isfinite(emitted) ? 0.0 : se > 0.0 ? std::erfc(gap / se / std::sqrt(2.0)) : (gap > 0.0 ? 0.0 : 1.0);
    t.test("emission flux", p, fmt::format("emitted {:.5g} ± {:.2g}, radiance {:.5g} ± {:.2g}", emitted, emittedSe, ref, refSe),
           fmt::format("flux of sampleEmission() against π r² ∫ Y(L) dω from {} uniform directions; p = {:.3g}", n, p));
}

} // namespace

/// sampleEmission(): finite values, positive pdfs where L > 0, unit directions, origins
/// on the emitter; and the luminance flux it implies against power().
void checkEmission(Target& t, const Setup& s) {
    const IEmitter& e = *s.emitter;
    const std::uint32_t flags = e.flags();
    PCG32 rng = t.rng("emission" + s.at);
    const std::uint64_t n = t.count(400000, 40000);
    const Point3f light = e.sampleDirect(Point3f(0.123f, 0.456f, 0.789f), Point2f(0.5f), SampledWavelengths::constant(550.f)).p;
    const float edge[] = {0.f, 1e-7f, 0.5f, OneMinusEpsilon};
    std::uint64_t bad = 0, densities = 0, badDensity = 0;
    std::string first, firstDensity;
    MeanVar flux;
    for (std::uint64_t i = 0; i < n; ++i) {
        Point2f uPos = uniform2(rng), uDir = uniform2(rng);
        if (i < 256) {  // the corners and edges of the unit square first
            uPos = Point2f(edge[i % 4], edge[(i / 4) % 4]);
            uDir = Point2f(edge[(i / 16) % 4], edge[(i / 64) % 4]);
        }
        SampledWavelengths l = SampledWavelengths::sampleVisible(rng.nextFloat());
        EmissionSample es = e.sampleEmission(uPos, uDir, l);
        const Point3f o = es.ray.o;
        const Vector3f d = es.ray.d;
        const bool lit = positive(es.L);
        std::string why;
        if (!valid(es.L) || !std::isfinite(es.pdfPosition) || !std::isfinite(es.pdfDirection) ||
            !(es.pdfPosition >= 0.f) || !(es.pdfDirection >= 0.f))
            why = "not finite or negative";
        else if (lit && !(es.pdfPosition > 0.f && es.pdfDirection > 0.f)) why = "L > 0 with a zero pdf";
        else if (lit && !(isFinite(o) && std::abs(length(d) - 1.f) <= 1e-4f)) why = "origin not finite or direction not unit";
        else if (lit && s.host.shape) {
            const double off = s.host.sphere ? std::abs(length(Vector3d(o)) - 0.5) : std::abs(double(o.z));
            const bool inside = s.host.sphere || (std::abs(o.x) <= 0.5f + 1e-4f && std::abs(o.y) <= 0.5f + 1e-4f);
            const Vector3f normal = s.host.sphere ? normalize(Vector3f(o)) : Vector3f(0.f, 0.f, 1.f);
            if (!(off <= 1e-4) || !inside) why = "origin not on the shape";
            else if (!(dot(normal, d) > 0.f)) why = "ray leaves the back of the shape";
        } else if (lit && (flags & EmitterDeltaPosition)) {
            if (!(length(o - light) <= 1e-5f * (1.f + length(light)))) why = "origin not at the light";
        } else if (lit && (flags & EmitterInfinite)) {
            const float r = SceneBounds.boundingRadius();
            if (!(length(o - SceneBounds.center()) >= r * (1.f - 1e-4f))) why = "origin inside the scene's bounding sphere";
            else if (!(dot(d, SceneBounds.center() - o) > 0.f)) why = "ray does not head into the scene";
        }
        if (!why.empty() && bad++ == 0)
            first = fmt::format("u = ({}, {}), ({}, {}): {} (o = ({}, {}, {}), d = ({}, {}, {}), pdf {} × {}, L[0] {})", uPos.x,
                                uPos.y, uDir.x, uDir.y, why, o.x, o.y, o.z, d.x, d.y, d.z, es.pdfPosition, es.pdfDirection, es.L[0]);
        // Luminance flux: Y(L) |cos θ| / (p_A p_ω) for a surface (radiance), Y(L) / (p_A p_ω)
        // otherwise (intensity of a point, or radiance through the disk at infinity).
        double w = 0.0;
        if (why.empty() && lit) {
            double cosine = s.host.shape ? std::abs(dot(es.n, d)) : 1.0;
            w = double(cie::toY(es.L, l)) * cosine / (double(es.pdfPosition) * double(es.pdfDirection));
        }
        if (i >= 256) flux.add(w);  // the corner inputs are not uniform draws
        // pdfEmission() (bidirectional renderers' MIS) must give back the sample's densities.
        float pdfPos = 0.f, pdfDir = 0.f;
        if (why.empty() && lit && e.pdfEmission(o, es.n, d, pdfPos, pdfDir)) {
            ++densities;
            double err = std::max(relError(double(pdfPos), double(es.pdfPosition)),
                                  relError(double(pdfDir), double(es.pdfDirection)));
            if (!(err <= ValueTolerance) && badDensity++ == 0)
                firstDensity = fmt::format("u = ({}, {}), ({}, {}): pdfEmission {} × {}, sampleEmission {} × {}", uPos.x,
                                           uPos.y, uDir.x, uDir.y, pdfPos, pdfDir, es.pdfPosition, es.pdfDirection);
        }
    }
    t.expect("emission" + s.at, bad == 0, fmt::format("{} bad of {}", bad, n), first);
    if (densities > 0)
        t.expect("emission densities" + s.at, badDensity == 0, fmt::format("{} of {} disagree", badDensity, densities),
                 badDensity ? firstDensity : "pdfEmission() against sampleEmission()'s pdfs, relative tolerance");
    else
        t.info("emission densities" + s.at, "none compared",
               "no lit sample (dark), or pdfEmission() not provided (infinite lights: bdpt does not start there)");

    const double power = e.power(), est = flux.mean, se = flux.stderror();
    const std::string figure = fmt::format("power() {:.5g}, estimate {:.5g} ± {:.2g}", power, est, se);
    if (flags & EmitterInfinite) {
        t.info("power" + s.at, figure,
               "an environment's power is the flux through the scene's cross-section: it only weighs lights");
        if (!e.isDelta()) checkEnvironmentFlux(t, s, est, se);
        return;
    }
    // power() is documented as approximate (it weighs lights against each other), so the
    // test asks for agreement within PowerTolerance, one-sided in each direction: enough to
    // rank lights and to catch a density or an emission off by a factor.
    double excess = std::max(0.0, std::abs(est - power) - PowerTolerance * std::abs(power));
    double p = !std::isfinite(power) || !std::isfinite(est) ? 0.0
               : se > 0.0                                   ? std::erfc(excess / se / std::sqrt(2.0))
                                                            : (excess > 0.0 ? 0.0 : 1.0);
    t.test("power" + s.at, p, figure,
           fmt::format("{} emission samples, luminance flux ∫ Y(L) cos θ dA dω; power() off by {:+.3g} % (allowed ±{:g} %)",
                       n - 256, est > 0.0 ? 100.0 * (power / est - 1.0) : 0.0, 100.0 * PowerTolerance));
}

/// Point-like emitters: L · dist² along an emitted ray is the intensity sampleEmission reports.
void checkInverseSquare(Target& t, const Setup& s) {
    PCG32 rng = t.rng("inverse-square");
    const SampledWavelengths l = SampledWavelengths::constant(550.f);
    const float dists[] = {1e-2f, 1.f, 1e2f, 1e4f};
    double worst = 0.0;
    int rays = 0, bad = 0;
    std::string first;
    for (int i = 0; i < 64; ++i) {
        // Away from the edges of the unit square, so that no ray grazes a cone's cutoff.
        Point2f u(0.1f + 0.8f * rng.nextFloat(), 0.1f + 0.8f * rng.nextFloat());
        EmissionSample em = s.emitter->sampleEmission(uniform2(rng), u, l);
        if (!positive(em.L) || !(em.pdfDirection > 0.f)) continue;
        ++rays;
        for (float dist : dists) {
            EmitterSample es = s.emitter->sampleDirect(em.ray(dist), uniform2(rng), l);
            double err = relError(double(es.L[0]) * double(es.dist) * double(es.dist), double(em.L[0]));
            worst = std::max(worst, std::isfinite(err) ? err : 1e30);
            if (!(err <= ValueTolerance) && bad++ == 0)
                first = fmt::format("at {:g}: L·dist² = {:.6g}, intensity {:.6g}", dist,
                                    double(es.L[0]) * es.dist * es.dist, em.L[0]);
        }
    }
    t.expect("inverse-square", bad == 0, fmt::format("worst rel. error {:.2g}", worst),
             fmt::format("{} rays at distances 1e-2 … 1e4; {} disagree{}{}", rays, bad, first.empty() ? "" : "; first: ", first));
}

} // namespace effigi::conform::emitter
