// Medium suite, transmittance: the estimators of include/effigi/render/transmittance.hpp
// on the medium under test.
//  - delta tracking, ratio tracking: each estimator's mean over n walks against the
//    exact transmittance T = exp(−∫σt ds) (the optical depth by midpoint quadrature of σt
//    on each majorant piece of the ray, exact for a homogeneous medium) over six
//    distances whose largest optical depth (distance times the largest σt met in the
//    ray's first 10 units) is 1e-6 (tiny), 0.05, 0.5, 2, 8 and 1e4 (huge), at four
//    wavelengths spanning 360–830 nm, each with its own σt. The ray's direction has
//    length 2, so a walk that mistakes parameter for distance is caught. Both estimates
//    lie in [0, 1], so under the null hypothesis their variance is at most T(1 − T)
//    (exactly that for delta tracking's 0/1 estimate): a two-sided z-test with that
//    variance where nT(1 − T) ≥ 25, and Bernstein's inequality, valid for any n, where
//    the normal approximation is not (tiny and huge depths). Bonferroni over depths and
//    wavelengths gives one row per estimator, judged at the run's Šidák level
//    (family-wise α = 0.01); with the bound the test is conservative for ratio tracking,
//    whose variance is smaller;
//  - estimators agree: delta against ratio tracking, a two-sample z-test with the sample
//    variances, where both are in the normal regime (nT(1 − T) ≥ 25);
//  - estimates: every single estimate finite and in [0, 1].
// Walks draw from Target::rng, seeded by the run's seed and the check's name.
#include "conformance/histogram.hpp"
#include "conformance/media_common.hpp"
#include "effigi/render/transmittance.hpp"

#include <array>
#include <cmath>

