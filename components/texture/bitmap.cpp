// texture "bitmap" — an image file as a texture, looked up at the surface's (u, v).
//
// Mitsuba 3 semantics: texel (0, 0) is the top-left pixel of the file; u runs along
// the rows, v down the columns; a lookup at uv reads pixel coordinate uv·(W, H) − ½
// (texel centres at half-integers). 8-bit images (PNG, JPEG) are sRGB-decoded to
// linear unless `raw`; EXR/HDR are linear already. An alpha channel is dropped.
// RGB texels are upsampled to spectra (Jakob & Hanika 2019) once at load time, and a
// bilinear lookup blends the four upsampled spectra (upsampling is not linear, so
// blending RGB first would differ, as Mitsuba notes). Texels in [0, 1] use the bounded
// fit, so a reflectance never exceeds 1 at any wavelength; brighter (HDR) texels the
// unbounded one. Scalar readings (evalFloat: roughness, bump heights) are the texel's
// value for one channel and its luminance for RGB, as Mitsuba's eval_1.
//
// Parameters:
//   filename     string  (required)  image file, relative to the scene file
//   filter_type  string  bilinear    bilinear | nearest
//   wrap_mode    string  repeat      repeat | mirror | clamp (outside [0, 1])
//   raw          bool    false       no sRGB decoding (normal maps, data)
//   to_uv        transform           affine map applied to (u, v) first
//   format       string  auto        storage precision in Mitsuba; effigi stores float
//
// Reference: Mitsuba 3 `bitmap`; W. Jakob, J. Hanika, "A Low-Dimensional Function Space
// for Efficient Spectral Upsampling", Computer Graphics Forum 38(2), 2019.
#include "texture_common.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/interfaces/itexture_resolution.hpp"
#include "effigi/render/bitmap.hpp"
#include "effigi/spectral/colorspace.hpp"

#include <vector>

namespace effigi {
namespace {

enum class WrapMode { Repeat, Mirror, Clamp };

/// ITextureResolution: the projector emitter takes its aspect ratio from the image.
class BitmapTexture final : public Implements<ITexture, ITextureResolution> {
public:
    static Schema schema() {
        Schema s("texture", "bitmap", "Image file texture (PNG, JPEG, EXR, HDR, ...) with bilinear or nearest lookup.");
        s.cite("Mitsuba 3 bitmap; Jakob & Hanika, Computer Graphics Forum 38(2), 2019");
        s.optional("filename", ParamType::String, "Image file, relative to the scene file").isRequired();
        s.string("filter_type", "bilinear", "Texel interpolation: bilinear or nearest").oneOf({"bilinear", "nearest"});
        s.string("wrap_mode", "repeat", "Lookups outside [0, 1]: repeat, mirror or clamp")
            .oneOf({"repeat", "mirror", "clamp"});
        s.boolean("raw", false, "Use the stored values as they are (no sRGB decoding): normal maps, data");
        s.transform("to_uv", "Affine transform applied to the texture coordinates before the lookup");
        s.string("format", "auto", "Mitsuba's storage precision; effigi always stores float (uint8 is refused, as in "
                                   "Mitsuba's spectral variants)")
            .oneOf({"auto", "variant", "float16", "uint8"});
        s.ignored("accel", "GPU texture hardware in Mitsuba; lookups here are always exact float arithmetic");
        // effigi-conform (conformance/texture_suite.cpp): the small image of the unit tests
        // (saturated primaries, black, white), every filter and wrap mode, uv shifted and
        // tiled, and an HDR image.
        const std::string img = "tests/data/textures/grid.png";
        s.addConformance({"default", {{"filename", img}}});
        s.addConformance({"nearest clamp", {{"filename", img}, {"filter_type", std::string("nearest")},
                                            {"wrap_mode", std::string("clamp")}}});
        s.addConformance({"bilinear mirror raw", {{"filename", img}, {"wrap_mode", std::string("mirror")}, {"raw", true}}});
        s.addConformance({"nearest mirror shifted tiled", {{"filename", img}, {"filter_type", std::string("nearest")},
                                                          {"wrap_mode", std::string("mirror")},
                                                          {"to_uv", Transform::translate({0.37f, 0.11f, 0.f}) *
                                                                        Transform::scale({2.f, 2.f, 1.f})}}});
        s.addConformance({"hdr", {{"filename", std::string("tests/data/emitters/sky.exr")}}});
        return s;
    }

