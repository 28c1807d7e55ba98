/*
 * film "hdrfilm" — a high-dynamic-range film: accumulates filtered samples and writes
 * OpenEXR (plus an 8-bit sRGB PNG preview beside it).
 *
 * Each pixel stores its channels' filter-weighted sums and the weight sum; develop()
 * divides them (the weighted average of Mitchell & Netravali 1988 / pbrt's film,
 * a 0 weight gives 0). Renderers splat spectral radiance as CIE XYZ into channels
 * "X","Y","Z"; developing converts them to linear sRGB (IEC 61966-2-1) for pixel_format
 * rgb/rgba, keeps XYZ for xyz and Y for luminance. Any further channels (AOVs, e.g.
 * "albedo.R") are written as they are, under their names.
 *
 * Parameters (Mitsuba 3 compatible):
 *   width, height          int, 768 x 576        full film size in pixels
 *   crop_offset_x/_y       int, 0                crop window origin
 *   crop_width/_height     int, full size        crop window size; only the crop is
 *                                                rendered and written (IFilm::cropOffset)
 *   pixel_format           rgb | rgba | xyz | luminance
 *   component_format       float16 | float32     EXR channel type
 *   file_format            openexr
 *   png                    bool, true            also write <name>.png beside <name>.exr
 *   exposure               float, 0              PNG exposure in stops (EXR is never scaled)
 *   rfilter                nested filter, default gaussian
 * Reference: D. P. Mitchell, A. N. Netravali, "Reconstruction Filters in Computer
 * Graphics", SIGGRAPH 1988; OpenEXR file layout, https://openexr.com.
 */
#include "hdrfilm_io.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/ifilter.hpp"

#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <mutex>
#include <set>

namespace effigi {
namespace {

enum class PixelFormat { RGB, RGBA, XYZ, Luminance };

const std::vector<std::string> PixelFormats{"rgb", "rgba", "xyz", "luminance"};
const std::vector<std::string> ComponentFormats{"float16", "float32"};
const std::vector<std::string> FileFormats{"openexr"};

/// Index of a string parameter's value among its choices, or an error listing them.
std::size_t choose(const Properties& p, const std::string& name, const std::vector<std::string>& choices) {
    const std::string& v = p.getString(name);
    auto it = std::find(choices.begin(), choices.end(), v);
    if (it == choices.end())
        failAt(p.whereOf(name), "{}: '{}' must be one of {}, got '{}'", p.describe(), name,
               fmt::join(choices, ", "), v);
    return std::size_t(it - choices.begin());
}

class HDRFilm final : public Implements<IFilm> {
public:
    static Schema schema() {
        Schema s("film", "hdrfilm", "High dynamic range film: filtered accumulation, OpenEXR output with a PNG preview.");
        s.cite("D. P. Mitchell, A. N. Netravali, Reconstruction Filters in Computer Graphics, SIGGRAPH 1988");
        s.integer("width", 768, "Film width").withUnit("pixels").range(1, 32768);
        s.integer("height", 576, "Film height").withUnit("pixels").range(1, 32768);
        s.integer("crop_offset_x", 0, "Left edge of the crop window").withUnit("pixels").atLeast(0);
        s.integer("crop_offset_y", 0, "Top edge of the crop window").withUnit("pixels").atLeast(0);
        s.optional("crop_width", ParamType::Int, "Crop window width (default: the rest of the film)").atLeast(1);
        s.optional("crop_height", ParamType::Int, "Crop window height (default: the rest of the film)").atLeast(1);
        s.string("pixel_format", "rgb", "Colour channels written: rgb, rgba, xyz or luminance").oneOf(PixelFormats);
        s.string("component_format", "float16", "EXR channel type: float16 or float32").oneOf(ComponentFormats);
        s.string("file_format", "openexr", "Output file format").oneOf(FileFormats);
        s.boolean("png", true, "Also write an 8-bit sRGB PNG beside the EXR");
        s.real("exposure", 0.0, "Exposure of the PNG (scale 2^exposure)").withUnit("stops").range(-64.0, 64.0);
        s.child("rfilter", "rfilter", "Reconstruction filter (default: gaussian)");
        return s;
    }

