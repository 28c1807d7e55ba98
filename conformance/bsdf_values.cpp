// BSDF suite, value checks: f, pdf and sample() never negative or NaN at ordinary and
// extreme arguments, and sample()'s f and pdf equal what f() and pdf() say.
#include "conformance/bsdf_common.hpp"

#include <limits>

namespace effigi::conform::bsdf {

namespace {

constexpr TransportMode Modes[2] = {TransportMode::Radiance, TransportMode::Importance};

/// Counts bad values and remembers the first one.
struct BadValues {
    std::uint64_t checked = 0, bad = 0;
    std::string first;
    double minValue = std::numeric_limits<double>::infinity();

    void spectrum(const SampledSpectrum& s, const std::string& what) {
        ++checked;
        for (int i = 0; i < NSpectrumSamples; ++i) minValue = std::min(minValue, double(s[i]));
        if (!usable(s)) note(what + " = " + spec(s));
    }
    void scalar(float v, const std::string& what) {
        ++checked;
        minValue = std::min(minValue, double(v));
        if (!(v >= 0.f) || !std::isfinite(v)) note(fmt::format("{} = {}", what, v));
    }
    void note(const std::string& what) {
        if (bad++ == 0) first = what;
    }
    std::string figure() const { return fmt::format("{} bad of {} values", bad, checked); }
};

/// f, pdf and sample() at one (wo, wi) pair; `label` names the arguments for the report.
void probe(const IBSDF& b, const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
           const SampledWavelengths& lambda, TransportMode mode, float uc, const Point2f& u, BadValues& bad,
           bool checkSample) {
    auto where = [&] {
        return fmt::format("wo = {}, wi = {}, {}, {}", vec(wo), vec(wi), lambdas(lambda), modeName(mode));
    };
    SampledSpectrum f = b.f(si, wo, wi, lambda, mode);
    if (!usable(f)) bad.spectrum(f, "f at " + where());
    else bad.spectrum(f, "");
    float pdf = b.pdf(si, wo, wi, lambda, mode);
    if (!(pdf >= 0.f) || !std::isfinite(pdf)) bad.scalar(pdf, "pdf at " + where());
    else bad.scalar(pdf, "");
    if (!checkSample) return;
    SampledWavelengths l = lambda;
    std::optional<BSDFSample> bs = b.sample(si, wo, uc, u, l, mode);
    if (!bs) return;
    std::string at = fmt::format("sample(wo = {}, uc = {}, u = ({}, {}), {})", vec(wo), uc, u.x, u.y, modeName(mode));
    ++bad.checked;
    if (!isFinite(bs->wi) || std::abs(length(bs->wi) - 1.f) > 1e-3f) bad.note(at + ": wi = " + vec(bs->wi) + " is not a unit vector");
    bad.scalar(bs->pdf, at + ": pdf");
    bad.spectrum(bs->f, at + ": f");
    if (!(bs->eta > 0.f) || !std::isfinite(bs->eta)) bad.note(fmt::format("{}: eta = {}", at, bs->eta));
    if (bs->pdf > 0.f) bad.spectrum(bs->f * (std::abs(bs->wi.z) / bs->pdf), at + ": weight f·|cos|/pdf");
}

} // namespace

void checkNonNegative(Target& t, const IBSDF& b) {
    PCG32 rng = t.rng("non-negative");
    const SurfaceInteraction si = probePoint();
    const std::uint64_t n = t.count(20000, 4000);
    BadValues bad;
    for (std::uint64_t i = 0; i < n; ++i) {
        Vector3f wo = uniformDirection(rng), wi = uniformDirection(rng);
        SampledWavelengths lambda = SampledWavelengths::sampleVisible(rng.nextFloat());
        float uc = rng.nextFloat();
        Point2f u(rng.nextFloat(), rng.nextFloat());
        probe(b, si, wo, wi, lambda, Modes[i & 1], uc, u, bad, true);
    }
    t.expect("non-negative", bad.bad == 0, fmt::format("min value {:.3g}", bad.minValue),
             bad.bad ? bad.figure() + "; first: " + bad.first : bad.figure() + " (f, pdf, sample at random arguments)");
}

void checkStability(Target& t, const IBSDF& b) {
    const SurfaceInteraction si = probePoint();
    // Normal incidence, grazing (cos θ = 1e-6) from both sides, exactly tangent, and
    // ordinary angles, at two azimuths.
    const float cosines[] = {1.f, 0.5f, 1e-6f, 0.f, -1e-6f, -0.5f, -1.f};
    const float phis[] = {0.f, 2.2f};
    std::vector<Vector3f> dirs;
    for (float c : cosines)
        for (float p : phis) dirs.push_back(direction(c, p));
    // Both ends of the wavelength range, alone and as hero sets.
    const SampledWavelengths lambdaSets[] = {SampledWavelengths::constant(LambdaMin),
                                             SampledWavelengths::constant(LambdaMax),
                                             SampledWavelengths::sampleVisible(0.f),
                                             SampledWavelengths::sampleVisible(OneMinusEpsilon)};
    const float edges[] = {0.f, 0.5f, OneMinusEpsilon};
    BadValues bad;
    for (const SampledWavelengths& lambda : lambdaSets) {
        for (TransportMode mode : Modes) {
            for (const Vector3f& wo : dirs) {
                for (const Vector3f& wi : dirs) probe(b, si, wo, wi, lambda, mode, 0.5f, Point2f(0.5f), bad, false);
                for (float uc : edges)
                    for (float u0 : edges)
                        for (float u1 : edges) probe(b, si, wo, wo, lambda, mode, uc, Point2f(u0, u1), bad, true);
            }
        }
        bad.spectrum(b.albedo(si, lambda), "albedo() at " + lambdas(lambda));
    }
    t.expect("stable", bad.bad == 0, bad.figure(),
             bad.bad ? "first: " + bad.first
                     : "cos θ in {±1, ±0.5, ±1e-6, 0}, λ = 360 and 830 nm, sample inputs at 0 and 1−ε");
}

void checkSampleWeight(Target& t, const IBSDF& b) {
    PCG32 rng = t.rng("sample weight");
    const SurfaceInteraction si = probePoint();
    const std::uint64_t n = t.count(20000, 4000);
    // f and pdf are float computations along different code paths: 1e-3 relative allows
    // a few dozen roundings, and is far below any modelling mistake (a missing cos θ or
    // a factor of π or 2).
    constexpr double Tolerance = 1e-3;
    double worstF = 0.0, worstPdf = 0.0;
    std::string worstCase;
    std::uint64_t compared = 0;
    for (std::uint64_t i = 0; i < n; ++i) {
        Vector3f wo = uniformDirection(rng);
        SampledWavelengths lambda = SampledWavelengths::sampleVisible(rng.nextFloat());
        TransportMode mode = Modes[i & 1];
        float uc = rng.nextFloat();
        Point2f u(rng.nextFloat(), rng.nextFloat());
        SampledWavelengths l = lambda;
        std::optional<BSDFSample> bs = b.sample(si, wo, uc, u, l, mode);
        if (!bs || !(bs->pdf > 0.f) || bs->isSpecular()) continue;
        ++compared;
        SampledSpectrum f = b.f(si, wo, bs->wi, l, mode);
        float pdf = b.pdf(si, wo, bs->wi, l, mode);
        double ef = 0.0;
        for (int k = 0; k < NSpectrumSamples; ++k) ef = std::max(ef, relativeError(bs->f[k], f[k]));
        double ep = relativeError(bs->pdf, pdf);
        if (std::max(ef, ep) > std::max(worstF, worstPdf))
            worstCase = fmt::format("wo = {}, wi = {}, {}: sample f = {}, pdf = {}; f() = {}, pdf() = {}", vec(wo),
                                    vec(bs->wi), modeName(mode), spec(bs->f), bs->pdf, spec(f), pdf);
        worstF = std::max(worstF, ef);
        worstPdf = std::max(worstPdf, ep);
    }
    if (compared == 0) {
        // Delta lobes only: their weights are the 'delta' check's business.
        if (!b.isPureSpecular()) t.skip("sample weight", "sample() never returned a non-delta sample");
        return;
    }
    bool ok = worstF <= Tolerance && worstPdf <= Tolerance;
    t.expect("sample weight", ok, fmt::format("worst rel. error {:.2g}", std::max(worstF, worstPdf)),
             fmt::format("{} samples; f {:.2g}, pdf {:.2g} (tolerance {}){}", compared, worstF, worstPdf, Tolerance,
                         ok ? "" : "; worst: " + worstCase));
}

} // namespace effigi::conform::bsdf