    explicit BitmapTexture(const Properties& p)
        : m_bilinear(p.getString("filter_type") == "bilinear"), m_uv(UVTransform::read(p, "to_uv")) {
        const std::string& wrap = p.getString("wrap_mode");
        m_wrap = wrap == "mirror" ? WrapMode::Mirror : wrap == "clamp" ? WrapMode::Clamp : WrapMode::Repeat;
        if (p.getString("format") == "uint8")
            failAt(p.whereOf("format"), "{}: format 'uint8' cannot hold spectral texels (Mitsuba refuses it in "
                                        "spectral variants too); use 'auto' or 'float16'", p.describe());
        Bitmap bmp;
        try {
            bmp = Bitmap::load(p.getPath("filename"));
        } catch (const Error& e) {
            failAt(p.whereOf("filename"), "{}: {}", p.describe(), e.what());
        }
        if (bmp.channels() > 4)
            failAt(p.whereOf("filename"), "{}: {}: {} channels; 1 (Y), 2 (YA), 3 (RGB) or 4 (RGBA) are supported",
                   p.describe(), bmp.filename(), bmp.channels());
        if (!p.getBool("raw")) bmp.convertToLinear();
        load(bmp);
    }

    SampledSpectrum eval(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override {
        Point2f uv = m_uv.apply(si.uv);
        if (m_channels == 1) return SampledSpectrum(lookup1(uv));
        return interpolate(uv, [&](int x, int y) { return m_spectral[index(x, y)].eval(lambda); });
    }

    float evalFloat(const SurfaceInteraction& si) const override { return lookup1(m_uv.apply(si.uv)); }

    Vector3f evalVector(const SurfaceInteraction& si) const override {
        Point2f uv = m_uv.apply(si.uv);
        if (m_channels == 1) return Vector3f(lookup1(uv));
        return interpolate(uv, [this](int x, int y) { return m_rgb[index(x, y)]; });
    }

    /// Analytic derivative of the bilinear interpolant (zero almost everywhere for
    /// nearest lookups): d/dx of the blend in texel units, times the resolution, then
    /// pulled back through to_uv.
    Vector2f evalFloatGradient(const SurfaceInteraction& si) const override {
        if (!m_bilinear) return Vector2f(0.f);
        Texel t = bilinear(m_uv.apply(si.uv));
        float f00 = m_scalar[index(t.x0, t.y0)], f10 = m_scalar[index(t.x1, t.y0)];
        float f01 = m_scalar[index(t.x0, t.y1)], f11 = m_scalar[index(t.x1, t.y1)];
        float dx = (1.f - t.wy) * (f10 - f00) + t.wy * (f11 - f01);
        float dy = (1.f - t.wx) * (f01 - f00) + t.wx * (f11 - f10);
        return m_uv.pullBack(Vector2f(dx * float(m_width), dy * float(m_height)));
    }

    float maxValue() const override { return m_max; }
    float mean() const override { return m_mean; }
    Vector2i resolution() const override { return {m_width, m_height}; }

private:
    struct Texel {
        int x0, x1, y0, y1;
        float wx, wy;  // weights of x1 and y1
    };

    void load(const Bitmap& bmp) {
        m_width = bmp.width();
        m_height = bmp.height();
        // Colour channels in file order, alpha dropped.
        std::vector<int> keep;
        for (int c = 0; c < bmp.channels(); ++c)
            if (c != bmp.alphaChannel()) keep.push_back(c);
        if (keep.size() == 2) keep.pop_back();  // alpha not named: YA as Y
        m_channels = keep.size() >= 3 ? 3 : 1;
        const std::size_t n = std::size_t(m_width) * std::size_t(m_height);
        m_scalar.resize(n);
        const Vector3f luma = RGBColorSpace::get(ColorSpaceId::SRGB).luminanceWeights();
        const RGBToSpectrumTable& table = RGBToSpectrumTable::sRGB();
        if (m_channels == 3) {
            m_rgb.resize(n);
            m_spectral.resize(n);
        }
        double sum = 0.0;
        m_max = 0.f;
        for (int y = 0; y < m_height; ++y)
            for (int x = 0; x < m_width; ++x) {
                std::size_t i = index(x, y);
                const float* px = bmp.pixel(x, y);
                if (m_channels == 1) {
                    m_scalar[i] = px[keep[0]];
                    m_max = std::max(m_max, m_scalar[i]);
                } else {
                    m_rgb[i] = Vector3f(px[keep[0]], px[keep[1]], px[keep[2]]);
                    m_scalar[i] = dot(luma, m_rgb[i]);
                    float top = 0.f;
                    m_spectral[i] = SpectralTexel::fromRGB(table, m_rgb[i], &top);
                    m_max = std::max(m_max, top);
                }
                sum += m_scalar[i];
            }
        m_mean = float(sum / double(n));
    }

    std::size_t index(int x, int y) const { return std::size_t(y) * std::size_t(m_width) + std::size_t(x); }

    /// Integer texel index into [0, n) under the wrap mode.
    int wrap(long long i, int n) const {
        switch (m_wrap) {
        case WrapMode::Clamp: return int(std::clamp<long long>(i, 0, n - 1));
        case WrapMode::Repeat: {
            long long r = i % n;
            return int(r < 0 ? r + n : r);
        }
        case WrapMode::Mirror: {
            long long r = i % (2LL * n);
            if (r < 0) r += 2LL * n;
            return int(r < n ? r : 2LL * n - 1 - r);
        }
        }
        return 0;
    }
    /// floor(p) reduced to a range where it fits an integer: the wrap modes are periodic
    /// (repeat: n, mirror: 2n) and clamp saturates, so nothing changes but huge
    /// coordinates no longer overflow. NaN coordinates read texel 0.
    long long reduce(float p, int n) const {
        double f = std::isfinite(p) ? std::floor(double(p)) : 0.0;
        if (m_wrap == WrapMode::Clamp) return (long long)std::clamp(f, -1.0, double(n));
        double period = m_wrap == WrapMode::Mirror ? 2.0 * n : double(n);
        return (long long)(f - period * std::floor(f / period));
    }

    Texel nearest(const Point2f& uv) const {
        int x = wrap(reduce(uv.x * float(m_width), m_width), m_width);
        int y = wrap(reduce(uv.y * float(m_height), m_height), m_height);
        return {x, x, y, y, 0.f, 0.f};
    }
    Texel bilinear(const Point2f& uv) const {
        float px = uv.x * float(m_width) - 0.5f, py = uv.y * float(m_height) - 0.5f;
        float wx = std::isfinite(px) ? px - std::floor(px) : 0.f, wy = std::isfinite(py) ? py - std::floor(py) : 0.f;
        long long ix = reduce(px, m_width), iy = reduce(py, m_height);
        return {wrap(ix, m_width), wrap(ix + 1, m_width), wrap(iy, m_height), wrap(iy + 1, m_height), wx, wy};
    }

    template <typename Fetch>
    auto interpolate(const Point2f& uv, Fetch fetch) const -> decltype(fetch(0, 0)) {
        if (!m_bilinear) {
            Texel t = nearest(uv);
            return fetch(t.x0, t.y0);
        }
        Texel t = bilinear(uv);
        auto top = fetch(t.x0, t.y0) * (1.f - t.wx) + fetch(t.x1, t.y0) * t.wx;
        auto bottom = fetch(t.x0, t.y1) * (1.f - t.wx) + fetch(t.x1, t.y1) * t.wx;
        return top * (1.f - t.wy) + bottom * t.wy;
    }
    float lookup1(const Point2f& uv) const {
        return interpolate(uv, [this](int x, int y) { return m_scalar[index(x, y)]; });
    }

    bool m_bilinear;
    UVTransform m_uv;
    WrapMode m_wrap = WrapMode::Repeat;
    int m_width = 0, m_height = 0, m_channels = 1;
    std::vector<float> m_scalar;            // evalFloat per texel: the value or its luminance
    std::vector<Vector3f> m_rgb;            // RGB textures: linear (or raw) texels
    std::vector<SpectralTexel> m_spectral;  // RGB textures: the same, upsampled
    float m_max = 0.f, m_mean = 0.f;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::BitmapTexture)