    explicit HDRFilm(const Properties& p) {
        m_fullSize = Vector2i(int(p.getInt("width")), int(p.getInt("height")));
        if (m_fullSize.x < 1 || m_fullSize.y < 1 || m_fullSize.x > 32768 || m_fullSize.y > 32768)
            failAt(p.whereOf("width"), "{}: film size {}x{} is not in [1, 32768]", p.describe(), m_fullSize.x,
                   m_fullSize.y);
        m_cropOffset = Point2i(int(std::clamp<std::int64_t>(p.getInt("crop_offset_x"), -1, 1 << 20)),
                               int(std::clamp<std::int64_t>(p.getInt("crop_offset_y"), -1, 1 << 20)));
        checkCrop(p, "crop_offset_x", m_cropOffset.x, 0, m_fullSize.x - 1);
        checkCrop(p, "crop_offset_y", m_cropOffset.y, 0, m_fullSize.y - 1);
        m_size = m_fullSize - m_cropOffset;
        if (p.has("crop_width")) m_size.x = int(std::clamp<std::int64_t>(p.getInt("crop_width"), 0, 1 << 20));
        if (p.has("crop_height")) m_size.y = int(std::clamp<std::int64_t>(p.getInt("crop_height"), 0, 1 << 20));
        checkCrop(p, "crop_width", m_size.x, 1, m_fullSize.x - m_cropOffset.x);
        checkCrop(p, "crop_height", m_size.y, 1, m_fullSize.y - m_cropOffset.y);

        m_format = PixelFormat(choose(p, "pixel_format", PixelFormats));
        m_half = choose(p, "component_format", ComponentFormats) == 0;
        choose(p, "file_format", FileFormats);
        m_png = p.getBool("png");
        m_exposure = p.getFloat("exposure");
        if (!std::isfinite(m_exposure))
            failAt(p.whereOf("exposure"), "{}: 'exposure' must be finite", p.describe());

        m_filter = p.get<IFilter>("rfilter");
        if (!m_filter) {
            Properties fp("rfilter", "gaussian", p.where());
            m_filter = effigi::query<IFilter>(Registry::instance().create("rfilter", "gaussian", fp));
            if (!m_filter) failAt(p.where(), "{}: the default filter 'gaussian' is not an rfilter", p.describe());
        }
        m_table = FilterTable(*m_filter);
    }

    Vector2i size() const override { return m_size; }
    Vector2i fullSize() const override { return m_fullSize; }
    Point2i cropOffset() const override { return m_cropOffset; }
    const IFilter& filter() const override { return *m_filter; }

    void prepare(const std::vector<std::string>& channels) override {
        std::set<std::string> seen;
        for (const std::string& c : channels)
            if (c.empty() || !seen.insert(c).second)
                fail("film: channel names must be unique and non-empty (got '{}')", fmt::join(channels, ", "));
        const bool xyz = channels.size() >= 3 && channels[0] == "X" && channels[1] == "Y" && channels[2] == "Z";
        std::vector<std::string> out;
        if (xyz) {
            switch (m_format) {
            case PixelFormat::RGB: out = {"R", "G", "B"}; break;
            case PixelFormat::RGBA: out = {"R", "G", "B", "A"}; break;
            case PixelFormat::XYZ: out = {"X", "Y", "Z"}; break;
            case PixelFormat::Luminance: out = {"Y"}; break;
            }
        }
        out.insert(out.end(), channels.begin() + (xyz ? 3 : 0), channels.end());
        seen.clear();
        for (const std::string& c : out)
            if (!seen.insert(c).second) fail("film: AOV channel '{}' clashes with a colour channel", c);

        std::lock_guard lock(m_mutex);
        m_xyz = xyz;
        m_channels = channels;
        m_outputNames = std::move(out);
        m_data.assign(std::size_t(m_size.x) * std::size_t(m_size.y) * (channels.size() + 1), 0.f);
    }

    ImageBlock createBlock(Point2i offset, Vector2i size) const override {
        return ImageBlock(offset, size, int(m_channels.size()), &m_table);
    }

    void put(const ImageBlock& block) override {
        const int n = block.stride();
        if (block.channels() != int(m_channels.size()))
            fail("film: block has {} channels, the film was prepared with {}", block.channels(), m_channels.size());
        // The block's stored rectangle (border included), clipped to the crop window.
        const Point2i lo = block.offset() - block.border();
        const Point2i hi = lo + block.storageSize();
        const int x0 = std::max(lo.x, 0), x1 = std::min(hi.x, m_size.x);
        const int y0 = std::max(lo.y, 0), y1 = std::min(hi.y, m_size.y);
        if (x0 >= x1 || y0 >= y1) return;
        const std::size_t count = std::size_t(x1 - x0) * std::size_t(n);
        std::lock_guard lock(m_mutex);
        for (int y = y0; y < y1; ++y) {
            const float* src = block.pixel(x0, y);
            float* dst = m_data.data() + (std::size_t(y) * std::size_t(m_size.x) + std::size_t(x0)) * std::size_t(n);
            for (std::size_t k = 0; k < count; ++k) dst[k] += src[k];
        }
    }

