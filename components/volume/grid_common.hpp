#pragma once
// The dense voxel grid behind `gridvolume` (Mitsuba's .vol files) and `vdbvolume`
// (OpenVDB files), with Mitsuba 3's gridvolume semantics:
//  - the grid fills the unit cube [0, 1]³, carried into the world by `to_world` (with
//    `use_grid_bbox`, the file's own bounding box is mapped onto the unit cube first);
//  - voxel (i, j, k) of an n_x × n_y × n_z grid is centred at ((i + ½)/n_x, …), as in a
//    GPU 3-D texture (Dr.Jit's Texture3f, which Mitsuba uses): "trilinear" blends the 8
//    voxels around a point, "nearest" takes the voxel the point lies in;
//  - outside the unit cube, `wrap_mode` clamps to the edge voxels (default), repeats or
//    mirrors the grid;
//  - 1 channel: a value, the same at every wavelength; 3 channels: a linear RGB colour,
//    upsampled to a spectrum per voxel at load time (Jakob & Hanika 2019, as every RGB
//    input of effigi: within [0, 1] the bounded fit, so an albedo stays ≤ 1; brighter
//    values fitted at half their largest channel and scaled back), the spectra of the 8
//    voxels blended after evaluation (upsampling is not linear). `raw` keeps the RGB
//    as data: eval then gives its luminance at every wavelength (Mitsuba refuses a
//    spectral lookup of raw RGB), as evalFloat always does for RGB.
// Bounds (IVolume::maxIn): each voxel's largest value over all wavelengths, the largest
// over the voxels whose support meets the box — the voxel itself for "nearest", the
// voxels within one voxel spacing of the box's centres for "trilinear" (their weights
// are ≥ 0 and sum to 1, so the blend lies below the largest of them).
// Data must be finite and ≥ 0 (densities and albedos): anything else is refused.
#include "effigi/core/properties.hpp"
#include "effigi/core/schema.hpp"
#include "effigi/interfaces/ivolume.hpp"
#include "effigi/render/vol_reader.hpp"
#include "effigi/spectral/colorspace.hpp"
#include "effigi/spectral/spectral_texel.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace effigi {

/// The parameters both grid components take besides the file.
inline void addGridParams(Schema& s) {
    s.string("filter_type", "trilinear", "Interpolation between voxel centres: trilinear or nearest")
        .oneOf({"trilinear", "nearest"});
    s.string("wrap_mode", "clamp", "Lookups outside the unit cube: clamp (edge voxels), repeat or mirror")
        .oneOf({"clamp", "repeat", "mirror"});
    s.boolean("raw", false, "Keep 3-channel data as numbers (no spectral upsampling): eval gives the luminance");
    s.transform("to_world", "Places the unit cube [0,1]^3 that the grid fills in the world");
    s.boolean("use_grid_bbox", false, "Map the file's own bounding box onto the unit cube before to_world");
    s.ignored("accel", "GPU texture hardware in Mitsuba; lookups here are exact float arithmetic");
    s.ignored("max_value", "a bound stated by the user; effigi computes true bounds from the data");
}

class GridVolumeBase : public Implements<IVolume> {
public:
    SampledSpectrum eval(const Point3f& p, const SampledWavelengths& lambda) const override {
        const Point3f u = toLocal(p);
        if (m_texels.empty()) return SampledSpectrum(lookup(u, [this](std::size_t i) { return m_scalar[i]; }));
        return lookup(u, [&](std::size_t i) { return m_texels[i].eval(lambda); });
    }
    float evalFloat(const Point3f& p) const override {
        return lookup(toLocal(p), [this](std::size_t i) { return m_scalar[i]; });
    }
    float maxValue() const override { return m_max; }
    float maxIn(const BBox3f& box) const override;
    BBox3f bbox() const override { return m_bbox; }
    Transform toWorld() const override { return m_toWorld; }
    glm::ivec3 resolution() const override { return m_n; }

protected:
    /// Take the grid read from `file` (named in messages; the scene line is that of
    /// `filename`), with the options of addGridParams.
    void setGrid(VolGrid g, const Properties& p, const std::string& file);

private:
    enum class Wrap { Clamp, Repeat, Mirror };

