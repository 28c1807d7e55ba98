#pragma once
// The accumulation buffer of hdrfilm and its development into images: which channels a
// renderer splats (X, Y, Z colour, spectral bins, AOVs), their filter-weighted sums, and
// the weighted averages (Mitchell & Netravali 1988) converted to the film's pixel format
// and colour space. Header-only because components/film/*.cpp each become a module.
#include "effigi/core/error.hpp"
#include "effigi/core/input.hpp"
#include "effigi/core/log.hpp"
#include "effigi/interfaces/iaccumulator.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/render/image_block.hpp"
#include "effigi/render/spectral_bins.hpp"
#include "effigi/spectral/colorspace.hpp"

#include <fmt/ranges.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <mutex>
#include <set>

namespace effigi::hdrfilm_io {

enum class PixelFormat { RGB, RGBA, XYZ, Luminance };

class FilmStorage {
public:
    FilmStorage(Vector2i size, PixelFormat format, const RGBColorSpace& colorSpace, SpectralBinning bins)
        : m_size(size), m_format(format), m_colorSpace(&colorSpace), m_bins(bins) {}

    PixelFormat format() const { return m_format; }
    const RGBColorSpace& colorSpace() const { return *m_colorSpace; }
    const SpectralBinning& bins() const { return m_bins; }
    /// Whether the channels start with X, Y, Z (colour to convert).
    bool hasXYZ() const { return m_xyz; }
    /// Whether the renderer supplied the film's spectral bin channels.
    bool hasBins() const { return m_binFirst >= 0; }
    int channels() const { return int(m_channels.size()); }

    /// Clear the storage for these channels. The film's bin channels (if it has bins and
    /// they are all there, in order) are kept apart for developSpectral(); everything
    /// after X, Y, Z else is an AOV written under its name.
    void prepare(const std::vector<std::string>& channels) {
        std::set<std::string> seen;
        for (const std::string& c : channels)
            if (c.empty() || !seen.insert(c).second)
                fail("film: channel names must be unique and non-empty (got '{}')", fmt::join(channels, ", "));
        const bool xyz = channels.size() >= 3 && channels[0] == "X" && channels[1] == "Y" && channels[2] == "Z";
        int binFirst = -1;
        if (m_bins.enabled()) {
            const std::vector<std::string> names = m_bins.channelNames();
            auto it = std::find(channels.begin(), channels.end(), names.front());
            if (it != channels.end() && std::size_t(channels.end() - it) >= names.size() &&
                std::equal(names.begin(), names.end(), it))
                binFirst = int(it - channels.begin());
            else
                log::warn("film: spectral_bins = {}, but the renderer supplies no spectral bin channels; no "
                          "spectral EXR will be written", m_bins.count());
        }
        std::vector<std::string> out;
        if (xyz) {
            switch (m_format) {
            case PixelFormat::RGB: out = {"R", "G", "B"}; break;
            case PixelFormat::RGBA: out = {"R", "G", "B", "A"}; break;
            case PixelFormat::XYZ: out = {"X", "Y", "Z"}; break;
            case PixelFormat::Luminance: out = {"Y"}; break;
            }
        }
        std::vector<int> copied;
        for (int c = xyz ? 3 : 0; c < int(channels.size()); ++c) {
            if (binFirst >= 0 && c >= binFirst && c < binFirst + m_bins.count()) continue;
            copied.push_back(c);
            out.push_back(channels[std::size_t(c)]);
        }
        seen.clear();
        for (const std::string& c : out)
            if (!seen.insert(c).second) fail("film: AOV channel '{}' clashes with a colour channel", c);

        std::lock_guard lock(m_mutex);
        m_xyz = xyz;
        m_binFirst = binFirst;
        m_copied = std::move(copied);
        m_channels = channels;
        m_outputNames = std::move(out);
        m_data.assign(std::size_t(m_size.x) * std::size_t(m_size.y) * (channels.size() + 1), 0.f);
        m_overflowed = 0;
        m_warnedOverflow = m_warnedClamp = false;
    }

