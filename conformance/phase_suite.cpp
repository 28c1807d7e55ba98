// Phase suite: an IPhaseFunction, in each of its configurations, against the promises of
// include/effigi/interfaces/iphasefunction.hpp.
//  - finite, non-negative: eval() and pdf() at random pairs of directions, at wi = ±wo
//    exactly and within 1e-4 rad of them (where peaked lobes cancel), and sample() at
//    random u and at u on the edges of the square, at random and extreme (360, 830 nm)
//    wavelengths;
//  - reciprocity: p(wo, wi) = p(wi, wo) to 1e-4 relative;
//  - sample: every draw gives a unit wi with pdf > 0 equal to pdf(wo, wi) and a weight
//    equal to eval/pdf, each to 1e-4 relative;
//  - normalisation: ∫ p dωi = 1 at every wavelength, by Monte Carlo with a defensive
//    mixture (Hesterberg 1995): half the directions uniform on the sphere, half from
//    sample(), weighted by 1/(½·1/4π + ½·pdf), which bounds the weights by 2 for a pdf
//    proportional to p, however peaked. A two-sided z-test per wavelength (Bonferroni
//    over the four), judged at the run's Šidák level; a floor of 1e-5 on the standard
//    error stands for float round-off of eval (an isotropic p gives weights of exactly 1);
//  - chi-square, pdf integral: phase_distribution.cpp.
#include "conformance/histogram.hpp"
#include "conformance/media_common.hpp"

#include <cmath>

