#pragma once
// Image file output for the hdrfilm module and `effigi convert`: OpenEXR through the
// OpenEXR library and 8-bit PNG through zlib (hdrfilm_png.hpp). Kept out of libeffigi so
// the core library links neither, and free of OpenImageIO so that a render loads none of
// its ~250 shared libraries. Header-only because components/<tag>/*.cpp each become a module.
#include "hdrfilm_png.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/log.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/render/tonemap.hpp"
#include "effigi/spectral/colorspace.hpp"

#include <Imath/half.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <ImfStandardAttributes.h>
#include <ImfStringAttribute.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <string>
#include <vector>

namespace effigi::hdrfilm_io {

namespace fs = std::filesystem;

/// OpenEXR, ZIP-compressed, one channel per image channel (HALF or FLOAT), metadata as
/// string attributes. A non-null `rgb` adds that colour space's chromaticities (primaries
/// and white) and an "effigi/colorspace" attribute naming it.
inline void writeExr(const fs::path& path, const Image& img, bool half, const RGBColorSpace* rgb,
                     const FilmMetadata& meta) {
    checkDirectory(path);
    if (img.channels() == 0 || img.width <= 0 || img.height <= 0)
        cannotWrite(path, "the film holds no image (prepare() was not called)");
    try {
        Imf::Header header(img.width, img.height);
        header.compression() = Imf::ZIP_COMPRESSION;
        FilmMetadata attributes = meta;
        if (rgb) {
            const auto& p = rgb->primaries();
            const colorimetry::Chromaticity w = rgb->whiteXY();
            auto v2 = [](colorimetry::Chromaticity c) { return Imath::V2f(float(c.x), float(c.y)); };
            Imf::addChromaticities(header, Imf::Chromaticities(v2(p[0]), v2(p[1]), v2(p[2]), v2(w)));
            attributes.emplace("effigi/colorspace", rgb->name());
        }
        for (const auto& [key, value] : attributes) {
            if (key.empty() || header.find(key) != header.end()) {
                log::warn("{}: metadata key '{}' clashes with a standard EXR attribute; skipped", path.string(), key);
                continue;
            }
            header.insert(key, Imf::StringAttribute(value));
        }
        // The output frame buffer must have the file's pixel type: halves are converted
        // here (round to nearest). No file gets Inf or NaN: beyond binary16's ±65504 (a
        // radiance of 1e5 is bright but legitimate) a value is clamped to that limit, a
        // non-finite float to ±FLT_MAX (NaN: 0), and the count is said.
        std::vector<Imath::half> halves;
        std::vector<float> finite;
        char* base = reinterpret_cast<char*>(const_cast<float*>(img.pixels.data()));
        std::size_t size = sizeof(float), clamped = 0;
        const float limit = half ? float(HALF_MAX) : FLT_MAX;
        auto clamp = [&](float v) {
            if (std::abs(v) <= limit) return v;
            ++clamped;
            return std::isnan(v) ? 0.f : std::copysign(limit, v);
        };
        if (half) {
            halves.reserve(img.pixels.size());
            for (float v : img.pixels) halves.push_back(Imath::half(clamp(v)));
            base = reinterpret_cast<char*>(halves.data());
            size = sizeof(Imath::half);
        } else if (!std::all_of(img.pixels.begin(), img.pixels.end(), [](float v) { return std::isfinite(v); })) {
            finite.reserve(img.pixels.size());
            for (float v : img.pixels) finite.push_back(clamp(v));
            base = reinterpret_cast<char*>(finite.data());
        }
        if (clamped > 0)
            log::warn("{}: {} value(s) beyond {} were clamped to ±{:g}{}", path.string(), clamped,
                      half ? "float16's range" : "the float range", limit,
                      half ? " (component_format float32 keeps them)" : "");
        const std::size_t xStride = size * std::size_t(img.channels());
        const std::size_t yStride = xStride * std::size_t(img.width);
        const Imf::PixelType type = half ? Imf::HALF : Imf::FLOAT;
        Imf::FrameBuffer fb;
        for (int c = 0; c < img.channels(); ++c) {
            const std::string& name = img.channelNames[std::size_t(c)];
            header.channels().insert(name, Imf::Channel(type));
            fb.insert(name, Imf::Slice(type, base + size * std::size_t(c), xStride, yStride));
        }
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(fb);
        file.writePixels(img.height);
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        cannotWrite(path, e.what());
    }
}

/// 8-bit sRGB PNG of 1 (grey) or 3 (linear sRGB) channels, as displayBytes() makes them;
/// metadata as text chunks.
inline void writePng(const fs::path& path, int width, int height, int channels, const std::vector<float>& linear,
                     float exposure, ToneMap toneMap, const FilmMetadata& meta) {
    checkDirectory(path);
    if ((channels != 1 && channels != 3) || width <= 0 || height <= 0) cannotWrite(path, "the film holds no image");
    writePngBytes(path, width, height, channels, displayBytes(channels, linear, exposure, toneMap), meta);
}

} // namespace effigi::hdrfilm_io
