// Spectral core: RGB upsampling round trips, CIE integration (Monte Carlo XYZ over sampled
// wavelengths), blackbodies, piecewise-linear spectra and table validation. The
// wavelength sampler itself: test_wavelengths.cpp.
#include "effigi/core/error.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/colorspace.hpp"
#include "effigi/spectral/spectrum.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <vector>

#include <unistd.h>

using namespace effigi;

namespace {

/// XYZ = ∫ S x̄ / ∫ ȳ by the trapezoid rule on the 1 nm CIE grid (the reference the
/// upsampling table was fitted against), in double precision.
glm::dvec3 integrateXYZ(const std::function<double(int)>& spd) {
    glm::dvec3 xyz(0.0);
    for (int i = 0; i < cie::TableSize; ++i) {
        double h = (i == 0 || i == cie::TableSize - 1) ? 0.5 : 1.0;
        double s = h * spd(i);
        xyz += s * glm::dvec3(cie::X[i], cie::Y[i], cie::Z[i]);
    }
    return xyz / double(cie::yIntegral());
}

float lambdaAt(int i) { return float(cie::TableStart + i); }

/// Normalised D65 (Y = 1) at table index i.
double d65At(int i) { return double(cie::D65[i]) * cie::d65Normalization(); }

Vector3f toRGB(const glm::dvec3& xyz) { return xyzToLinearSRGB(Vector3f(xyz)); }

} // namespace

TEST_CASE("cie: normalisations", "[spectral]") {
    // ∫ȳ of CIE 1931 on 360–830 nm is 106.857 (CIE 15:2004).
    CHECK(cie::yIntegral() == Approx(106.857).epsilon(1e-4));
    // Normalised D65 has luminance exactly 1 and the standard white chromaticity.
    glm::dvec3 white = integrateXYZ(d65At);
    CHECK(white.y == Approx(1.0).epsilon(1e-6));
    double sum = white.x + white.y + white.z;
    CHECK(white.x / sum == Approx(0.31271).margin(5e-5));
    CHECK(white.y / sum == Approx(0.32902).margin(5e-5));
}

TEST_CASE("upsampling: reflectance RGB -> spectrum -> RGB round trip", "[spectral]") {
    // 16³ grid over the whole linear sRGB cube, rendered under normalised D65.
    double maxErr = 0.0;
    Vector3f worst(0.f);
    const int n = 16;
    for (int r = 0; r < n; ++r)
        for (int g = 0; g < n; ++g)
            for (int b = 0; b < n; ++b) {
                Vector3f rgb(r / float(n - 1), g / float(n - 1), b / float(n - 1));
                Spectrum s = Spectrum::fromRGB(rgb, SpectrumKind::Reflectance);
                Vector3f back = toRGB(integrateXYZ([&](int i) { return s(lambdaAt(i)) * d65At(i); }));
                double e = maxAbsComponent(back - rgb);
                if (e > maxErr) maxErr = e, worst = rgb;
                // A reflectance never leaves [0, 1], and maxValue bounds it.
                for (int i = 0; i < cie::TableSize; i += 10) {
                    REQUIRE(s(lambdaAt(i)) >= 0.f);
                    REQUIRE(s(lambdaAt(i)) <= 1.f);
                    REQUIRE(s(lambdaAt(i)) <= s.maxValue() + 1e-6f);
                }
            }
    INFO("max |ΔRGB| = " << maxErr << " at (" << worst.x << ", " << worst.y << ", " << worst.z << ")");
    CHECK(maxErr < 1e-3);
}