    Point3f toLocal(const Point3f& p) const { return Point3f(m_toLocal * glm::vec4(p, 1.f)); }
    std::size_t index(int x, int y, int z) const {
        return (std::size_t(z) * std::size_t(m_n.y) + std::size_t(y)) * std::size_t(m_n.x) + std::size_t(x);
    }
    /// A voxel index (any integer) into [0, n) under the wrap mode.
    int wrap(long long i, int n) const {
        if (m_wrap == Wrap::Clamp) return int(std::clamp<long long>(i, 0, n - 1));
        const long long period = m_wrap == Wrap::Mirror ? 2LL * n : n;
        long long r = i % period;
        if (r < 0) r += period;
        return int(r < n ? r : period - 1 - r);
    }
    /// floor(x) brought into a range where it fits an integer without changing what
    /// wrap() makes of it; a NaN coordinate reads voxel 0.
    long long reduce(double x, int n) const {
        const double f = std::isfinite(x) ? std::floor(x) : 0.0;
        if (m_wrap == Wrap::Clamp) return (long long)std::clamp(f, -1.0, double(n));
        const double period = m_wrap == Wrap::Mirror ? 2.0 * n : double(n);
        return (long long)(f - period * std::floor(f / period));
    }

    template <typename Fetch>
    auto lookup(const Point3f& u, Fetch fetch) const -> decltype(fetch(0)) {
        if (!m_trilinear)
            return fetch(index(wrap(reduce(double(u.x) * m_n.x, m_n.x), m_n.x), wrap(reduce(double(u.y) * m_n.y, m_n.y), m_n.y),
                               wrap(reduce(double(u.z) * m_n.z, m_n.z), m_n.z)));
        int i0[3], i1[3];
        float w[3];  // weight of the upper neighbour along each axis
        for (int a = 0; a < 3; ++a) {
            const double x = double(u[a]) * m_n[a] - 0.5;
            const long long f = reduce(x, m_n[a]);
            w[a] = std::isfinite(x) ? float(x - std::floor(x)) : 0.f;
            i0[a] = wrap(f, m_n[a]);
            i1[a] = wrap(f + 1, m_n[a]);
        }
        auto row = [&](int y, int z) { return fetch(index(i0[0], y, z)) * (1.f - w[0]) + fetch(index(i1[0], y, z)) * w[0]; };
        auto plane = [&](int z) { return row(i0[1], z) * (1.f - w[1]) + row(i1[1], z) * w[1]; };
        return plane(i0[2]) * (1.f - w[2]) + plane(i1[2]) * w[2];
    }

    glm::ivec3 m_n{1, 1, 1};
    bool m_trilinear = true;
    Wrap m_wrap = Wrap::Clamp;
    std::vector<float> m_scalar;             // per voxel: the value, or the RGB's luminance
    std::vector<SpectralTexel> m_texels;     // RGB grids (not raw): the upsampled voxels
    std::vector<float> m_bound;              // per voxel: the largest of eval and evalFloat
    Transform m_toWorld;
    glm::mat4 m_toLocal{1.f};
    BBox3f m_bbox;
    float m_max = 0.f;
};

