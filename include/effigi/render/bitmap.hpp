#pragma once
// Bitmap — an image file read into float pixels, for textures and environment maps.
//
// Reading goes through OpenImageIO (PNG, JPEG, EXR, HDR, TGA, BMP, TIFF, ...). The loader
// is NOT part of libeffigi: it is the static library `effigi_image` (src/render/bitmap.cpp),
// linked only by the modules that read images (texture-bitmap, emitter-envmap, ...).
// OpenImageIO pulls in a few hundred shared libraries at start-up; keeping it out of
// libeffigi means a scene without image textures never loads them. Link it with
//   set(EFFIGI_COMPONENT_LIBS_<tag>/<name> effigi_image)   (components/CMakeLists.txt)
// This header itself does not include OpenImageIO.
#include <filesystem>
#include <string>
#include <vector>

namespace effigi {

class Bitmap {
public:
    /// An empty bitmap (0 x 0).
    Bitmap() = default;
    /// Pixels given directly: width * height * channels floats, row-major, top row first,
    /// channels interleaved. Throws effigi::Error if the sizes disagree.
    Bitmap(int width, int height, int channels, std::vector<float> pixels, bool srgb = false);

    /// Read subimage 0 of an image file. Throws effigi::Error with the one line
    /// "<file>: <cause>" if it is missing, unreadable, corrupt or truncated.
    static Bitmap load(const std::filesystem::path& file);

    int width() const { return m_width; }
    int height() const { return m_height; }
    int channels() const { return m_channels; }
    bool empty() const { return m_pixels.empty(); }
    /// True when the values are sRGB-encoded (8/16-bit PNG, JPEG, ...: what the file
    /// declares, else integer data); false for linear data (EXR, HDR, float TIFF).
    bool srgb() const { return m_srgb; }
    /// Index of the alpha channel, or -1 (from the file's channel names, else RGBA/YA).
    int alphaChannel() const { return m_alpha; }
    /// The file it was read from (empty when built from memory).
    const std::string& filename() const { return m_filename; }

    /// Channel c of pixel (x, y); no bounds check.
    float at(int x, int y, int c) const {
        return m_pixels[(std::size_t(y) * std::size_t(m_width) + std::size_t(x)) * std::size_t(m_channels) +
                        std::size_t(c)];
    }
    const float* pixel(int x, int y) const {
        return m_pixels.data() + (std::size_t(y) * std::size_t(m_width) + std::size_t(x)) * std::size_t(m_channels);
    }
    const std::vector<float>& data() const { return m_pixels; }
    std::vector<float>& data() { return m_pixels; }

    /// Decode sRGB values to linear (IEC 61966-2-1), all channels but alpha; afterwards
    /// srgb() is false. Does nothing for linear data.
    void convertToLinear();
    /// The sRGB decoding curve (srgbDecode of effigi/spectral/colorspace.hpp), made odd
    /// so negative values stay finite.
    static float srgbToLinear(float v);

private:
    int m_width = 0, m_height = 0, m_channels = 0;
    int m_alpha = -1;
    bool m_srgb = false;
    std::string m_filename;
    std::vector<float> m_pixels;
};

} // namespace effigi