TEST_CASE("upsampling: off-grid reflectances round trip", "[spectral]") {
    // Random colours fall between table nodes, so this measures the trilinear
    // interpolation of the coefficients. Its error is not uniform: typical colours
    // reproduce to ~2e-4 (median), but near the white corner and the bright saturated
    // edges the fitted coefficients change by tens per table cell (a reflectance close
    // to 1 must change shape strongly to shift a ratio by 1.6 %), and interpolating them
    // linearly leaves up to ~3e-3 (measured max over 50 000 colours with the 64³ table;
    // a 128³ table gives ~1e-3). The nodes themselves are fitted to ~3e-6. So: 99 % of
    // colours within 1e-3, all within 4e-3.
    PCG32 rng(42, 7);
    std::vector<double> errors;
    for (int k = 0; k < 4000; ++k) {
        Vector3f rgb(rng.nextFloat(), rng.nextFloat(), rng.nextFloat());
        Spectrum s = Spectrum::fromRGB(rgb, SpectrumKind::Reflectance);
        Vector3f back = toRGB(integrateXYZ([&](int i) { return s(lambdaAt(i)) * d65At(i); }));
        errors.push_back(maxAbsComponent(back - rgb));
    }
    std::sort(errors.begin(), errors.end());
    INFO("median " << errors[2000] << ", 99th percentile " << errors[3960] << ", max " << errors.back());
    CHECK(errors[2000] < 3e-4);
    CHECK(errors[3960] < 1e-3);
    CHECK(errors.back() < 4e-3);
}

TEST_CASE("upsampling: illuminant and unbounded RGB round trip", "[spectral]") {
    // Illuminant spectra already contain D65, so they are integrated as they are.
    // Both kinds look up the table at rgb / (2 max(rgb)) and scale by 2 max(rgb), so
    // the table's error is scaled too: the bound is 1e-3 · max(1, max(rgb)).
    double maxIll = 0.0, maxUnb = 0.0;
    for (float range : {1.f, 2.f}) {  // [0, 1]³ on a 16³ grid, [0, 2]³ on a 9³ grid
        const int n = range == 1.f ? 16 : 9;
        for (int r = 0; r < n; ++r)
            for (int g = 0; g < n; ++g)
                for (int b = 0; b < n; ++b) {
                    Vector3f rgb = range * Vector3f(r, g, b) / float(n - 1);
                    float bound = std::max(1.f, maxComponent(rgb));
                    Spectrum e = Spectrum::fromRGB(rgb, SpectrumKind::Illuminant);
                    Vector3f back = toRGB(integrateXYZ([&](int i) { return e(lambdaAt(i)); }));
                    maxIll = std::max(maxIll, double(maxAbsComponent(back - rgb)) / bound);

                    Spectrum u = Spectrum::fromRGB(rgb, SpectrumKind::Unbounded);
                    back = toRGB(integrateXYZ([&](int i) { return u(lambdaAt(i)) * d65At(i); }));
                    maxUnb = std::max(maxUnb, double(maxAbsComponent(back - rgb)) / bound);
                    REQUIRE(u.maxValue() >= u(550.f) * (1.f - 1e-6f));
                    REQUIRE(e.maxValue() >= e(550.f) * (1.f - 1e-6f));
                }
    }
    INFO("illuminant max |ΔRGB|/max(1, m) = " << maxIll << ", unbounded " << maxUnb);
    CHECK(maxIll < 1e-3);
    CHECK(maxUnb < 1e-3);

    // White (1, 1, 1) is exactly normalised D65; black is zero.
    Spectrum w = Spectrum::fromRGB(Vector3f(1.f), SpectrumKind::Illuminant);
    for (int i = 0; i < cie::TableSize; i += 7) CHECK(w(lambdaAt(i)) == Approx(d65At(i)).epsilon(1e-6));
    CHECK(Spectrum::fromRGB(Vector3f(0.f), SpectrumKind::Illuminant)(500.f) == 0.f);
    CHECK(Spectrum::fromRGB(Vector3f(0.f), SpectrumKind::Unbounded).maxValue() == 0.f);
    // A bright emitter keeps its value: the scale is carried outside the table.
    Spectrum bright = Spectrum::fromRGB(Vector3f(17.f, 12.f, 4.f), SpectrumKind::Illuminant);
    Vector3f back = toRGB(integrateXYZ([&](int i) { return bright(lambdaAt(i)); }));
    CHECK(maxAbsComponent(back - Vector3f(17.f, 12.f, 4.f)) < 17.f * 1e-3f);
}

