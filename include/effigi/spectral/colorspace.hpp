#pragma once
// Linear RGB colour spaces by their primaries and white (CIE 15:2004 / IEC 61966-2-1),
// and the conversions the film and `effigi convert` use.
//
// effigi's XYZ is scene-referred with a D65 white: the emission that linear-sRGB white
// (1, 1, 1) denotes is D65 scaled to Y = 1 (cie::d65Normalization). Spaces whose white
// is not D65 (ACEScg) receive D65-referred XYZ through a von Kries transform in the
// Bradford cone space (Lam 1985, as given by Lindbloom and in CIE 160:2004's review), so
// that a D65-white surface is RGB (1, 1, 1) in every space.
//
// Primaries and whites, as published:
//   sRGB / Rec.709: IEC 61966-2-1:1999 and ITU-R BT.709-6: R (0.64, 0.33), G (0.30, 0.60),
//                   B (0.15, 0.06), white D65.
//   Rec.2020:       ITU-R BT.2020-2, table 3: R (0.708, 0.292), G (0.170, 0.797),
//                   B (0.131, 0.046), white D65.
//   ACEScg (AP1):   Academy S-2014-004 (ACEScg) with SMPTE ST 2065-1:2012 white:
//                   R (0.713, 0.293), G (0.165, 0.830), B (0.128, 0.044),
//                   white (0.32168, 0.33767) ("ACES white", near D60).
// The D65 white is taken as XYZ (0.95047, 1, 1.08883), the white of the CIE 1931 2°
// observer and tabulated D65 (xy 0.31273, 0.32902, which the standards round to
// (0.3127, 0.3290)). This is the white of the sRGB matrices below, which the build-time
// RGB->spectrum fit (tools/rgb2spec_opt) shares, so every D65 space agrees on white.
#include "effigi/math/vector.hpp"

#include <glm/mat3x3.hpp>

#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace effigi {

/// XYZ -> linear sRGB / Rec.709 primaries, D65 white (IEC 61966-2-1).
inline Vector3f xyzToLinearSRGB(const Vector3f& xyz) {
    // GLM matrices are column-major: each glm::vec3 below is a column.
    static const glm::mat3 M(3.2404542f, -0.9692660f, 0.0556434f,   //
                             -1.5371385f, 1.8760108f, -0.2040259f,  //
                             -0.4985314f, 0.0415560f, 1.0572252f);
    return M * xyz;
}

inline Vector3f linearSRGBToXYZ(const Vector3f& rgb) {
    static const glm::mat3 M(0.4124564f, 0.2126729f, 0.0193339f,  //
                             0.3575761f, 0.7151522f, 0.1191920f,  //
                             0.1804375f, 0.0721750f, 0.9503041f);
    return M * rgb;
}

/// The sRGB transfer function (encode linear -> display).
inline float srgbEncode(float v) {
    if (v <= 0.0031308f) return 12.92f * v;
    return 1.055f * std::pow(v, 1.f / 2.4f) - 0.055f;
}
inline float srgbDecode(float v) {
    if (v <= 0.04045f) return v / 12.92f;
    return std::pow((v + 0.055f) / 1.055f, 2.4f);
}

namespace colorimetry {

struct Chromaticity {
    double x = 0.0, y = 0.0;
};

/// XYZ with Y = 1 of a chromaticity.
inline glm::dvec3 xyToXYZ(Chromaticity c) { return {c.x / c.y, 1.0, (1.0 - c.x - c.y) / c.y}; }
inline Chromaticity xyzToXY(const glm::dvec3& v) {
    double s = v.x + v.y + v.z;
    return {v.x / s, v.y / s};
}

/// The D65 white of the film (see the header comment).
inline constexpr glm::dvec3 D65White{0.95047, 1.0, 1.08883};
/// ACES white, SMPTE ST 2065-1:2012.
inline constexpr Chromaticity AcesWhite{0.32168, 0.33767};

/// Linear RGB -> XYZ for primaries r, g, b and a white of XYZ w (Y = 1): the columns are
/// the primaries' XYZ, scaled so that RGB (1, 1, 1) is w (SMPTE RP 177-1993, sec. 3.3).
inline glm::dmat3 rgbToXYZMatrix(Chromaticity r, Chromaticity g, Chromaticity b, const glm::dvec3& w) {
    glm::dmat3 P(xyToXYZ(r), xyToXYZ(g), xyToXYZ(b));  // columns
    glm::dvec3 s = glm::inverse(P) * w;
    return glm::dmat3(P[0] * s.x, P[1] * s.y, P[2] * s.z);
}

/// Bradford chromatic adaptation of XYZ from white `from` to white `to` (von Kries
/// scaling in the Bradford "sharpened cone" space; K. M. Lam, PhD thesis, Bradford 1985).
inline glm::dmat3 bradfordAdaptation(const glm::dvec3& from, const glm::dvec3& to) {
    // Rows of the Bradford matrix, written transposed because GLM is column-major.
    const glm::dmat3 B = glm::transpose(glm::dmat3(0.8951, 0.2664, -0.1614,   //
                                                   -0.7502, 1.7135, 0.0367,   //
                                                   0.0389, -0.0685, 1.0296));
    glm::dvec3 a = B * from, b = B * to;
    glm::dmat3 D(1.0);
    D[0][0] = b.x / a.x, D[1][1] = b.y / a.y, D[2][2] = b.z / a.z;
    return glm::inverse(B) * D * B;
}

} // namespace colorimetry