namespace effigi::conform::media {

namespace {

constexpr double Depths[] = {1e-6, 0.05, 0.5, 2.0, 8.0, 1e4};
using Values = std::array<double, NSpectrumSamples>;

/// exp(−τ) per wavelength over [0, tMax] of the ray, τ by the midpoint rule on each of the
/// pieces the medium's majorants cut the ray into, skipping those whose majorant is 0
/// (σt = 0 there: the majorant check holds the medium to it). Exact for a homogeneous
/// medium (one piece); a bounded heterogeneous medium is resolved however short its
/// stretch of a long ray, and a majorant grid's cells each get 1024 points.
Values exactTransmittance(const IMedium& m, const Ray& ray, float tMax, const SampledWavelengths& l) {
    constexpr int Points = 1024, MaxPieces = 4096;
    const double speed = double(length(ray.d));
    Values tau{};
    float t0 = 0.f;
    for (int piece = 0; piece < MaxPieces && t0 < tMax; ++piece) {
        const MajorantSegment seg = m.majorant(ray, t0, tMax, l);
        const float t1 = std::min(seg.tMax, tMax);
        if (!(t1 > t0)) break;
        if (seg.sigmaMaj.maxValue() > 0.f) {
            const double width = double(t1) - double(t0), step = width * speed / Points;
            for (int j = 0; j < Points; ++j) {
                const SampledSpectrum st = m.at(ray(float(double(t0) + (j + 0.5) / Points * width)), l).sigmaT();
                for (int k = 0; k < NSpectrumSamples; ++k) tau[std::size_t(k)] += double(st[k]) * step;
            }
        }
        t0 = t1;
    }
    Values T;
    for (int k = 0; k < NSpectrumSamples; ++k) T[std::size_t(k)] = std::exp(-tau[std::size_t(k)]);
    return T;
}

/// Two-sided p-value of the mean of n estimates in [0, 1] whose expectation is T under
/// the null hypothesis (their variance is then at most T(1 − T)).
double boundedMeanPValue(double mean, double T, double n) {
    if (!std::isfinite(mean)) return 0.0;
    const double v = T * (1.0 - T), dev = std::abs(mean - T);
    if (n * v >= 25.0) return std::erfc(dev / std::sqrt(2.0 * v / n));
    if (dev == 0.0) return 1.0;
    // Bernstein: P(|mean − T| ≥ ε) ≤ 2 exp(−n ε² / (2σ² + 2ε/3)) for |X − T| ≤ 1.
    return std::min(1.0, 2.0 * std::exp(-n * dev * dev / (2.0 * v + 2.0 * dev / 3.0)));
}

/// The smallest p-value of a family and where it was.
struct Worst {
    std::vector<double> p;
    double smallest = 2.0;
    std::string where;
    void add(double pv, const std::string& what) {
        p.push_back(pv);
        if (pv < smallest) {
            smallest = pv;
            where = what;
        }
    }
};

} // namespace

void checkTransmittance(Target& t, const IMedium& m) {
    const std::uint64_t n = t.count(100000, 20000);
    const Ray ray{Point3f(0.3f, -0.2f, 0.1f), 2.f * normalize(Vector3f(1.f, 2.f, 3.f)), Infinity};
    const float speed = length(ray.d);
    const SampledWavelengths l = SampledWavelengths::fromNodes({360.f, 517.f, 673.f, 830.f}, {1.f, 1.f, 1.f, 1.f});
    // The depths are those of the largest σt met in the first 10 units of distance (all
    // of it for a homogeneous medium; a heterogeneous one has its own profile).
    float sigmaMax = 0.f;
    for (int j = 0; j <= 256; ++j)
        sigmaMax = std::max(sigmaMax, m.at(ray(10.f * float(j) / 256.f / speed), l).sigmaT().maxValue());
    if (!(sigmaMax > 0.f) || !std::isfinite(sigmaMax)) sigmaMax = 1.f;  // vacuum: T = 1 at any distance
    Worst delta, ratio, agree;
    Tally estimates;
    for (double depth : Depths) {
        const float tMax = float(depth / double(sigmaMax) / double(speed));
        const Values T = exactTransmittance(m, ray, tMax, l);
        MeanVar dAcc[NSpectrumSamples], rAcc[NSpectrumSamples];
        PCG32 dRng = t.rng(fmt::format("delta tracking {}", depth)), rRng = t.rng(fmt::format("ratio tracking {}", depth));
        auto uD = [&] { return dRng.nextFloat(); };
        auto uR = [&] { return rRng.nextFloat(); };
        for (std::uint64_t i = 0; i < n; ++i) {
            const SampledSpectrum d = deltaTrackingTransmittance(m, ray, tMax, l, uD);
            const SampledSpectrum r = ratioTrackingTransmittance(m, ray, tMax, l, uR);
            for (int k = 0; k < NSpectrumSamples; ++k) {
                dAcc[k].add(double(d[k]));
                rAcc[k].add(double(r[k]));
                const bool ok = d[k] >= 0.f && d[k] <= 1.f && r[k] >= 0.f && r[k] <= 1.f;
                if (!ok || i == 0)
                    estimates.note(ok, fmt::format("optical depth {:g} at {} nm: delta {}, ratio {}", depth, l[k], d[k], r[k]));
            }
        }
        for (int k = 0; k < NSpectrumSamples; ++k) {
            const double exact = T[std::size_t(k)], dn = double(n);
            const std::string at = fmt::format("σt d = {:.3g} at {} nm", -std::log(std::max(exact, 1e-300)), l[k]);
            delta.add(boundedMeanPValue(dAcc[k].mean, exact, dn),
                      fmt::format("{}: T̂ = {:.6g}, exp(−σt d) = {:.6g}", at, dAcc[k].mean, exact));
            ratio.add(boundedMeanPValue(rAcc[k].mean, exact, dn),
                      fmt::format("{}: T̂ = {:.6g}, exp(−σt d) = {:.6g}", at, rAcc[k].mean, exact));
            const double se = std::sqrt(dAcc[k].variance() / dn + rAcc[k].variance() / dn);
            if (dn * exact * (1.0 - exact) >= 25.0 && se > 0.0)
                agree.add(std::erfc(std::abs(dAcc[k].mean - rAcc[k].mean) / se / std::sqrt(2.0)),
                          fmt::format("{}: delta {:.6g}, ratio {:.6g} (± {:.2g})", at, dAcc[k].mean, rAcc[k].mean, se));
        }
    }
    const std::string walks = fmt::format("{} walks at each of {} optical depths × 4 wavelengths; smallest p at ", n,
                                          std::size(Depths));
    for (auto [name, w] : {std::pair{"delta tracking", &delta}, std::pair{"ratio tracking", &ratio}}) {
        const double pv = combinePValues(w->p);
        t.test(name, pv, fmt::format("p = {:.3g}", pv), walks + w->where);
    }
    if (agree.p.empty())
        t.skip("estimators agree", "no depth with nT(1 − T) ≥ 25 at any wavelength (T is 0 or 1 throughout)");
    else {
        const double pv = combinePValues(agree.p);
        t.test("estimators agree", pv, fmt::format("p = {:.3g}", pv),
               fmt::format("{} comparisons; smallest p at {}", agree.p.size(), agree.where));
    }
    t.expect("estimates", estimates.bad == 0, fmt::format("{} bad", estimates.bad),
             estimates.detail("every delta- and ratio-tracking estimate finite and in [0, 1]"));
}

} // namespace effigi::conform::media
