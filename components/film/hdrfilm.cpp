/*
 * film "hdrfilm" — a high-dynamic-range film: accumulates filtered samples and writes
 * OpenEXR (plus an 8-bit sRGB PNG preview beside it, and optionally a spectral EXR).
 *
 * Each pixel stores its channels' filter-weighted sums and the weight sum; develop()
 * divides them (the weighted average of Mitchell & Netravali 1988 / pbrt's film,
 * a 0 weight gives 0). Renderers splat spectral radiance as CIE XYZ into channels
 * "X","Y","Z"; developing converts them to linear RGB of `colorspace` (sRGB/Rec.709,
 * Rec.2020 or ACEScg; effigi/spectral/colorspace.hpp) for pixel_format rgb/rgba, keeps
 * XYZ for xyz and Y for luminance. Any further channels (AOVs, e.g. "albedo.R") are
 * written as they are, under their names.
 *
 * Spectral output: with spectral_bins = N > 0 the film asks renderers (IFilm::spectralBins)
 * for N bin channels over [spectral_min, spectral_max] and writes them to <name>.spectral.exr
 * beside the output (out.exr -> out.spectral.exr) in the layout of Fichet, Pacanowski,
 * Wilkie, "An OpenEXR Layout for Spectral Images", JCGT 10(3), 2021 (spectral_exr.hpp).
 * The PNG is display-referred sRGB whatever `colorspace` is: exposure, then `tonemap`.
 *
 * Running sums: the film is an IAccumulator, so a checkpoint can save its sums and a
 * resumed render (or rank 0 of an MPI job, summing the ranks' films) put them back.
 *
 * Limits: a film whose buffers do not fit in the machine's memory is refused with its
 * size when created and when a renderer prepares its channels. No developed value or file
 * holds Inf or NaN: a block pixel whose sums would overflow stays off the film, a value
 * beyond float's (or float16's) range is clamped to it; both are said once with a count.
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
 *   colorspace             srgb | rec2020 | acescg  primaries of the RGB outputs (EXR)
 *   tonemap                none | reinhard | filmic PNG tone map (effigi/render/tonemap.hpp)
 *   spectral_bins          int, 0 (off), ≤ 128   bins of the spectral EXR
 *   spectral_min/_max      float, 360 / 830 nm   wavelength range of the bins
 *   rfilter                nested filter, default gaussian
 * Reference: D. P. Mitchell, A. N. Netravali, "Reconstruction Filters in Computer
 * Graphics", SIGGRAPH 1988; OpenEXR file layout, https://openexr.com; W3C, "Portable
 * Network Graphics (PNG) Specification", 2nd ed. (written with zlib alone, hdrfilm_png.hpp,
 * so that a render loads no OpenImageIO).
 */
#include "film_storage.hpp"
#include "spectral_exr.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/ifilter.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <memory>
#include <thread>

