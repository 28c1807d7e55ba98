#include "image_io.hpp"

#include "effigi/core/error.hpp"
#include "effigi/spectral/colorspace.hpp"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>

namespace effigi::app {

Image readRGB(const std::filesystem::path& path) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) fail("{}: cannot read image: {}", path.string(), OIIO::geterror());
    const OIIO::ImageSpec& spec = in->spec();
    auto channel = [&](const char* name, int fallback) {
        int c = spec.channelindex(name);
        return c >= 0 ? c : fallback;
    };
    int r = channel("R", 0), g = channel("G", 1), b = channel("B", 2);
    if (spec.nchannels < 3 || std::max({r, g, b}) >= spec.nchannels)
        fail("{}: needs R, G and B channels, has {}", path.string(), spec.nchannels);
    std::vector<float> px(std::size_t(spec.width) * spec.height * spec.nchannels);
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()))
        fail("{}: {}", path.string(), in->geterror());
    Image img;
    img.width = spec.width;
    img.height = spec.height;
    img.channelNames = {"R", "G", "B"};
    img.pixels.resize(std::size_t(spec.width) * spec.height * 3);
    for (std::size_t i = 0; i < std::size_t(spec.width) * spec.height; ++i) {
        const float* p = &px[i * spec.nchannels];
        img.pixels[3 * i] = p[r];
        img.pixels[3 * i + 1] = p[g];
        img.pixels[3 * i + 2] = p[b];
    }
    return img;
}

void writePNG(const std::filesystem::path& path, int width, int height, const std::vector<float>& rgb) {
    std::vector<unsigned char> bytes(rgb.size());
    for (std::size_t i = 0; i < rgb.size(); ++i)
        bytes[i] = (unsigned char)(std::clamp(srgbEncode(std::clamp(rgb[i], 0.f, 1.f)), 0.f, 1.f) * 255.f + 0.5f);
    auto out = OIIO::ImageOutput::create(path.string());
    OIIO::ImageSpec spec(width, height, 3, OIIO::TypeDesc::UINT8);
    if (!out || !out->open(path.string(), spec) || !out->write_image(OIIO::TypeDesc::UINT8, bytes.data()) ||
        !out->close())
        fail("cannot write {}: {}", path.string(), out ? out->geterror() : OIIO::geterror());
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

std::string readAttribute(const std::filesystem::path& path, const std::string& name) {
    auto in = OIIO::ImageInput::open(path.string());
    if (!in) return {};
    return std::string(in->spec().get_string_attribute(name));
}

} // namespace effigi::app