    /// Add a block, border included, clipped to the window (thread-safe). A block pixel
    /// whose sums are not finite, or would overflow the film's, stays off the film whole
    /// (its weight too) and is counted: renderers keep NaN/Inf samples off the film, but
    /// finite samples near float's limit can still add up to Inf.
    void put(const ImageBlock& block) {
        const int n = block.stride();
        if (block.channels() != int(m_channels.size()))
            fail("film: block has {} channels, the film was prepared with {}", block.channels(), m_channels.size());
        const Point2i lo = block.offset() - block.border();
        const Point2i hi = lo + block.storageSize();
        const int x0 = std::max(lo.x, 0), x1 = std::min(hi.x, m_size.x);
        const int y0 = std::max(lo.y, 0), y1 = std::min(hi.y, m_size.y);
        if (x0 >= x1 || y0 >= y1) return;
        std::lock_guard lock(m_mutex);
        for (int y = y0; y < y1; ++y) {
            const float* src = block.pixel(x0, y);
            float* dst = m_data.data() + (std::size_t(y) * std::size_t(m_size.x) + std::size_t(x0)) * std::size_t(n);
            for (int x = x0; x < x1; ++x, src += n, dst += n) {
                bool finite = true;
                for (int k = 0; k < n; ++k) finite &= std::isfinite(dst[k] + src[k]);
                if (!finite) {
                    ++m_overflowed;
                    continue;
                }
                for (int k = 0; k < n; ++k) dst[k] += src[k];
            }
        }
    }

    /// The running sums (IAccumulator): the window's size and channels as the layout
    /// ("film WxH" and one channel name a line), every pixel's channel sums and weight.
    AccumulatorSums saveSums() const {
        std::lock_guard lock(m_mutex);
        AccumulatorSums s;
        if (m_channels.empty()) return s;
        s.layout = layoutOf(m_channels);
        s.floats = m_data;
        return s;
    }
    /// The channels of a layout saveSums() wrote for a film of this size; an error if it
    /// is another film's.
    std::vector<std::string> channelsOf(const AccumulatorSums& s) const {
        std::vector<std::string> channels;
        const std::string head = fmt::format("film {}x{}", m_size.x, m_size.y);
        std::size_t at = s.layout.find('\n');
        if (s.layout.substr(0, at) != head)
            fail("film: the saved sums are of another film ('{}', this is '{}')", excerpt(s.layout.substr(0, at)),
                 head);
        while (at != std::string::npos) {
            const std::size_t next = s.layout.find('\n', at + 1);
            channels.push_back(s.layout.substr(at + 1, next == std::string::npos ? next : next - at - 1));
            at = next;
        }
        const std::size_t expected = std::size_t(m_size.x) * std::size_t(m_size.y) * (channels.size() + 1);
        if (channels.empty() || s.floats.size() != expected || !s.doubles.empty())
            fail("film: the saved sums hold {} values, a {}x{} film with {} channels needs {}", s.floats.size(),
                 m_size.x, m_size.y, channels.size(), expected);
        return channels;
    }
    /// Put back sums of channelsOf(s) (prepare() with them first).
    void loadSums(const AccumulatorSums& s) {
        std::lock_guard lock(m_mutex);
        if (s.layout != layoutOf(m_channels) || s.floats.size() != m_data.size())
            fail("film: the saved sums do not fit the prepared film");
        m_data = s.floats;
    }

    /// Colour in the pixel format (RGB of the colour space for rgb/rgba), then the AOVs.
    /// Every value is finite (finiteValues()).
    Image develop() const {
        std::lock_guard lock(m_mutex);
        Image img = emptyImage(m_outputNames);
        const std::size_t stride = m_channels.size() + 1, out = m_outputNames.size();
        for (std::size_t i = 0; out > 0 && i < img.pixels.size() / out; ++i) {
            const float* src = m_data.data() + i * stride;
            float* dst = img.pixels.data() + i * out;
            const float inv = src[stride - 1] != 0.f ? 1.f / src[stride - 1] : 0.f;
            std::size_t o = 0;
            if (m_xyz) {
                const Vector3f xyz = Vector3f(src[0], src[1], src[2]) * inv;
                switch (m_format) {
                case PixelFormat::RGB:
                case PixelFormat::RGBA: {
                    const Vector3f rgb = m_colorSpace->fromXYZ(xyz);
                    dst[o++] = rgb.x, dst[o++] = rgb.y, dst[o++] = rgb.z;
                    if (m_format == PixelFormat::RGBA) dst[o++] = 1.f;
                    break;
                }
                case PixelFormat::XYZ: dst[o++] = xyz.x, dst[o++] = xyz.y, dst[o++] = xyz.z; break;
                case PixelFormat::Luminance: dst[o++] = xyz.y; break;
                }
            }
            for (int c : m_copied) dst[o++] = src[c] * inv;
        }
        finiteValues(img);
        return img;
    }

