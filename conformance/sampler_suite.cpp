// Sampler suite: values in [0,1), reproducible per (pixel, index), uniform in each
// dimension, independent between dimensions and consecutive samples, the stratification
// the sampler claims (ISampler::claims()), and the convergence rate it claims: the slope
// of log RMS error against log N for a smooth and a discontinuous 2D integrand.
#include "conformance/histogram.hpp"
#include "effigi/interfaces/isampler.hpp"

#include <fmt/format.h>

namespace effigi::conform {

namespace {

constexpr int Dims = 8;  // 1D dimensions drawn per sample after getPixel2D()

/// One sample's values: getPixel2D() then Dims × get1D().
struct Draw {
    float v[Dims + 2];
};

Ref<ISampler> withCount(Target& t, std::int64_t spp) {
    if (!t.hasParameter("sample_count")) return t.as<ISampler>();
    return query<ISampler>(t.create({{"sample_count", spp}}));
}

void checkValues(Target& t, ISampler& s) {
    const int spp = std::max(1, std::min(s.samplesPerPixel(), 64));
    const int pixels = int(t.count(1 << 16, 1 << 14) / std::uint64_t(spp));
    const int bins1 = t.quick() ? 32 : 64, bins2 = 16;
    std::vector<Draw> draws;
    draws.reserve(std::size_t(pixels) * std::size_t(spp));
    std::uint64_t outOfRange = 0;
    std::string firstBad;
    for (int p = 0; p < pixels; ++p) {
        // Pixels on both sides of zero: scratch domains use negative coordinates.
        s.startPixel(Point2i(p % 256 - 128, p / 256 - 3));
        for (int i = 0; i < spp; ++i) {
            s.startSample(std::uint64_t(i));
            Draw d;
            Point2f px = s.getPixel2D();
            d.v[0] = px.x;
            d.v[1] = px.y;
            for (int k = 0; k < Dims; ++k) d.v[k + 2] = s.get1D();
            for (float v : d.v)
                if (!(v >= 0.f && v < 1.f) && outOfRange++ == 0)
                    firstBad = fmt::format("value {} at pixel {}, sample {}", v, p, i);
            draws.push_back(d);
        }
    }
    t.expect("range", outOfRange == 0, fmt::format("{} of {} outside [0,1)", outOfRange, draws.size() * (Dims + 2)),
             outOfRange ? "first: " + firstBad : "getPixel2D() and get1D() over " + std::to_string(pixels) + " pixels");

    // Uniformity of each dimension: chi-square of a 1D histogram.
    const double n = double(draws.size());
    std::vector<double> p1;
    for (int k = 0; k < Dims + 2; ++k) {
        std::vector<double> obs(std::size_t(bins1), 0.0), exp(std::size_t(bins1), n / bins1);
        for (const Draw& d : draws) obs[std::size_t(std::clamp(int(d.v[k] * bins1), 0, bins1 - 1))] += 1.0;
        p1.push_back(stats::chiSquareTest(obs, exp).pValue);
    }
    double pu = combinePValues(p1);
    t.test("uniform", pu, fmt::format("p = {:.3g}", pu),
           fmt::format("{} points, {} bins in each of {} dimensions (pixel x, y and {} get1D); worst p = {:.3g}",
                       draws.size(), bins1, Dims + 2, Dims, *std::min_element(p1.begin(), p1.end())));

    // Independence: pairs of dimensions (and the same dimension of consecutive samples)
    // must be uniform on the unit square.
    std::vector<std::pair<int, int>> pairs = {{0, 1}, {2, 3}, {3, 4}, {2, 9}, {0, 2}, {1, 5}};
    std::vector<double> p2;
    auto test2D = [&](auto&& point, std::size_t count) {
        std::vector<double> obs(std::size_t(bins2 * bins2), 0.0), exp(obs.size(), double(count) / (bins2 * bins2));
        for (std::size_t i = 0; i < count; ++i) {
            auto [x, y] = point(i);
            int cx = std::clamp(int(x * bins2), 0, bins2 - 1), cy = std::clamp(int(y * bins2), 0, bins2 - 1);
            obs[std::size_t(cy * bins2 + cx)] += 1.0;
        }
        p2.push_back(stats::chiSquareTest(obs, exp).pValue);
    };
    for (auto [a, b] : pairs)
        test2D([&](std::size_t i) { return std::pair{draws[i].v[a], draws[i].v[b]}; }, draws.size());
    std::string consecutive;
    // Stratified and quasi-random samplers place a pixel's samples jointly on purpose;
    // only a sampler claiming none must make consecutive samples independent.
    if (spp >= 2 && s.claims().stratification == StratifyNone) {
        // Dimension 2 of sample i against sample i + 1 of the same pixel.
        std::vector<std::pair<float, float>> cp;
        for (std::size_t i = 0; i + 1 < draws.size(); ++i)
            if ((i + 1) % std::size_t(spp) != 0) cp.emplace_back(draws[i].v[2], draws[i + 1].v[2]);
        test2D([&](std::size_t i) { return cp[i]; }, cp.size());
        consecutive = " and consecutive samples";
    }
    double pi = combinePValues(p2);
    t.test("independent", pi, fmt::format("p = {:.3g}", pi),
           fmt::format("{}×{} histograms of {} dimension pairs{}", bins2, bins2, pairs.size(), consecutive));
}

void checkReproducible(Target& t, ISampler& s) {
    // The same (pixel, index) must give the same values whatever was drawn before.
    auto draw = [&](Point2i px, std::uint64_t i) {
        s.startPixel(px);
        s.startSample(i);
        std::vector<float> v;
        for (int k = 0; k < 6; ++k) v.push_back(s.get1D());
        Point2f q = s.get2D();
        v.push_back(q.x);
        v.push_back(q.y);
        return v;
    };
    const int spp = std::max(1, s.samplesPerPixel());
    bool same = true;
    for (int k = 0; k < 8; ++k) {
        Point2i px(k * 37 - 100, k * k);
        std::uint64_t idx = std::uint64_t(k * 5 % spp);
        auto a = draw(px, idx);
        draw(Point2i(k + 1, -k), std::uint64_t((k + 3) % spp));
        draw(px, std::uint64_t((idx + 1) % spp));
        same = same && a == draw(px, idx);
    }
    t.expect("reproducible", same, same ? "identical" : "differs",
             "values of a (pixel, index) after drawing others in between");
}

void checkStratification(Target& t, ISampler& base) {
    const std::uint32_t claims = base.claims().stratification;
    if (claims == StratifyNone) {
        t.info("stratification", "none claimed", "only uniformity and independence apply");
        return;
    }
    const int spp = 16;  // a square and a power of two: every claim applies
    Ref<ISampler> s = withCount(t, spp);
    if (s->samplesPerPixel() != spp) {
        t.skip("stratification", fmt::format("cannot set sample_count = {} (has {})", spp, s->samplesPerPixel()));
        return;
    }
    auto onePerCell = [](const std::vector<int>& cells, int n) {
        std::vector<int> seen(std::size_t(n), 0);
        for (int c : cells)
            if (c >= 0 && c < n) ++seen[std::size_t(c)];
        return std::all_of(seen.begin(), seen.end(), [](int k) { return k == 1; });
    };
    for (auto [flag, name] : {std::pair{StratifyLatinHypercube, "latin hypercube"},
                              std::pair{StratifyJittered2D, "jittered 2D"},
                              std::pair{StratifyElementary2D, "elementary intervals"}}) {
        if (!(claims & flag)) continue;
        int pixels = 8, failures = 0, checks = 0;
        for (int p = 0; p < pixels; ++p) {
            s->startPixel(Point2i(p, 2 * p + 1));
            std::vector<std::vector<Point2f>> pts(4);
            for (int i = 0; i < spp; ++i) {
                s->startSample(std::uint64_t(i));
                for (int d = 0; d < 4; ++d) {
                    if (flag == StratifyLatinHypercube) pts[std::size_t(d)].push_back(Point2f(s->get1D(), 0.f));
                    else pts[std::size_t(d)].push_back(s->get2D());
                }
            }
            const int dims = flag == StratifyElementary2D ? 1 : 4;
            for (int d = 0; d < dims; ++d) {
                const auto& q = pts[std::size_t(d)];
                if (flag == StratifyLatinHypercube) {
                    std::vector<int> c;
                    for (auto v : q) c.push_back(int(v.x * spp));
                    failures += !onePerCell(c, spp), ++checks;
                } else if (flag == StratifyJittered2D) {
                    std::vector<int> c;
                    for (auto v : q) c.push_back(int(v.y * 4) * 4 + int(v.x * 4));
                    failures += !onePerCell(c, spp), ++checks;
                } else {
                    for (int a = 0; a <= 4; ++a) {  // intervals 2^-a × 2^-(4-a)
                        std::vector<int> c;
                        for (auto v : q) c.push_back(int(v.y * float(1 << (4 - a))) * (1 << a) + int(v.x * float(1 << a)));
                        failures += !onePerCell(c, spp), ++checks;
                    }
                }
            }
        }
        t.expect(std::string("stratification: ") + name, failures == 0, fmt::format("{} of {} patterns violate it", failures, checks),
                 fmt::format("spp = {}, {} pixels", spp, pixels));
    }
}

/// Least-squares slope of y against x.
double slope(const std::vector<double>& x, const std::vector<double>& y) {
    double mx = 0, my = 0;
    for (std::size_t i = 0; i < x.size(); ++i) mx += x[i], my += y[i];
    mx /= double(x.size());
    my /= double(x.size());
    double sxy = 0, sxx = 0;
    for (std::size_t i = 0; i < x.size(); ++i) sxy += (x[i] - mx) * (y[i] - my), sxx += (x[i] - mx) * (x[i] - mx);
    return sxy / sxx;
}

void checkConvergence(Target& t, ISampler& base) {
    const SamplerClaims claims = base.claims();
    const int kMax = t.quick() ? 9 : 12, replicates = int(t.count(64, 32));
    // Smooth: ∫∫ e^x (1 + cos(2πy)/2) = e − 1. Discontinuous: the quarter disk x² + y² < 0.6,
    // area 0.15π.
    auto smooth = [](Point2f u) { return std::exp(double(u.x)) * (1.0 + 0.5 * std::cos(2.0 * std::numbers::pi * u.y)); };
    auto disk = [](Point2f u) { return double(u.x) * u.x + double(u.y) * u.y < 0.6 ? 1.0 : 0.0; };
    const double exact[2] = {std::numbers::e - 1.0, 0.15 * std::numbers::pi};
    std::vector<double> logN, logErr[2];
    for (int k = 2; k <= kMax; ++k) {
        std::int64_t n = std::int64_t(1) << k;
        Ref<ISampler> s = withCount(t, n);
        // Samplers may round sample_count (to a square, a power of two): the claim is about
        // their own N-sample pattern, not a truncated one.
        if (t.hasParameter("sample_count")) n = std::max(1, s->samplesPerPixel());
        double sq[2] = {0.0, 0.0};
        for (int r = 0; r < replicates; ++r) {
            s->startPixel(Point2i(r, 11));
            double sum[2] = {0.0, 0.0};
            for (std::int64_t i = 0; i < n; ++i) {
                s->startSample(std::uint64_t(i));
                Point2f u = s->get2D();
                sum[0] += smooth(u);
                sum[1] += disk(u);
            }
            for (int f = 0; f < 2; ++f) {
                double e = sum[f] / double(n) - exact[f];
                sq[f] += e * e;
            }
        }
        logN.push_back(std::log(double(n)));
        for (int f = 0; f < 2; ++f) logErr[f].push_back(0.5 * std::log(std::max(sq[f] / replicates, 1e-300)));
    }
    // With 64 replicates the log RMS error of plain MC scatters by ~0.09 per point, and the
    // fitted slope over N = 4..4096 by ~0.012 (~0.03 with --quick): 0.1 is 8 (3.5) sigma.
    constexpr double Tolerance = 0.1;
    const double claimed[2] = {claims.smoothRate, claims.discontinuousRate};
    const char* names[2] = {"convergence smooth", "convergence discontinuous"};
    for (int f = 0; f < 2; ++f) {
        double m = slope(logN, logErr[f]);
        t.expect(names[f], std::abs(m - claimed[f]) <= Tolerance,
                 fmt::format("slope {:.3f} (claim {:.2f} ± {})", m, claimed[f], Tolerance),
                 fmt::format("RMS error over {} pixels at N = 4..{}: {:.3g} .. {:.3g}", replicates, 1 << kMax,
                             std::exp(logErr[f].front()), std::exp(logErr[f].back())));
    }
}

void runSamplerSuite(Target& t) {
    Ref<ISampler> s = t.as<ISampler>();
    if (!s) {
        t.expect("interface", false, "-", "component does not implement ISampler");
        return;
    }
    checkValues(t, *s);
    checkReproducible(t, *s);
    checkStratification(t, *s);
    checkConvergence(t, *s);
}

} // namespace

} // namespace effigi::conform

EFFIGI_CONFORMANCE_SUITE("sampler",
                         "values in [0,1), reproducible, uniform, independent dimensions, claimed stratification, "
                         "claimed convergence rate",
                         effigi::conform::runSamplerSuite);
