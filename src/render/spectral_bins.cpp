// Spectral bins and the spectral OpenEXR channel names (effigi/render/spectral_bins.hpp).
#include "effigi/render/spectral_bins.hpp"

#include "effigi/core/error.hpp"
#include "effigi/spectral/cie.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>

namespace effigi {

SpectralBinning::SpectralBinning(int count, float lambdaMin, float lambdaMax) {
    if (count < 0 || count > MaxBins) fail("spectral bins: {} bins requested, allowed 0..{}", count, MaxBins);
    if (!(lambdaMin >= LambdaMin && lambdaMax <= LambdaMax && lambdaMin < lambdaMax))
        fail("spectral bins: range [{}, {}] nm must satisfy {} <= min < max <= {}", lambdaMin, lambdaMax, LambdaMin,
             LambdaMax);
    m_count = count;
    m_min = lambdaMin;
    m_max = lambdaMax;
    m_width = count > 0 ? (lambdaMax - lambdaMin) / float(count) : 0.f;
    m_invWidth = count > 0 ? 1.f / m_width : 0.f;
}

bool SpectralBinning::estimate(const SampledSpectrum& L, const SampledWavelengths& lambda, float* out) const {
    if (m_count == 0) return true;
    std::fill(out, out + m_count, 0.f);
    const SampledSpectrum pdf = lambda.pdf();
    // 1 / (N · w): the mean over the N hero wavelengths, per nm of bin width.
    const float norm = m_invWidth / float(NSpectrumSamples);
    bool finite = true;
    for (int i = 0; i < NSpectrumSamples; ++i) {
        if (!(pdf[i] > 0.f)) continue;
        const int b = binOf(lambda[i]);
        if (b < 0) continue;
        const float v = L[i] / pdf[i] * norm;
        finite = finite && std::isfinite(v);
        out[b] += v;
    }
    if (!finite) std::fill(out, out + m_count, 0.f);
    return finite;
}

std::vector<std::string> SpectralBinning::channelNames() const {
    std::vector<std::string> names;
    names.reserve(std::size_t(m_count));
    for (int b = 0; b < m_count; ++b) names.push_back(spectral_exr::channelName(double(center(b))));
    return names;
}

namespace spectral_exr {

std::string channelName(double lambdaNm) {
    // fmt is locale-independent, so the decimal point is always '.' before the swap.
    std::string v = fmt::format("{:.6f}", lambdaNm);
    std::replace(v.begin(), v.end(), '.', ',');
    return "S0." + v + "nm";
}

namespace {

/// Power of ten of an SI prefix allowed by the layout, or nullopt.
std::optional<int> prefixExponent(std::string_view p) {
    static const std::pair<std::string_view, int> prefixes[] = {
        {"", 0},  {"Y", 24}, {"Z", 21}, {"E", 18}, {"P", 15}, {"T", 12}, {"G", 9},   {"M", 6}, {"k", 3},
        {"h", 2}, {"da", 1}, {"d", -1}, {"c", -2}, {"m", -3}, {"u", -6}, {"n", -9}, {"p", -12}};
    for (const auto& [name, e] : prefixes)
        if (name == p) return e;
    return std::nullopt;
}

bool isDigit(char c) { return c >= '0' && c <= '9'; }

} // namespace

std::optional<double> parseChannelName(std::string_view name) {
    if (name.substr(0, 3) != "S0.") return std::nullopt;
    name.remove_prefix(3);
    // The number: digits, an optional comma and digits (at least one digit in all), then
    // an optional exponent E[+-]digits.
    std::size_t i = 0, digits = 0;
    std::string number;
    while (i < name.size() && isDigit(name[i])) number += name[i++], ++digits;
    if (i < name.size() && name[i] == ',') {
        number += '.', ++i;
        while (i < name.size() && isDigit(name[i])) number += name[i++], ++digits;
    }
    if (digits == 0) return std::nullopt;
    if (i + 1 < name.size() && (name[i] == 'E' || name[i] == 'e')) {
        std::size_t j = i + 1;
        std::string exponent = "e";
        if (name[j] == '+' || name[j] == '-') exponent += name[j++];
        std::size_t start = j;
        while (j < name.size() && isDigit(name[j])) exponent += name[j++];
        // "E" not followed by digits is the prefix exa, not an exponent.
        if (j > start) number += exponent, i = j;
    }
    std::string_view unit = name.substr(i);
    double scale;  // unit -> metres or hertz
    bool hertz;
    if (unit.size() >= 2 && unit.substr(unit.size() - 2) == "Hz") {
        hertz = true;
        unit.remove_suffix(2);
    } else if (!unit.empty() && unit.back() == 'm') {
        hertz = false;
        unit.remove_suffix(1);
    } else {
        return std::nullopt;
    }
    std::optional<int> e = prefixExponent(unit);
    if (!e) return std::nullopt;
    scale = std::pow(10.0, double(*e));
    double value = 0.0;
    auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), value);
    if (ec != std::errc() || end != number.data() + number.size() || !(value > 0.0) || !std::isfinite(value))
        return std::nullopt;
    constexpr double SpeedOfLight = 299792458.0;  // m/s, exact (SI)
    const double lambdaNm = hertz ? SpeedOfLight / (value * scale) * 1e9 : value * scale * 1e9;
    if (!std::isfinite(lambdaNm) || !(lambdaNm > 0.0)) return std::nullopt;
    return lambdaNm;
}

