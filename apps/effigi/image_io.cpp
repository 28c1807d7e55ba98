#include "image_io.hpp"

#include "image_io_oiio.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/input.hpp"
#include "effigi/core/module.hpp"
#include "effigi/spectral/colorspace.hpp"

#include "hdrfilm_png.hpp"  // components/film: the PNG writer hdrfilm uses

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <dlfcn.h>

namespace effigi::app {

namespace {

std::string oneLine(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    std::replace(s.begin(), s.end(), '\n', ' ');
    return s;
}

[[noreturn]] void cannotRead(const std::filesystem::path& path, const std::string& why) {
    fail("{}: cannot read image: {}", path.string(), oneLine(why));
}

/// An EXR by its magic number (OpenEXR file layout: 76 2f 31 01), or by its extension
/// when it has one, so that a broken .exr is reported by OpenEXR, not by OpenImageIO.
bool isExr(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) cannotRead(path, std::strerror(errno));
    unsigned char magic[4] = {0, 0, 0, 0};
    const std::size_t n = std::fread(magic, 1, 4, f);
    std::fclose(f);
    return ext == ".exr" || (n == 4 && magic[0] == 0x76 && magic[1] == 0x2f && magic[2] == 0x31 && magic[3] == 0x01);
}

/// R, G, B of an EXR's data window (any pixel type, converted to float); a file without
/// all three takes its first three channels, in the file's (alphabetical) order.
Image readExr(const std::filesystem::path& path) {
    Image img;
    try {
        Imf::InputFile file(path.c_str());
        const Imf::Header& header = file.header();
        const Imath::Box2i dw = header.dataWindow();
        std::vector<std::string> names;
        for (auto it = header.channels().begin(); it != header.channels().end(); ++it) {
            if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
                cannotRead(path, fmt::format("channel '{}' is subsampled", it.name()));
            names.push_back(it.name());
        }
        std::array<std::string, 3> rgb{"R", "G", "B"};
        const bool named = std::all_of(rgb.begin(), rgb.end(), [&](const std::string& c) {
            return std::find(names.begin(), names.end(), c) != names.end();
        });
        if (!named) {
            if (names.size() < 3) fail("{}: needs R, G and B channels, has {}", path.string(), names.size());
            std::copy_n(names.begin(), 3, rgb.begin());
        }
        img.width = dw.max.x - dw.min.x + 1;
        img.height = dw.max.y - dw.min.y + 1;
        img.channelNames = {"R", "G", "B"};
        img.pixels.assign(std::size_t(img.width) * std::size_t(img.height) * 3, 0.f);
        Imf::FrameBuffer fb;
        for (std::size_t c = 0; c < 3; ++c)
            fb.insert(rgb[c], Imf::Slice::Make(Imf::FLOAT, img.pixels.data() + c, dw, 3 * sizeof(float),
                                               3 * sizeof(float) * std::size_t(img.width)));
        file.setFrameBuffer(fb);
        file.readPixels(dw.min.y, dw.max.y);
    } catch (const Error&) {
        throw;
    } catch (const std::exception& e) {
        cannotRead(path, e.what());
    }
    return img;
}

/// The OpenImageIO module's reader, loaded on the first call (and only then).
oiio::ReadRGB oiioReader(const std::filesystem::path& forFile) {
    struct Loaded {
        oiio::ReadRGB read = nullptr;
        std::string error;
    };
    static const Loaded loaded = [] {
        Loaded l;
        const std::filesystem::path module = libraryDirectory() / "effigi" / oiio::ModuleFile;
        void* handle = dlopen(module.c_str(), RTLD_NOW | RTLD_LOCAL);
        if (!handle) l.error = fmt::format("OpenImageIO is needed for this format and did not load ({})", dlerror());
        else if (!(l.read = reinterpret_cast<oiio::ReadRGB>(dlsym(handle, oiio::ReadRGBSymbol))))
            l.error = fmt::format("{} has no entry point {}", module.string(), oiio::ReadRGBSymbol);
        return l;
    }();
    if (!loaded.read) cannotRead(forFile, loaded.error);
    return loaded.read;
}

} // namespace

Image readRGB(const std::filesystem::path& path) {
    // A regular file only: the readers read to the end (/dev/zero has none), and opening
    // a FIFO would wait for a writer.
    regularFileSize(path, "image");
    if (isExr(path)) return readExr(path);
    Image img;
    std::string error;
    if (!oiioReader(path)(path.c_str(), img, error)) fail("{}", error);
    return img;
}

void writePNG(const std::filesystem::path& path, int width, int height, const std::vector<float>& rgb) {
    std::vector<std::uint8_t> bytes(rgb.size());
    for (std::size_t i = 0; i < rgb.size(); ++i)
        bytes[i] = (unsigned char)(std::clamp(srgbEncode(std::clamp(rgb[i], 0.f, 1.f)), 0.f, 1.f) * 255.f + 0.5f);
    hdrfilm_io::writePngBytes(path, width, height, 3, bytes, {});
}

std::vector<float> falseColour(const std::vector<float>& values, float maxValue) {
    // Piecewise-linear through five points of a viridis-like ramp (linear RGB).
    static const std::array<std::array<float, 3>, 5> ramp = {{{0.074f, 0.005f, 0.116f},
                                                              {0.040f, 0.110f, 0.330f},
                                                              {0.020f, 0.300f, 0.250f},
                                                              {0.300f, 0.600f, 0.050f},
                                                              {0.950f, 0.840f, 0.010f}}};
    std::vector<float> rgb(values.size() * 3);
    for (std::size_t i = 0; i < values.size(); ++i) {
        float t = maxValue > 0.f ? std::clamp(values[i] / maxValue, 0.f, 1.f) : 0.f;
        if (!std::isfinite(values[i])) t = 1.f;
        float x = t * float(ramp.size() - 1);
        int k = std::min(int(x), int(ramp.size()) - 2);
        float f = x - float(k);
        for (int c = 0; c < 3; ++c) rgb[3 * i + c] = (1.f - f) * ramp[k][c] + f * ramp[k + 1][c];
    }
    return rgb;
}

} // namespace effigi::app