inline void GridVolumeBase::setGrid(VolGrid g, const Properties& p, const std::string& file) {
    const SourceLocation& where = p.whereOf("filename");
    if (g.channels != 1 && g.channels != 3)
        failAt(where, "{}: {} has {} channels; a grid volume takes 1 (a value) or 3 (RGB)", p.describe(), file,
               g.channels);
    for (std::size_t i = 0; i < g.data.size(); ++i)
        if (!(g.data[i] >= 0.f) || !std::isfinite(g.data[i])) {
            const std::size_t v = i / g.channels;
            failAt(where, "{}: {}: value {} at voxel ({}, {}, {}) channel {}; volume data must be finite and >= 0",
                   p.describe(), file, g.data[i], v % g.size[0], (v / g.size[0]) % g.size[1],
                   v / (std::size_t(g.size[0]) * g.size[1]), i % g.channels);
        }
    m_n = glm::ivec3(int(g.size[0]), int(g.size[1]), int(g.size[2]));
    m_trilinear = p.getString("filter_type") == "trilinear";
    const std::string& wrapMode = p.getString("wrap_mode");
    m_wrap = wrapMode == "repeat" ? Wrap::Repeat : wrapMode == "mirror" ? Wrap::Mirror : Wrap::Clamp;

    const std::size_t n = g.data.size() / g.channels;
    m_scalar.resize(n);
    m_bound.resize(n);
    const bool spectral = g.channels == 3 && !p.getBool("raw");
    if (spectral) m_texels.resize(n);
    const Vector3f luma = RGBColorSpace::get(ColorSpaceId::SRGB).luminanceWeights();
    for (std::size_t i = 0; i < n; ++i) {
        if (g.channels == 1) {
            m_scalar[i] = m_bound[i] = g.data[i];
            continue;
        }
        const Vector3f rgb(g.data[3 * i], g.data[3 * i + 1], g.data[3 * i + 2]);
        m_scalar[i] = m_bound[i] = std::max(0.f, dot(luma, rgb));
        if (spectral) {
            float top = 0.f;
            m_texels[i] = SpectralTexel::fromRGB(RGBToSpectrumTable::sRGB(), rgb, &top);
            m_bound[i] = std::max(m_bound[i], top);
        }
    }
    m_max = n ? *std::max_element(m_bound.begin(), m_bound.end()) : 0.f;

    // Unit cube -> (the file's box ->) world. In double: the inverse is what lookups use.
    glm::dmat4 toWorld(p.getTransform("to_world").matrix());
    if (p.getBool("use_grid_bbox")) {
        const Vector3f e = g.bbox.extents();
        if (!(e.x > 0.f && e.y > 0.f && e.z > 0.f) || !isFinite(e) || !isFinite(g.bbox.min))
            failAt(p.whereOf("use_grid_bbox"), "{}: {}: the file's bounding box ({}, {}, {}) - ({}, {}, {}) is empty or "
                   "not finite; use_grid_bbox needs a box of positive size", p.describe(), file, g.bbox.min.x,
                   g.bbox.min.y, g.bbox.min.z, g.bbox.max.x, g.bbox.max.y, g.bbox.max.z);
        glm::dmat4 box(1.0);
        for (int a = 0; a < 3; ++a) {
            box[a][a] = double(e[a]);
            box[3][a] = double(g.bbox.min[a]);
        }
        toWorld = toWorld * box;
    }
    const double det = glm::determinant(glm::dmat3(toWorld));
    if (toWorld[0][3] != 0.0 || toWorld[1][3] != 0.0 || toWorld[2][3] != 0.0 || toWorld[3][3] != 1.0 ||
        !(std::abs(det) > 0.0) || !std::isfinite(det) || !std::isfinite(1.0 / det))
        failAt(p.whereOf("to_world"), "{}: parameter 'to_world' must be a finite, invertible affine map", p.describe());
    m_toWorld = Transform(glm::mat4(toWorld), glm::mat4(glm::inverse(toWorld)));
    m_toLocal = m_toWorld.inverseMatrix();
    for (int c = 0; c < 8; ++c) m_bbox.expand(m_toWorld.point(Point3f(c & 1, (c >> 1) & 1, (c >> 2) & 1)));
}

inline float GridVolumeBase::maxIn(const BBox3f& box) const {
    if (!box.valid()) return 0.f;
    // The box in unit-cube coordinates (an enclosing box of its image, in double).
    glm::dvec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
    const glm::dmat4 toLocal(m_toLocal);
    for (int c = 0; c < 8; ++c) {
        const glm::dvec3 q(c & 1 ? box.max.x : box.min.x, c & 2 ? box.max.y : box.min.y, c & 4 ? box.max.z : box.min.z);
        const glm::dvec3 l(toLocal * glm::dvec4(q, 1.0));
        lo = glm::min(lo, l);
        hi = glm::max(hi, l);
    }
    // Voxels whose support meets it, per axis: a slack of 1e-4 voxel covers the float
    // rounding of lookups, which map points to the unit cube in float.
    std::vector<int> axes[3];
    for (int a = 0; a < 3; ++a) {
        const int n = m_n[a];
        const double shift = m_trilinear ? 0.5 : 0.0, slack = 1e-4;
        const double first = std::floor(lo[a] * n - shift - slack), last = std::floor(hi[a] * n - shift + slack) +
                                                                         (m_trilinear ? 1.0 : 0.0);
        if (!std::isfinite(first) || !std::isfinite(last)) return m_max;
        const double period = m_wrap == Wrap::Mirror ? 2.0 * n : double(n);
        if (m_wrap != Wrap::Clamp && last - first + 1.0 >= period) {
            for (int i = 0; i < n; ++i) axes[a].push_back(i);
            continue;
        }
        const long long from = reduce(first, n), count = (long long)(last - first);
        if (m_wrap == Wrap::Clamp)
            for (long long i = std::clamp<long long>((long long)std::max(first, -1.0), 0, n - 1),
                           end = std::clamp<long long>((long long)std::min(last, double(n)), 0, n - 1);
                 i <= end; ++i)
                axes[a].push_back(int(i));
        else
            for (long long i = 0; i <= count; ++i) axes[a].push_back(wrap(from + i, n));
    }
    float m = 0.f;
    for (int z : axes[2])
        for (int y : axes[1])
            for (int x : axes[0]) m = std::max(m, m_bound[index(x, y, z)]);
    return m;
}

} // namespace effigi