TEST_CASE("upsampling: greys are exact constants", "[spectral]") {
    for (float v : {0.f, 1e-4f, 0.1f, 0.18f, 0.5f, 0.731f, 0.999f, 1.f}) {
        RGBSigmoidPolynomial p = RGBToSpectrumTable::sRGB()(Vector3f(v));
        CHECK(p.c0 == 0.f);
        CHECK(p.c1 == 0.f);
        Spectrum s = Spectrum::fromRGB(Vector3f(v), SpectrumKind::Reflectance);
        for (float l : {360.f, 455.5f, 600.f, 830.f}) CHECK(s(l) == Approx(v).margin(1e-7));
        CHECK(s.maxValue() == Approx(v).margin(1e-7));
    }
    // The limits are reached exactly through s(±∞).
    CHECK(Spectrum::fromRGB(Vector3f(0.f), SpectrumKind::Reflectance)(500.f) == 0.f);
    CHECK(Spectrum::fromRGB(Vector3f(1.f), SpectrumKind::Reflectance)(500.f) == 1.f);
    // Out-of-range reflectances are clamped to the unit cube; non-finite input is an error.
    CHECK(Spectrum::fromRGB(Vector3f(2.f), SpectrumKind::Reflectance)(500.f) == 1.f);
    CHECK(Spectrum::fromRGB(Vector3f(-1.f), SpectrumKind::Reflectance)(500.f) == 0.f);
    CHECK_THROWS_AS(Spectrum::fromRGB(Vector3f(NAN, 0.f, 0.f), SpectrumKind::Unbounded), Error);
}

TEST_CASE("sigmoid polynomial: maxValue", "[spectral]") {
    RGBSigmoidPolynomial bump{-1e-4f, 0.11f, -30.f};  // vertex at 550 nm
    CHECK(bump.maxValue() == Approx(bump(550.f)).epsilon(1e-6));
    RGBSigmoidPolynomial dip{1e-4f, -0.11f, 30.f};  // minimum inside: max at an end
    CHECK(dip.maxValue() == Approx(std::max(dip(360.f), dip(830.f))).epsilon(1e-6));
    RGBSigmoidPolynomial rising{0.f, 0.01f, -6.f};
    CHECK(rising.maxValue() == Approx(rising(830.f)).epsilon(1e-6));
}

TEST_CASE("wavelength sampling: toXYZ of a constant spectrum converges", "[spectral]") {
    // Monte Carlo XYZ of the equal-energy spectrum S ≡ 1 against direct integration.
    // Per component a two-sided z-test at α = 1e-5 (|z| < 4.42) with the sample
    // standard error; seeded.
    glm::dvec3 expected = integrateXYZ([](int) { return 1.0; });
    PCG32 rng(7, 3);
    const int N = 400000;
    glm::dvec3 sum(0.0), sumSq(0.0);
    SampledSpectrum one(1.f);
    for (int k = 0; k < N; ++k) {
        SampledWavelengths wl = SampledWavelengths::sampleVisible(rng.nextFloat());
        glm::dvec3 xyz(cie::toXYZ(one, wl));
        sum += xyz;
        sumSq += xyz * xyz;
        REQUIRE(double(cie::toY(one, wl)) == Approx(xyz.y).epsilon(1e-5));
    }
    glm::dvec3 mean = sum / double(N);
    for (int c = 0; c < 3; ++c) {
        double var = sumSq[c] / N - mean[c] * mean[c];
        double se = std::sqrt(var / N);
        INFO("component " << c << ": mean " << mean[c] << ", expected " << expected[c] << ", se " << se);
        CHECK(std::abs(mean[c] - expected[c]) < 4.42 * se);
    }
    CHECK(expected.y == Approx(1.0).epsilon(1e-6));  // ∫ȳ/∫ȳ
}