namespace effigi::conform::media {

std::vector<Vector3f> conditioningDirections(Target& t) {
    PCG32 rng = t.rng("conditioning directions");
    const Vector3f random = uniformDirection(rng);
    if (t.quick()) return {Vector3f(0.f, 0.f, 1.f), random};
    return {Vector3f(0.f, 0.f, 1.f), Vector3f(0.f, 0.f, -1.f), Vector3f(1.f, 0.f, 0.f), random};
}

namespace {

struct Pair {
    Vector3f wo, wi;
};

/// Random pairs, and pairs at and near the forward (wi = −wo) and backward (wi = wo)
/// poles and at right angles.
std::vector<Pair> probePairs(Target& t, PCG32& rng) {
    std::vector<Pair> pairs;
    const std::uint64_t n = t.count(4000, 1000);
    for (std::uint64_t i = 0; i < n; ++i) pairs.push_back({uniformDirection(rng), uniformDirection(rng)});
    for (int i = 0; i < 32; ++i) {
        const Vector3f wo = i == 0 ? Vector3f(0.f, 0.f, 1.f) : i == 1 ? Vector3f(0.f, 0.f, -1.f) : uniformDirection(rng);
        const Frame f(wo);
        for (const Vector3f& wi : {wo, -wo, f.s, normalize(wo + 1e-4f * f.s), normalize(-wo + 1e-4f * f.t)})
            pairs.push_back({wo, wi});
    }
    return pairs;
}

/// No slot below zero (a NaN is the "finite" check's).
bool notNegative(const SampledSpectrum& s) {
    for (int i = 0; i < NSpectrumSamples; ++i)
        if (s[i] < 0.f) return false;
    return true;
}

void checkValues(Target& t, const IPhaseFunction& p) {
    PCG32 rng = t.rng("values");
    Tally finite, negative, reciprocal;
    std::size_t i = 0;
    for (const Pair& pr : probePairs(t, rng)) {
        const SampledWavelengths l = probeWavelengths(rng, i++);
        const SampledSpectrum f = p.eval(pr.wo, pr.wi, l), back = p.eval(pr.wi, pr.wo, l);
        const float pdf = p.pdf(pr.wo, pr.wi, l);
        const std::string at = fmt::format("wo = {}, wi = {}", vec(pr.wo), vec(pr.wi));
        finite.note(f.isFinite() && std::isfinite(pdf), fmt::format("{}: eval {}, pdf {}", at, spec(f), pdf));
        negative.note(notNegative(f) && !(pdf < 0.f), fmt::format("{}: eval {}, pdf {}", at, spec(f), pdf));
        if (!f.isFinite() || !back.isFinite()) continue;  // the "finite" check's
        double worst = 0.0;
        for (int k = 0; k < NSpectrumSamples; ++k) worst = std::max(worst, relativeError(f[k], back[k], 1e-12));
        reciprocal.note(worst <= 1e-4, fmt::format("{}: p(wo, wi) = {}, p(wi, wo) = {}", at, spec(f), spec(back)));
        reciprocal.worst = std::max(reciprocal.worst, worst);
    }
    // sample() at u on the edges of the square.
    const float edges[] = {0.f, 1e-7f, 0.5f, 1.f - 1e-7f, OneMinusEpsilon};
    for (const Vector3f& wo : conditioningDirections(t))
        for (float a : edges)
            for (float b : edges) {
                const SampledWavelengths l = probeWavelengths(rng, i++);
                auto s = p.sample(wo, Point2f(a, b), l);
                bool ok = !s || (isFinite(s->wi) && std::isfinite(s->pdf) && s->weight.isFinite());
                finite.note(ok, fmt::format("sample(wo = {}, u = ({}, {})) gives wi = {}, pdf {}, weight {}", vec(wo),
                                            a, b, s ? vec(s->wi) : "-", s ? s->pdf : 0.f, s ? spec(s->weight) : "-"));
            }
    t.expect("finite", finite.bad == 0, finite.figure(),
             finite.detail("eval, pdf and sample finite at random, forward, backward and edge inputs"));
    t.expect("non-negative", negative.bad == 0, negative.figure(), negative.detail("eval ≥ 0 and pdf ≥ 0"));
    t.expect("reciprocity", reciprocal.bad == 0, fmt::format("max rel. error {:.2g}", reciprocal.worst),
             reciprocal.detail(fmt::format("p(wo, wi) = p(wi, wo) to 1e-4 at {} pairs", reciprocal.checked)));
}

void checkSamples(Target& t, const IPhaseFunction& p) {
    PCG32 rng = t.rng("sample");
    const std::uint64_t n = t.count(100000, 20000);
    Tally tally;
    for (std::uint64_t i = 0; i < n; ++i) {
        const Vector3f wo = uniformDirection(rng);
        const SampledWavelengths l = probeWavelengths(rng, std::size_t(i));
        const Point2f u(rng.nextFloat(), rng.nextFloat());
        auto s = p.sample(wo, u, l);
        const std::string at = fmt::format("wo = {}, u = ({}, {})", vec(wo), u.x, u.y);
        if (!s) {
            tally.note(false, at + ": no sample (a phase function scatters every time)");
            continue;
        }
        const float pdf = p.pdf(wo, s->wi, l);
        const SampledSpectrum f = p.eval(wo, s->wi, l);
        double worst = std::max(relativeError(s->pdf, pdf), std::abs(double(length(s->wi)) - 1.0));
        for (int k = 0; k < NSpectrumSamples; ++k)
            worst = std::max(worst, relativeError(double(s->weight[k]), double(f[k]) / double(s->pdf)));
        const bool ok = s->pdf > 0.f && std::isfinite(s->pdf) && worst <= 1e-4;
        tally.worst = std::max(tally.worst, std::isnan(worst) ? 1e9 : worst);
        tally.note(ok, fmt::format("{}: wi = {} (|wi| = {}), pdf {} but pdf(wo, wi) = {}, weight {} but eval/pdf = {}",
                                   at, vec(s->wi), length(s->wi), s->pdf, pdf, spec(s->weight), spec(f / s->pdf)));
    }
    t.expect("sample", tally.bad == 0, fmt::format("max rel. error {:.2g}", tally.worst),
             tally.detail(fmt::format("{} draws: unit wi, pdf = pdf(wo, wi) > 0, weight = eval/pdf (1e-4)", n)));
}

void checkNormalisation(Target& t, const IPhaseFunction& p) {
    PCG32 rng = t.rng("normalisation");
    const std::uint64_t n = t.count(1000000, 100000);
    const SampledWavelengths l = SampledWavelengths::sampleUniform(rng.nextFloat());
    MeanVar acc[NSpectrumSamples];
    for (std::uint64_t i = 0; i < n; ++i) {
        const Vector3f wo = uniformDirection(rng);
        const bool uniform = rng.nextFloat() < 0.5f;
        const Point2f u(rng.nextFloat(), rng.nextFloat());
        Vector3f wi = uniformDirection(rng);
        if (!uniform) {
            auto s = p.sample(wo, u, l);
            if (!s) {  // the mixture drew from sample(), which gave nothing: weight 0
                for (auto& a : acc) a.add(0.0);
                continue;
            }
            wi = s->wi;
        }
        const double q = 0.5 * double(Inv4Pi) + 0.5 * double(p.pdf(wo, wi, l));
        const SampledSpectrum f = p.eval(wo, wi, l);
        for (int k = 0; k < NSpectrumSamples; ++k) acc[k].add(q > 0.0 ? double(f[k]) / q : 0.0);
    }
    std::vector<double> pValues;
    double worstZ = 0.0;
    std::string means;
    for (int k = 0; k < NSpectrumSamples; ++k) {
        const double se = std::sqrt(acc[k].stderror() * acc[k].stderror() + 1e-10);
        const double z = (acc[k].mean - 1.0) / se;
        pValues.push_back(std::isfinite(z) ? 2.0 * (1.0 - stats::normalCdf(std::abs(z))) : 0.0);
        worstZ = std::max(worstZ, std::isfinite(z) ? std::abs(z) : 1e9);
        means += fmt::format("{}{:.1f} nm: {:.5f} ± {:.1g}", k ? ", " : "", l[k], acc[k].mean, se);
    }
    const double pv = combinePValues(pValues);
    t.test("normalisation", pv, fmt::format("p = {:.3g}", pv),
           fmt::format("∫ p dωi by {} mixture draws (½ uniform, ½ sample()), max |z| = {:.2f}: {}", n, worstZ, means));
}

void runPhaseSuite(Target& t) {
    Ref<IPhaseFunction> p = t.as<IPhaseFunction>();
    if (!p) {
        t.expect("interface", false, "-", "component does not implement IPhaseFunction");
        return;
    }
    checkValues(t, *p);
    checkSamples(t, *p);
    checkNormalisation(t, *p);
    checkPhaseDistribution(t, *p);
}

} // namespace

} // namespace effigi::conform::media

EFFIGI_CONFORMANCE_SUITE("phase",
                         "finite, non-negative, reciprocal values; sample() against pdf() and eval(); ∫p = 1; chi-square",
                         effigi::conform::media::runPhaseSuite);