namespace effigi {
namespace {

using hdrfilm_io::PixelFormat;

const std::vector<std::string> PixelFormats{"rgb", "rgba", "xyz", "luminance"};
const std::vector<std::string> ComponentFormats{"float16", "float32"};
const std::vector<std::string> FileFormats{"openexr"};
const std::vector<std::string> ColorSpaces(RGBColorSpace::names().begin(), RGBColorSpace::names().end());
const std::vector<std::string> ToneMaps(tonemap::names().begin(), tonemap::names().end());

/// Index of a string parameter's value among its choices, or an error listing them.
std::size_t choose(const Properties& p, const std::string& name, const std::vector<std::string>& choices) {
    const std::string& v = p.getString(name);
    auto it = std::find(choices.begin(), choices.end(), v);
    if (it == choices.end())
        failAt(p.whereOf(name), "{}: '{}' must be one of {}, got '{}'", p.describe(), name,
               fmt::join(choices, ", "), v);
    return std::size_t(it - choices.begin());
}

/// Bytes of memory this machine can give a process: its physical memory, or the cgroup
/// (v2) limit of the container it runs in when that is lower. 0 when unknown.
double availableMemory() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
    double bytes = pages > 0 && page > 0 ? double(pages) * double(page) : 0.0;
    std::ifstream cg("/sys/fs/cgroup/memory.max");
    double limit = 0.0;
    if (cg >> limit && limit > 0.0 && (bytes == 0.0 || limit < bytes)) bytes = limit;  // "max" reads as nothing
    return bytes;
}

/// Refuses (at `where`, naming the film `name`) a film whose buffers cannot fit in this
/// machine's memory, before anything is allocated: the sums of `channels` channels and
/// the weight, the developed image of `outputs` channels with its float16 copy and the
/// PNG preview's linear floats and bytes (held while writing), and one tile block per
/// thread. The limit is the machine's, not a constant: large films on big machines pass.
void checkFilmMemory(const SourceLocation& where, const std::string& name, Vector2i size, int channels, int outputs) {
    constexpr double GiB = 1024.0 * 1024.0 * 1024.0;
    constexpr int Tile = 64;  // bound on a renderer's tile side (32) plus a filter border
    const double pixels = double(size.x) * double(size.y);
    const double sums = pixels * 4.0 * double(channels + 1);
    const double written = pixels * ((4.0 + 2.0) * double(outputs) + 4.0 * 3.0 + 3.0);
    const double blocks = double(std::max(1u, std::thread::hardware_concurrency())) * Tile * Tile * 4.0 * (channels + 1);
    const double need = sums + written + blocks, have = availableMemory();
    if (have > 0.0 && need > have)
        failAt(where,
               "{}: film {}x{} with {} floats per pixel needs {:.1f} GiB ({:.1f} GiB of sums, {:.1f} GiB to develop and "
               "write), more than the {:.1f} GiB of memory this machine has; render a smaller film or crop window",
               name, size.x, size.y, channels + 1, need / GiB, sums / GiB, (written + blocks) / GiB, have / GiB);
}

class HDRFilm final : public Implements<IFilm, IAccumulator> {
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
        // Mitsuba's hdrfilm options without an effect here.
        s.ignored("banner", "no banner is ever drawn into the image");
        s.ignored("compensate", "no Kahan compensation: pixel sums are plain float sums");
        s.ignored("sample_border", "no samples are taken beyond the film's edge");
        s.real("exposure", 0.0, "Exposure of the PNG (scale 2^exposure)").withUnit("stops").range(-64.0, 64.0);
        s.string("colorspace", "srgb", "RGB primaries of the EXR: srgb (Rec.709), rec2020 or acescg (AP1)")
            .oneOf(ColorSpaces);
        s.string("tonemap", "none", "Tone map of the PNG: none (clamp), reinhard (2002) or filmic (ACES fit)")
            .oneOf(ToneMaps);
        s.integer("spectral_bins", 0, "Bins of a spectral EXR <name>.spectral.exr (0: none)")
            .range(0, SpectralBinning::MaxBins);
        s.real("spectral_min", double(LambdaMin), "Shortest wavelength of the spectral bins")
            .withUnit("nm")
            .range(double(LambdaMin), double(LambdaMax));
        s.real("spectral_max", double(LambdaMax), "Longest wavelength of the spectral bins")
            .withUnit("nm")
            .range(double(LambdaMin), double(LambdaMax));
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

        const auto format = PixelFormat(choose(p, "pixel_format", PixelFormats));
        m_half = choose(p, "component_format", ComponentFormats) == 0;
        choose(p, "file_format", FileFormats);
        m_png = p.getBool("png");
        m_exposure = p.getFloat("exposure");
        if (!std::isfinite(m_exposure))
            failAt(p.whereOf("exposure"), "{}: 'exposure' must be finite", p.describe());
        choose(p, "colorspace", ColorSpaces);
        choose(p, "tonemap", ToneMaps);
        const RGBColorSpace& colorSpace = RGBColorSpace::get(RGBColorSpace::parse(p.getString("colorspace")).value());
        m_toneMap = tonemap::parse(p.getString("tonemap")).value();
        const float lo = p.getFloat("spectral_min"), hi = p.getFloat("spectral_max");
        if (!(lo < hi))
            failAt(p.whereOf("spectral_min"),
                   "{}: 'spectral_min' ({} nm) must be below 'spectral_max' ({} nm)", p.describe(), lo, hi);
        const std::int64_t bins = p.getInt("spectral_bins");
        if (bins < 0 || bins > SpectralBinning::MaxBins)
            failAt(p.whereOf("spectral_bins"), "{}: 'spectral_bins' = {} is not in [0, {}]", p.describe(), bins,
                   SpectralBinning::MaxBins);
        // Checked now with the channels every colour renderer splats (X, Y, Z and the bins),
        // again in prepare() with the renderer's own.
        const int outputs = format == PixelFormat::RGBA ? 4 : format == PixelFormat::Luminance ? 1 : 3;
        m_sizeWhere = p.whereOf("width");
        m_name = p.describe();
        checkFilmMemory(m_sizeWhere, m_name, m_size, 3 + int(bins), outputs + (bins > 0 ? 3 + int(bins) : 0));
        m_storage = std::make_unique<hdrfilm_io::FilmStorage>(m_size, format, colorSpace,
                                                              SpectralBinning(int(bins), lo, hi));

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
    int spectralBins() const override { return m_storage->bins().count(); }
    std::pair<float, float> spectralRange() const override {
        return {m_storage->bins().lambdaMin(), m_storage->bins().lambdaMax()};
    }