    Image develop() const override {
        std::lock_guard lock(m_mutex);
        Image img;
        img.width = m_size.x;
        img.height = m_size.y;
        img.channelNames = m_outputNames;
        const std::size_t in = m_channels.size(), stride = in + 1, out = m_outputNames.size();
        const std::size_t pixels = std::size_t(m_size.x) * std::size_t(m_size.y);
        if (m_data.size() != pixels * stride) return img;  // not prepared
        img.pixels.resize(pixels * out);
        for (std::size_t i = 0; i < pixels; ++i) {
            const float* src = m_data.data() + i * stride;
            float* dst = img.pixels.data() + i * out;
            const float w = src[in];
            const float inv = w != 0.f ? 1.f / w : 0.f;
            std::size_t first = 0, o = 0;
            if (m_xyz) {
                const Vector3f xyz = Vector3f(src[0], src[1], src[2]) * inv;
                switch (m_format) {
                case PixelFormat::RGB:
                case PixelFormat::RGBA: {
                    const Vector3f rgb = xyzToLinearSRGB(xyz);
                    dst[o++] = rgb.x, dst[o++] = rgb.y, dst[o++] = rgb.z;
                    if (m_format == PixelFormat::RGBA) dst[o++] = 1.f;
                    break;
                }
                case PixelFormat::XYZ: dst[o++] = xyz.x, dst[o++] = xyz.y, dst[o++] = xyz.z; break;
                case PixelFormat::Luminance: dst[o++] = xyz.y; break;
                }
                first = 3;
            }
            for (std::size_t c = first; c < in; ++c) dst[o++] = src[c] * inv;
        }
        return img;
    }

    std::vector<std::filesystem::path> write(const std::filesystem::path& path, const FilmMetadata& meta) const override {
        std::filesystem::path main = path;
        std::string ext = main.extension().string();
        std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        if (ext.empty()) main += ".exr", ext = ".exr";  // file_format decides, as in Mitsuba
        if (ext != ".exr" && ext != ".png")
            fail("cannot write {}: unsupported extension '{}' (hdrfilm writes .exr and .png)", path.string(), ext);

        const Image img = develop();
        std::vector<std::filesystem::path> written;
        if (ext == ".exr") {
            const bool rgb = m_xyz && (m_format == PixelFormat::RGB || m_format == PixelFormat::RGBA);
            hdrfilm_io::writeExr(main, img, m_half, rgb, meta);
            written.push_back(main);
            if (!m_png) return written;
            main.replace_extension(".png");
        }
        writePreview(main, img, meta);
        written.push_back(main);
        return written;
    }

private:
    static void checkCrop(const Properties& p, const char* name, int v, int lo, int hi) {
        if (v < lo || v > hi)
            failAt(p.whereOf(name), "{}: '{}' = {} puts the crop window outside the {}x{} film (allowed: {}..{})",
                   p.describe(), name, v, p.getInt("width"), p.getInt("height"), lo, hi);
    }

    /// The PNG shows the colour: linear sRGB (XYZ converted for pixel_format xyz), grey
    /// for luminance; without XYZ the first three channels, or the first as grey.
    void writePreview(const std::filesystem::path& path, const Image& img, const FilmMetadata& meta) const {
        const int nc = m_xyz ? (m_format == PixelFormat::Luminance ? 1 : 3)
                             : (img.channels() >= 3 ? 3 : std::min(img.channels(), 1));
        const bool fromXYZ = m_xyz && m_format == PixelFormat::XYZ;
        std::vector<float> linear(std::size_t(img.width) * std::size_t(img.height) * std::size_t(nc));
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                float* d = linear.data() + (std::size_t(y) * std::size_t(img.width) + std::size_t(x)) * std::size_t(nc);
                if (nc == 3) {
                    Vector3f v(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2));
                    if (fromXYZ) v = xyzToLinearSRGB(v);
                    d[0] = v.x, d[1] = v.y, d[2] = v.z;
                } else if (nc == 1) {
                    d[0] = img.at(x, y, 0);
                }
            }
        hdrfilm_io::writePng(path, img.width, img.height, nc, linear, m_exposure, meta);
    }

    Vector2i m_fullSize{0}, m_size{0};
    Point2i m_cropOffset{0};
    PixelFormat m_format = PixelFormat::RGB;
    bool m_half = true, m_png = true, m_xyz = false;
    float m_exposure = 0.f;
    Ref<IFilter> m_filter;
    FilterTable m_table;
    std::vector<std::string> m_channels, m_outputNames;
    std::vector<float> m_data;
    mutable std::mutex m_mutex;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::HDRFilm)