TEST_CASE("blackbody: Wien peak and chromaticity", "[spectral]") {
    for (float T : {3000.f, 4500.f, 5778.f, 6504.f, 9000.f}) {
        Spectrum bb = Spectrum::blackbody(T);
        double wien = 2.8977719e6 / T;
        // Dense scan for the maximum. The peak is flat (B/B_max ≈ 1 − 2.4 (Δλ/λ)²), so
        // float evaluation resolves it only to |Δλ/λ| ≈ 2e-4: allow 3e-4 λ.
        double best = 0.0, arg = 0.0;
        for (int k = -5000; k <= 5000; ++k) {
            double l = wien + 0.01 * k;
            double v = bb(float(l));
            if (v > best) best = v, arg = l;
        }
        INFO("T = " << T << " K: peak at " << arg << " nm, Wien " << wien << " nm");
        CHECK(std::abs(arg - wien) < 3e-4 * wien);
        // Away from the flat top the ordering is unambiguous in float.
        for (double d : {2.0, 5.0, 20.0}) {
            CHECK(bb(float(wien)) > bb(float(wien - d)));
            CHECK(bb(float(wien)) > bb(float(wien + d)));
        }
        CHECK(best == Approx(1.0).epsilon(1e-5));  // normalised to peak 1
        CHECK(bb.maxValue() >= bb(float(std::clamp(wien, 360.0, 830.0))) * (1 - 1e-6));
        CHECK(bb.maxValue() <= 1.f + 1e-6f);
    }
    // Spectral radiance from Planck's law at 500 nm, 5000 K: 1.2107e13 W sr⁻¹ m⁻³.
    CHECK(planck(500.f, 5000.f) == Approx(1.2107e4).epsilon(1e-3));

    // The Planckian locus at 6500 K lies at (x, y) ≈ (0.3135, 0.3237) (CIE 1931); the
    // 6504 K blackbody must sit there within 2e-3. D65 itself is slightly above the
    // locus (0.3127, 0.3290), so it is within 6e-3 of it.
    Spectrum bb = Spectrum::blackbody(6504.f);
    glm::dvec3 xyz = integrateXYZ([&](int i) { return bb(lambdaAt(i)); });
    double x = xyz.x / (xyz.x + xyz.y + xyz.z), y = xyz.y / (xyz.x + xyz.y + xyz.z);
    INFO("6504 K chromaticity (" << x << ", " << y << ")");
    CHECK(std::abs(x - 0.3135) < 2e-3);
    CHECK(std::abs(y - 0.3237) < 2e-3);
    CHECK(std::hypot(x - 0.3127, y - 0.3290) < 6e-3);

    CHECK_THROWS_AS(Spectrum::blackbody(0.f), Error);
    CHECK_THROWS_AS(Spectrum::blackbody(-100.f), Error);
    CHECK_THROWS_AS(Spectrum::blackbody(NAN), Error);
}

TEST_CASE("piecewise-linear spectra", "[spectral]") {
    Spectrum s = Spectrum::piecewiseLinear({400.f, 500.f, 700.f}, {0.2f, 0.6f, 0.1f});
    CHECK(s.type() == Spectrum::Type::Piecewise);
    CHECK(s(400.f) == Approx(0.2f));
    CHECK(s(500.f) == Approx(0.6f));
    CHECK(s(450.f) == Approx(0.4f));
    CHECK(s(650.f) == Approx(0.225f));
    CHECK(s(300.f) == 0.2f);  // constant beyond the ends
    CHECK(s(900.f) == 0.1f);
    CHECK(s.maxValue() == Approx(0.6f));
    CHECK(s.scaled(2.f)(450.f) == Approx(0.8f));
    SampledSpectrum v = s.sample(SampledWavelengths::constant(450.f));
    CHECK(v[3] == Approx(0.4f));

    Spectrum single = Spectrum::piecewiseLinear({550.f}, {0.3f});
    CHECK(single(360.f) == 0.3f);
    CHECK(single(830.f) == 0.3f);

    CHECK(Spectrum(0.25f)(612.f) == 0.25f);
    CHECK(Spectrum(0.25f).maxValue() == 0.25f);

    CHECK_THROWS_AS(Spectrum::piecewiseLinear({400.f, 500.f}, {1.f}), Error);
    CHECK_THROWS_AS(Spectrum::piecewiseLinear({}, {}), Error);
    CHECK_THROWS_AS(Spectrum::piecewiseLinear({500.f, 400.f}, {1.f, 2.f}), Error);
    CHECK_THROWS_AS(Spectrum::piecewiseLinear({400.f, 400.f}, {1.f, 2.f}), Error);
    CHECK_THROWS_AS(Spectrum::piecewiseLinear({400.f, 500.f}, {1.f, NAN}), Error);
}