    /// "R","G","B" of the colour space (from XYZ; zero without it), then the bin means,
    /// filter-weighted like every other channel.
    Image developSpectral() const {
        std::lock_guard lock(m_mutex);
        std::vector<std::string> names{"R", "G", "B"};
        for (int b = 0; m_binFirst >= 0 && b < m_bins.count(); ++b)
            names.push_back(m_channels[std::size_t(m_binFirst + b)]);
        Image img = emptyImage(std::move(names));
        const std::size_t stride = m_channels.size() + 1, out = img.channelNames.size();
        const int bins = m_binFirst >= 0 ? m_bins.count() : 0;
        for (std::size_t i = 0; i < img.pixels.size() / out; ++i) {
            const float* src = m_data.data() + i * stride;
            float* dst = img.pixels.data() + i * out;
            const float inv = src[stride - 1] != 0.f ? 1.f / src[stride - 1] : 0.f;
            if (m_xyz) {
                const Vector3f rgb = m_colorSpace->fromXYZ(Vector3f(src[0], src[1], src[2]) * inv);
                dst[0] = rgb.x, dst[1] = rgb.y, dst[2] = rgb.z;
            }
            for (int b = 0; b < bins; ++b) dst[3 + b] = src[m_binFirst + b] * inv;
        }
        finiteValues(img);
        return img;
    }

private:
    /// The sums are finite, but a weighted average can still overflow (a large sum over a
    /// tiny weight from a filter's tail or negative lobes, or the colour matrix on values
    /// near float's limit): such a value becomes ±FLT_MAX (NaN: 0), so that no image holds
    /// Inf or NaN. Said once per render with the count, and with the pixels kept off in put().
    void finiteValues(Image& img) const {
        std::size_t clamped = 0;
        for (float& v : img.pixels)
            if (!std::isfinite(v)) {
                v = std::isnan(v) ? 0.f : std::copysign(FLT_MAX, v);
                ++clamped;
            }
        if (m_overflowed > 0 && !m_warnedOverflow) {
            m_warnedOverflow = true;
            log::warn("film: {} pixel contribution(s) of rendered blocks were kept off the film: their sums would "
                      "overflow float", m_overflowed);
        }
        if (clamped > 0 && !m_warnedClamp) {
            m_warnedClamp = true;
            log::warn("film: {} developed value(s) overflowed float and were clamped to ±{:g}", clamped, FLT_MAX);
        }
    }

    std::string layoutOf(const std::vector<std::string>& channels) const {
        return fmt::format("film {}x{}\n{}", m_size.x, m_size.y, fmt::join(channels, "\n"));
    }

    /// An image of the window's size with these channels, zeroed; no pixels if not
    /// prepared. Call with the mutex held.
    Image emptyImage(std::vector<std::string> names) const {
        Image img;
        img.width = m_size.x;
        img.height = m_size.y;
        img.channelNames = std::move(names);
        const std::size_t pixels = std::size_t(m_size.x) * std::size_t(m_size.y);
        if (m_data.size() == pixels * (m_channels.size() + 1)) img.pixels.assign(pixels * img.channelNames.size(), 0.f);
        return img;
    }

    Vector2i m_size{0};
    PixelFormat m_format = PixelFormat::RGB;
    const RGBColorSpace* m_colorSpace = nullptr;
    SpectralBinning m_bins;
    bool m_xyz = false;
    int m_binFirst = -1;              // first bin channel among m_channels, or -1
    std::vector<std::string> m_channels, m_outputNames;
    std::vector<int> m_copied;        // channels written as they are (AOVs)
    std::vector<float> m_data;        // per pixel: channel sums, then the weight sum
    std::uint64_t m_overflowed = 0;   // block pixels put() kept off the film
    mutable bool m_warnedOverflow = false, m_warnedClamp = false;
    mutable std::mutex m_mutex;
};

} // namespace effigi::hdrfilm_io
