#pragma once
// RGB -> spectrum upsampling after Jakob & Hanika 2019, "A Low-Dimensional Function
// Space for Efficient Spectral Upsampling" (Computer Graphics Forum 38(2)). A smooth
// reflectance s(c0 λ² + c1 λ + c2) reproduces an RGB colour under the colour space's
// white; the coefficients are tabulated over RGB by tools/rgb2spec_opt at build time.
#include "effigi/math/vector.hpp"

#include <string>
#include <vector>

namespace effigi {

/// s(c0 λ² + c1 λ + c2) with s(x) = ½ + x / (2 √(1 + x²)); λ in nm.
struct RGBSigmoidPolynomial {
    float c0 = 0.f, c1 = 0.f, c2 = 0.f;

    static float sigmoid(float x) {
        if (std::isinf(x)) return x > 0.f ? 1.f : 0.f;
        return 0.5f + x / (2.f * std::sqrt(1.f + x * x));
    }
    /// The polynomial is evaluated in double: in nm its terms are large and cancel
    /// (|c2| reaches ~10²), so float evaluation would add noise of ~10⁻⁵.
    float operator()(float lambda) const { return sigmoid(float(polynomial(lambda))); }
    double polynomial(double lambda) const { return (double(c0) * lambda + double(c1)) * lambda + double(c2); }
    /// Largest value over [360, 830] nm: at an end point or at the parabola's vertex.
    float maxValue() const;
};

class RGBToSpectrumTable {
public:
    /// The sRGB table, loaded once from share/effigi/rgb2spec_srgb.bin.
    static const RGBToSpectrumTable& sRGB();

    /// Load a table written by tools/rgb2spec_opt; throws effigi::Error if malformed.
    explicit RGBToSpectrumTable(const std::string& path);

    /// Coefficients for an RGB triple with components in [0, 1].
    RGBSigmoidPolynomial operator()(const Vector3f& rgb) const;

    int resolution() const { return m_res; }

private:
    int m_res = 0;
    std::vector<float> m_zNodes;  // m_res nodes of the brightness axis
    std::vector<float> m_coeffs;  // [3][res][res][res][3]
};

} // namespace effigi
