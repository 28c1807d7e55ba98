#pragma once
// Colorimetry for the tests (test_colorchecker, test_spectrum_inputs), written from the
// CIE formulas and independent of the renderer's spectral code: reading the data/spectra
// CSV tables, tristimulus values by 1 nm summation (CIE 15:2004 §7), CIELAB (§8.2.1),
// CIEDE2000 (Sharma, Wu & Dalal 2005) and the Bradford chromatic adaptation.
#include "effigi/spectral/cie.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

namespace effigi::test {

using Vec3 = glm::dvec3;

/// A "lambda,value" table from data/spectra, read without effigi's loader.
struct Table {
    std::vector<double> lambda, value;

    /// Linear interpolation, the end values held beyond the ends (effigi's convention).
    double operator()(double l) const {
        if (l <= lambda.front()) return value.front();
        if (l >= lambda.back()) return value.back();
        std::size_t i = std::size_t(std::upper_bound(lambda.begin(), lambda.end(), l) - lambda.begin());
        double t = (l - lambda[i - 1]) / (lambda[i] - lambda[i - 1]);
        return (1 - t) * value[i - 1] + t * value[i];
    }
};

inline Table readTable(const std::string& name) {
    std::ifstream in(std::string(EFFIGI_SOURCE_DIR) + "/data/spectra/" + name + ".csv");
    INFO("data/spectra/" << name << ".csv");
    REQUIRE(in);
    Table t;
    std::string line;
    bool header = false;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        if (!header) {
            REQUIRE(line == "lambda,value");
            header = true;
            continue;
        }
        std::replace(line.begin(), line.end(), ',', ' ');
        std::istringstream ss(line);
        double l = 0, v = 0;
        REQUIRE(static_cast<bool>(ss >> l >> v));
        t.lambda.push_back(l);
        t.value.push_back(v);
    }
    REQUIRE(t.lambda.size() >= 2);
    return t;
}

/// Σ S(λ) (x̄, ȳ, z̄)(λ) over the 1 nm CMF table, 360–830 nm (CIE 15:2004 §7.1 with Δλ = 1 nm).
inline Vec3 tristimulus(const std::function<double(double)>& S) {
    Vec3 xyz(0.0);
    for (int i = 0; i < cie::TableSize; ++i) {
        double s = S(double(cie::TableStart + i));
        xyz += s * Vec3(cie::X[i], cie::Y[i], cie::Z[i]);
    }
    return xyz;
}

inline glm::dvec2 chromaticity(const Vec3& xyz) {
    double sum = xyz.x + xyz.y + xyz.z;
    return {xyz.x / sum, xyz.y / sum};
}

/// XYZ of an object colour ρ under illuminant D, white (ρ = 1) at Y = 1.
inline Vec3 objectXYZ(const Table& rho, const Table& illuminant) {
    double k = 1.0 / tristimulus([&](double l) { return illuminant(l); }).y;
    return k * tristimulus([&](double l) { return rho(l) * illuminant(l); });
}

inline Vec3 xyYToXYZ(double x, double y, double Y) { return {x * Y / y, Y, (1.0 - x - y) * Y / y}; }

struct Lab {
    double L, a, b;
};

/// CIE 1976 L*a*b* relative to the white `wn` (CIE 15:2004 §8.2.1).
inline Lab toLab(const Vec3& xyz, const Vec3& wn) {
    auto f = [](double t) {
        const double d = 6.0 / 29.0;
        return t > d * d * d ? std::cbrt(t) : t / (3 * d * d) + 4.0 / 29.0;
    };
    double fx = f(xyz.x / wn.x), fy = f(xyz.y / wn.y), fz = f(xyz.z / wn.z);
    return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

/// CIEDE2000 colour difference, k_L = k_C = k_H = 1: G. Sharma, W. Wu, E. N. Dalal, "The
/// CIEDE2000 Color-Difference Formula: Implementation Notes, Supplementary Test Data, and
/// Mathematical Observations", Color Res. Appl. 30(1), 2005, the steps of their §2.
inline double deltaE2000(const Lab& p, const Lab& q) {
    const double deg = 3.14159265358979323846 / 180.0;
    const double pow25_7 = 6103515625.0;  // 25^7
    double c1 = std::hypot(p.a, p.b), c2 = std::hypot(q.a, q.b);
    double cbar7 = std::pow(0.5 * (c1 + c2), 7.0);
    double g = 0.5 * (1.0 - std::sqrt(cbar7 / (cbar7 + pow25_7)));
    double a1 = (1 + g) * p.a, a2 = (1 + g) * q.a;
    double cp1 = std::hypot(a1, p.b), cp2 = std::hypot(a2, q.b);
    auto hue = [&](double b, double a) {
        if (a == 0.0 && b == 0.0) return 0.0;
        double h = std::atan2(b, a) / deg;
        return h < 0 ? h + 360.0 : h;
    };
    double h1 = hue(p.b, a1), h2 = hue(q.b, a2);

    double dL = q.L - p.L, dC = cp2 - cp1, dh = 0.0;
    if (cp1 * cp2 != 0.0) {
        dh = h2 - h1;
        if (dh > 180) dh -= 360;
        else if (dh < -180) dh += 360;
    }
    double dH = 2 * std::sqrt(cp1 * cp2) * std::sin(0.5 * dh * deg);

    double lbar = 0.5 * (p.L + q.L), cbarp = 0.5 * (cp1 + cp2), hbar = h1 + h2;
    if (cp1 * cp2 != 0.0) {
        if (std::abs(h1 - h2) <= 180) hbar = 0.5 * (h1 + h2);
        else if (h1 + h2 < 360) hbar = 0.5 * (h1 + h2 + 360);
        else hbar = 0.5 * (h1 + h2 - 360);
    }
    double t = 1 - 0.17 * std::cos((hbar - 30) * deg) + 0.24 * std::cos(2 * hbar * deg) +
               0.32 * std::cos((3 * hbar + 6) * deg) - 0.20 * std::cos((4 * hbar - 63) * deg);
    double dTheta = 30 * std::exp(-std::pow((hbar - 275) / 25, 2.0));
    double cbarp7 = std::pow(cbarp, 7.0);
    double rc = 2 * std::sqrt(cbarp7 / (cbarp7 + pow25_7));
    double l50 = (lbar - 50) * (lbar - 50);
    double sl = 1 + 0.015 * l50 / std::sqrt(20 + l50), sc = 1 + 0.045 * cbarp, sh = 1 + 0.015 * cbarp * t;
    double rt = -std::sin(2 * dTheta * deg) * rc;
    double x = dL / sl, y = dC / sc, z = dH / sh;
    return std::sqrt(x * x + y * y + z * z + rt * y * z);
}

/// Bradford chromatic adaptation of XYZ from white `ws` to white `wd` (von Kries scaling
/// in the Bradford cone space; K. M. Lam 1985, as used by ICC.1:2010 Annex E).
inline Vec3 bradford(const Vec3& xyz, const Vec3& ws, const Vec3& wd) {
    // M_BFD, given column by column (glm is column-major): rows (0.8951, 0.2664, -0.1614),
    // (-0.7502, 1.7135, 0.0367), (0.0389, -0.0685, 1.0296).
    const glm::dmat3 mt(0.8951, -0.7502, 0.0389, 0.2664, 1.7135, -0.0685, -0.1614, 0.0367, 1.0296);
    Vec3 s = mt * ws, d = mt * wd;
    Vec3 cone = (mt * xyz) * (d / s);
    return glm::inverse(mt) * cone;
}

} // namespace effigi::test