enum class ColorSpaceId { SRGB, Rec2020, ACEScg };

/// A linear RGB space. fromXYZ/toXYZ take and give effigi's D65-referred XYZ (adapted to
/// the space's white where that differs); the native matrices relate RGB to XYZ under
/// the space's own white.
class RGBColorSpace {
public:
    RGBColorSpace(std::string name, colorimetry::Chromaticity r, colorimetry::Chromaticity g,
                  colorimetry::Chromaticity b, const glm::dvec3& white)
        : m_name(std::move(name)), m_primaries{r, g, b}, m_white(white) {
        m_rgbToXYZ = colorimetry::rgbToXYZMatrix(r, g, b, white);
        m_xyzToRGB = glm::inverse(m_rgbToXYZ);
        glm::dmat3 adapt = colorimetry::bradfordAdaptation(colorimetry::D65White, white);
        // A D65 space needs no adaptation; skip it so that sRGB stays exactly its matrix.
        const bool d65 = glm::all(glm::lessThan(glm::abs(white - colorimetry::D65White), glm::dvec3(1e-12)));
        if (d65) adapt = glm::dmat3(1.0);
        m_fromXYZ = glm::mat3(m_xyzToRGB * adapt);
        m_toXYZ = glm::mat3(glm::inverse(m_xyzToRGB * adapt));
        m_luminance = Vector3f(float(m_rgbToXYZ[0].y), float(m_rgbToXYZ[1].y), float(m_rgbToXYZ[2].y));
    }

    const std::string& name() const { return m_name; }
    /// Effigi XYZ (D65-referred) -> linear RGB of this space.
    Vector3f fromXYZ(const Vector3f& xyz) const { return m_fromXYZ * xyz; }
    /// Linear RGB of this space -> effigi XYZ (D65-referred).
    Vector3f toXYZ(const Vector3f& rgb) const { return m_toXYZ * rgb; }
    /// Native matrices (no adaptation), double precision.
    const glm::dmat3& rgbToXYZ() const { return m_rgbToXYZ; }
    const glm::dmat3& xyzToRGB() const { return m_xyzToRGB; }
    /// Relative luminance weights of R, G, B (the Y row of rgbToXYZ).
    const Vector3f& luminanceWeights() const { return m_luminance; }
    float luminance(const Vector3f& rgb) const { return dot(m_luminance, rgb); }
    const std::array<colorimetry::Chromaticity, 3>& primaries() const { return m_primaries; }
    colorimetry::Chromaticity whiteXY() const { return colorimetry::xyzToXY(m_white); }
    const glm::dvec3& whiteXYZ() const { return m_white; }

    static const RGBColorSpace& get(ColorSpaceId id) {
        using colorimetry::Chromaticity;
        static const RGBColorSpace srgb("srgb", Chromaticity{0.64, 0.33}, Chromaticity{0.30, 0.60},
                                        Chromaticity{0.15, 0.06}, colorimetry::D65White);
        static const RGBColorSpace rec2020("rec2020", Chromaticity{0.708, 0.292}, Chromaticity{0.170, 0.797},
                                           Chromaticity{0.131, 0.046}, colorimetry::D65White);
        static const RGBColorSpace acescg("acescg", Chromaticity{0.713, 0.293}, Chromaticity{0.165, 0.830},
                                          Chromaticity{0.128, 0.044}, colorimetry::xyToXYZ(colorimetry::AcesWhite));
        switch (id) {
        case ColorSpaceId::Rec2020: return rec2020;
        case ColorSpaceId::ACEScg: return acescg;
        case ColorSpaceId::SRGB: break;
        }
        return srgb;
    }
    /// The names accepted by the film's `colorspace` and `effigi convert --colorspace`.
    static const std::array<const char*, 3>& names() {
        static const std::array<const char*, 3> n{"srgb", "rec2020", "acescg"};
        return n;
    }
    static std::optional<ColorSpaceId> parse(std::string_view name) {
        if (name == "srgb") return ColorSpaceId::SRGB;
        if (name == "rec2020") return ColorSpaceId::Rec2020;
        if (name == "acescg") return ColorSpaceId::ACEScg;
        return std::nullopt;
    }

private:
    std::string m_name;
    std::array<colorimetry::Chromaticity, 3> m_primaries;
    glm::dvec3 m_white;
    glm::dmat3 m_rgbToXYZ{1.0}, m_xyzToRGB{1.0};
    glm::mat3 m_fromXYZ{1.f}, m_toXYZ{1.f};
    Vector3f m_luminance{0.f};
};

} // namespace effigi