    void prepare(const std::vector<std::string>& channels) override {
        const int colour = channels.size() >= 3 && channels[0] == "X" ? 3 : 0;  // become 1-4 output channels
        checkFilmMemory(m_sizeWhere, m_name, m_size, int(channels.size()), int(channels.size()) - colour + 4);
        m_storage->prepare(channels);
    }
    ImageBlock createBlock(Point2i offset, Vector2i size) const override {
        return ImageBlock(offset, size, m_storage->channels(), &m_table);
    }
    void put(const ImageBlock& block) override { m_storage->put(block); }
    Image develop() const override { return m_storage->develop(); }
    // IAccumulator: the sums of a checkpoint or of other MPI ranks (apps/effigi/render_mpi.cpp).
    AccumulatorSums saveSums() const override { return m_storage->saveSums(); }
    void loadSums(const AccumulatorSums& sums) override {
        prepare(m_storage->channelsOf(sums));
        m_storage->loadSums(sums);
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
        const std::filesystem::path spectral = spectral_exr::spectralPath(main);
        if (ext == ".exr") {
            const PixelFormat f = m_storage->format();
            const bool rgb = m_storage->hasXYZ() && (f == PixelFormat::RGB || f == PixelFormat::RGBA);
            hdrfilm_io::writeExr(main, img, m_half, rgb ? &m_storage->colorSpace() : nullptr, meta);
            written.push_back(main);
            main.replace_extension(".png");
        }
        if (ext == ".png" || m_png) {
            writePreview(main, img, meta);
            written.push_back(main);
        }
        if (m_storage->hasBins()) {
            spectral_exr::writeFile(spectral, m_storage->developSpectral(), m_storage->colorSpace(),
                                    m_storage->bins(), meta);
            written.push_back(spectral);
        }
        return written;
    }

private:
    static void checkCrop(const Properties& p, const char* name, int v, int lo, int hi) {
        if (v < lo || v > hi)
            failAt(p.whereOf(name), "{}: '{}' = {} puts the crop window outside the {}x{} film (allowed: {}..{})",
                   p.describe(), name, v, p.getInt("width"), p.getInt("height"), lo, hi);
    }

    /// The PNG shows the colour as sRGB whatever the colour space: RGB converted through
    /// XYZ, XYZ converted, grey for luminance; without XYZ the first three channels, or
    /// the first as grey. Exposure and the tone map apply here only.
    void writePreview(const std::filesystem::path& path, const Image& img, const FilmMetadata& meta) const {
        const bool xyz = m_storage->hasXYZ();
        const PixelFormat format = m_storage->format();
        const RGBColorSpace& cs = m_storage->colorSpace();
        const int nc = xyz ? (format == PixelFormat::Luminance ? 1 : 3)
                           : (img.channels() >= 3 ? 3 : std::min(img.channels(), 1));
        const bool fromXYZ = xyz && format == PixelFormat::XYZ;
        const bool fromRGB = xyz && !fromXYZ && &cs != &RGBColorSpace::get(ColorSpaceId::SRGB);
        std::vector<float> linear(std::size_t(img.width) * std::size_t(img.height) * std::size_t(nc));
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                float* d = linear.data() + (std::size_t(y) * std::size_t(img.width) + std::size_t(x)) * std::size_t(nc);
                if (nc == 3) {
                    Vector3f v(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2));
                    if (fromXYZ) v = xyzToLinearSRGB(v);
                    if (fromRGB) v = xyzToLinearSRGB(cs.toXYZ(v));
                    d[0] = v.x, d[1] = v.y, d[2] = v.z;
                } else if (nc == 1) {
                    d[0] = img.at(x, y, 0);
                }
            }
        hdrfilm_io::writePng(path, img.width, img.height, nc, linear, m_exposure, m_toneMap, meta);
    }

    Vector2i m_fullSize{0}, m_size{0};
    Point2i m_cropOffset{0};
    bool m_half = true, m_png = true;
    float m_exposure = 0.f;
    ToneMap m_toneMap = ToneMap::None;
    Ref<IFilter> m_filter;
    FilterTable m_table;
    std::unique_ptr<hdrfilm_io::FilmStorage> m_storage;  // channels, sums, development
    SourceLocation m_sizeWhere;                          // for prepare()'s memory check
    std::string m_name;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::HDRFilm)
