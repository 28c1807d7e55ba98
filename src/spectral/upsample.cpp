// RGB -> sigmoid-polynomial lookup (Jakob & Hanika 2019, §4): loads the table that
// tools/rgb2spec_opt fits at build time and interpolates it trilinearly.
#include "effigi/spectral/upsample.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/module.hpp"
#include "effigi/spectral/wavelengths.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>

namespace effigi {

float RGBSigmoidPolynomial::maxValue() const {
    // s is monotonic, so the maximum of s(p(λ)) is that of p: at an end of the range
    // or, for a downward parabola, at its vertex.
    double m = std::max(polynomial(LambdaMin), polynomial(LambdaMax));
    if (c0 < 0.f) {
        double vertex = -double(c1) / (2.0 * double(c0));
        if (vertex > LambdaMin && vertex < LambdaMax) m = std::max(m, polynomial(vertex));
    }
    return sigmoid(float(m));
}

namespace {

constexpr char Magic[16] = "EFFIGI_RGB2SPEC";  // 15 characters and '\0'
constexpr int MaxResolution = 1024;

std::uint32_t readU32(const unsigned char* p) {
    return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 | std::uint32_t(p[2]) << 16 |
           std::uint32_t(p[3]) << 24;
}
float readFloat(const unsigned char* p) {
    std::uint32_t u = readU32(p);
    float f;
    std::memcpy(&f, &u, 4);
    return f;
}

} // namespace

RGBToSpectrumTable::RGBToSpectrumTable(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("{}: cannot open the RGB->spectrum table", path);
    std::vector<unsigned char> data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) fail("{}: error reading the RGB->spectrum table", path);

    const std::size_t header = sizeof Magic + 4;
    if (data.size() < header || std::memcmp(data.data(), Magic, sizeof Magic) != 0)
        fail("{}: not an RGB->spectrum table (bad magic; expected a file written by rgb2spec_opt)", path);
    std::uint32_t res = readU32(data.data() + sizeof Magic);
    if (res < 2 || res > std::uint32_t(MaxResolution))
        fail("{}: RGB->spectrum table resolution {} is outside [2, {}]", path, res, MaxResolution);
    const std::size_t nCoeffs = std::size_t(3) * res * res * res * 3;
    const std::size_t expected = header + 4 * (std::size_t(res) + nCoeffs);
    if (data.size() != expected)
        fail("{}: RGB->spectrum table has {} bytes, expected {} for resolution {}", path, data.size(),
             expected, res);

    m_res = int(res);
    m_zNodes.resize(res);
    const unsigned char* p = data.data() + header;
    for (std::size_t i = 0; i < res; ++i, p += 4) {
        m_zNodes[i] = readFloat(p);
        bool ok = m_zNodes[i] >= 0.f && m_zNodes[i] <= 1.f && (i == 0 || m_zNodes[i] > m_zNodes[i - 1]);
        if (!ok) fail("{}: RGB->spectrum table brightness nodes are not ascending in [0, 1] (node {})", path, i);
    }
    if (m_zNodes.front() != 0.f || m_zNodes.back() != 1.f)
        fail("{}: RGB->spectrum table brightness nodes must span [0, 1]", path);
    m_coeffs.resize(nCoeffs);
    for (std::size_t i = 0; i < nCoeffs; ++i, p += 4) {
        m_coeffs[i] = readFloat(p);
        if (!std::isfinite(m_coeffs[i]))
            fail("{}: RGB->spectrum table coefficient {} is not finite", path, i);
    }
}

const RGBToSpectrumTable& RGBToSpectrumTable::sRGB() {
    // A failed load throws out of the initialiser, so the next call tries again.
    static const RGBToSpectrumTable table((dataDirectory() / "rgb2spec_srgb.bin").string());
    return table;
}

RGBSigmoidPolynomial RGBToSpectrumTable::operator()(const Vector3f& rgbIn) const {
    // Components outside [0, 1] (and NaN) are clamped: the table covers the unit cube.
    float rgb[3];
    for (int i = 0; i < 3; ++i) rgb[i] = rgbIn[i] > 0.f ? std::min(rgbIn[i], 1.f) : 0.f;

    if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) {
        // Greys are constant spectra, solved exactly: s(c2) = v <=> c2 = u / √(1 − u²),
        // u = 2v − 1 (±∞ at v = 0 and 1, which sigmoid() maps to 0 and 1).
        double u = 2.0 * double(rgb[0]) - 1.0;
        double c2 = u / std::sqrt(1.0 - u * u);
        return {0.f, 0.f, float(c2)};
    }

    // Slab of the largest component; the other two become ratios to it (paper §4).
    int l = rgb[0] >= rgb[1] ? (rgb[0] >= rgb[2] ? 0 : 2) : (rgb[1] >= rgb[2] ? 1 : 2);
    float z = rgb[l];  // > 0: the components differ and none is negative
    float x = rgb[(l + 1) % 3] / z, y = rgb[(l + 2) % 3] / z;

    const int last = m_res - 1;
    auto cell = [last](float v, int& i) {
        float f = std::clamp(v, 0.f, 1.f) * float(last);
        i = std::min(int(f), last - 1);
        return f - float(i);
    };
    int xi, yi;
    float tx = cell(x, xi), ty = cell(y, yi);
    int zi = int(std::upper_bound(m_zNodes.begin(), m_zNodes.end(), z) - m_zNodes.begin()) - 1;
    zi = std::clamp(zi, 0, last - 1);
    float tz = std::clamp((z - m_zNodes[zi]) / (m_zNodes[zi + 1] - m_zNodes[zi]), 0.f, 1.f);

    auto at = [&](int dz, int dy, int dx, int c) {
        std::size_t idx = (((std::size_t(l) * m_res + zi + dz) * m_res + yi + dy) * m_res + xi + dx) * 3 + c;
        return m_coeffs[idx];
    };
    float out[3];
    for (int c = 0; c < 3; ++c) {
        auto lx = [&](int dz, int dy) { return lerp(tx, at(dz, dy, 0, c), at(dz, dy, 1, c)); };
        float z0 = lerp(ty, lx(0, 0), lx(0, 1)), z1 = lerp(ty, lx(1, 0), lx(1, 1));
        out[c] = lerp(tz, z0, z1);
    }
    return {out[0], out[1], out[2]};
}

} // namespace effigi