std::vector<double> edgesFromCenters(std::span<const double> c) {
    if (c.size() < 2) fail("spectral bands: at least two band centres are needed to infer band widths");
    for (std::size_t i = 1; i < c.size(); ++i)
        if (!(c[i] > c[i - 1])) fail("spectral bands: centres must be distinct and sorted ({} after {})", c[i], c[i - 1]);
    std::vector<double> e(c.size() + 1);
    for (std::size_t i = 1; i < c.size(); ++i) e[i] = 0.5 * (c[i - 1] + c[i]);
    e.front() = c.front() - (e[1] - c.front());
    e.back() = c.back() + (c.back() - e[c.size() - 1]);
    return e;
}

namespace {

/// ∫_a^b of a 1 nm table interpolated linearly (cie::lookup), exactly: the trapezoid
/// rule between the table's nodes and the clipped interval's ends.
double integrateTable(const float* table, double a, double b) {
    const double lo = std::max(a, double(cie::TableStart));
    const double hi = std::min(b, double(cie::TableStart + cie::TableSize - 1));
    if (!(hi > lo)) return 0.0;
    double sum = 0.0, x0 = lo;
    double f0 = cie::lookup(table, float(x0));
    while (x0 < hi) {
        double x1 = std::min(std::floor(x0) + 1.0, hi);
        double f1 = cie::lookup(table, float(x1));
        sum += 0.5 * (f0 + f1) * (x1 - x0);
        x0 = x1, f0 = f1;
    }
    return sum;
}

} // namespace

namespace {

/// ∫_a^b (λ − m) f(λ) dλ of a table, exactly (the integrand is quadratic per interval:
/// Simpson's rule is exact).
double integrateTableMoment(const float* table, double a, double b, double m) {
    const double lo = std::max(a, double(cie::TableStart));
    const double hi = std::min(b, double(cie::TableStart + cie::TableSize - 1));
    if (!(hi > lo)) return 0.0;
    double sum = 0.0, x0 = lo;
    while (x0 < hi) {
        double x1 = std::min(std::floor(x0) + 1.0, hi), xm = 0.5 * (x0 + x1);
        auto g = [&](double x) { return (x - m) * double(cie::lookup(table, float(x))); };
        sum += (x1 - x0) / 6.0 * (g(x0) + 4.0 * g(xm) + g(x1));
        x0 = x1;
    }
    return sum;
}

} // namespace

std::vector<Vector3f> xyzWeights(std::span<const double> edges, Reconstruction r) {
    std::vector<Vector3f> w;
    if (edges.size() < 2) return w;
    const std::size_t n = edges.size() - 1;
    const double norm = 1.0 / double(cie::yIntegral());
    const float* cmf[3] = {cie::X, cie::Y, cie::Z};
    std::vector<glm::dvec3> acc(n, glm::dvec3(0.0));
    for (std::size_t b = 0; b < n; ++b)
        for (int k = 0; k < 3; ++k) acc[b][k] = integrateTable(cmf[k], edges[b], edges[b + 1]);
    if (r == Reconstruction::Linear && n >= 2) {
        // Within bin b, S(λ) ≈ S_b + s_b (λ − m_b), m_b the bin's midpoint: the bin's mean
        // is kept and the slope s_b comes from the neighbouring bins' means (central
        // difference, one-sided at the ends). It adds s_b ∫_b (λ − m_b) x̄ dλ to X, which
        // is linear in the neighbours' means: fold it into their weights.
        auto mid = [&](std::size_t b) { return 0.5 * (edges[b] + edges[b + 1]); };
        for (std::size_t b = 0; b < n; ++b) {
            const std::size_t lo = b == 0 ? 0 : b - 1, hi = b + 1 == n ? b : b + 1;
            const double dm = mid(hi) - mid(lo);
            for (int k = 0; k < 3; ++k) {
                const double moment = integrateTableMoment(cmf[k], edges[b], edges[b + 1], mid(b));
                acc[hi][k] += moment / dm;
                acc[lo][k] -= moment / dm;
            }
        }
    }
    for (const glm::dvec3& a : acc) w.emplace_back(Vector3f(a * norm));
    return w;
}

} // namespace spectral_exr
} // namespace effigi