TEST_CASE("upsampling table: corrupt files are errors naming the file", "[spectral]") {
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("effigi_test_spectral_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    // A valid resolution-2 table: magic, res, z nodes {0, 1}, 3·2³·3 zero coefficients
    // (little endian, as is this machine).
    std::vector<char> good(16 + 4 + 2 * 4 + 3 * 8 * 3 * 4, 0);
    std::memcpy(good.data(), "EFFIGI_RGB2SPEC", 16);
    const std::int32_t res = 2;
    const float one = 1.f;
    std::memcpy(&good[16], &res, 4);
    std::memcpy(&good[24], &one, 4);
    auto write = [&](const std::string& name, const std::vector<char>& bytes) {
        fs::path p = dir / name;
        std::ofstream(p, std::ios::binary).write(bytes.data(), std::streamsize(bytes.size()));
        return p.string();
    };

    std::string ok = write("good.bin", good);
    RGBToSpectrumTable table(ok);
    CHECK(table.resolution() == 2);
    CHECK(table(Vector3f(0.3f, 0.2f, 0.1f)).c2 == 0.f);

    auto expectError = [](const std::string& path) {
        CHECK_THROWS_AS(RGBToSpectrumTable(path), Error);
        CHECK_THROWS_WITH(RGBToSpectrumTable(path), Catch::Contains(path));
    };
    std::vector<char> bad = good;
    bad[3] = 'X';
    expectError(write("magic.bin", bad));
    bad = good;
    bad.resize(bad.size() - 4);
    expectError(write("truncated.bin", bad));
    expectError(write("short.bin", std::vector<char>(good.begin(), good.begin() + 10)));
    bad = good;
    bad[16] = 100;  // resolution 100 with the data of 2
    expectError(write("res.bin", bad));
    bad = good;
    float nan = NAN;
    std::memcpy(&bad[bad.size() - 4], &nan, 4);
    expectError(write("nan.bin", bad));
    bad = good;
    float half = 0.5f;
    std::memcpy(&bad[24], &half, 4);  // z nodes {0, 0.5}
    expectError(write("nodes.bin", bad));
    expectError((dir / "missing.bin").string());
    fs::remove_all(dir);

    // The shipped table loads and has the build resolution.
    CHECK(RGBToSpectrumTable::sRGB().resolution() >= 16);
}

TEST_CASE("spectrum: the inline sample() path equals operator()", "[spectral]") {
    using namespace effigi;
    PCG32 rng(7, 3);
    for (int k = 0; k < 2000; ++k) {
        Vector3f rgb(rng.nextFloat(), rng.nextFloat(), rng.nextFloat());
        if (k % 10 == 0) rgb = Vector3f(float(k % 3 == 0), float(k % 3 == 1), 0.f);  // primaries, black
        for (SpectrumKind kind : {SpectrumKind::Reflectance, SpectrumKind::Illuminant}) {
            Spectrum s = Spectrum::fromRGB(rgb * (kind == SpectrumKind::Illuminant ? 7.f : 1.f), kind);
            SampledWavelengths lambda = SampledWavelengths::sampleVisible(rng.nextFloat());
            SampledSpectrum v = s.sample(lambda);
            for (int i = 0; i < NSpectrumSamples; ++i)
                CHECK(v[i] == Approx(s(lambda[i])).margin(1e-6).epsilon(1e-5));
        }
    }
}
