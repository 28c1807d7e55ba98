// Integrals of the embedded CIE tables (effigi/spectral/cie.hpp). Every sum here uses
// the trapezoid rule on the 1 nm grid, which integrates the piecewise-linear tables
// exactly; it is the same rule the RGB->spectrum fit (tools/rgb2spec_opt) uses, so a
// fitted reflectance reproduces its RGB under these definitions.
#include "effigi/spectral/cie.hpp"

namespace effigi::cie {
namespace {

double trapezoid(const float* a, const float* b) {
    double sum = 0.0;
    for (int i = 0; i < TableSize; ++i) {
        double h = (i == 0 || i == TableSize - 1) ? 0.5 : 1.0;
        sum += h * double(a[i]) * (b ? double(b[i]) : 1.0);
    }
    return sum;
}

} // namespace

float yIntegral() {
    static const float value = float(trapezoid(Y, nullptr));  // ≈ 106.86 for CIE 1931
    return value;
}

// The factor k that multiplies the relative D65 table values (cie::D65, 100 at 560 nm)
// to give the SPD S(λ) = k·D65(λ) whose luminance Y = ∫ S ȳ dλ / ∫ ȳ dλ is exactly 1:
// k = ∫ ȳ dλ / ∫ D65 ȳ dλ. S is the emission that linear-sRGB white (1, 1, 1) denotes.
float d65Normalization() {
    static const float value = float(trapezoid(Y, nullptr) / trapezoid(D65, Y));
    return value;
}

} // namespace effigi::cie
