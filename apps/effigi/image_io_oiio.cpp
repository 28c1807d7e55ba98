// The app's OpenImageIO reader: built as its own module (lib/effigi/image-oiio.so, see
// apps/CMakeLists.txt), never linked into the effigi binary, and dlopen'ed by
// image_io.cpp only for a reference image that is not EXR. OpenImageIO pulls in ~250
// shared libraries; a command that never reads such an image loads none of them.
#include "image_io_oiio.hpp"

#include <OpenImageIO/imageio.h>

#include <fmt/format.h>

#include <algorithm>
#include <exception>
#include <type_traits>
#include <vector>

namespace {

/// OpenImageIO's messages may span lines; an effigi error is one line.
std::string oneLine(std::string s) {
    while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
    std::replace(s.begin(), s.end(), '\n', ' ');
    return s;
}

void read(const std::string& path, effigi::Image& img, std::string& error) {
    auto in = OIIO::ImageInput::open(path);
    if (!in) {
        error = fmt::format("{}: cannot read image: {}", path, oneLine(OIIO::geterror()));
        return;
    }
    const OIIO::ImageSpec& spec = in->spec();
    auto channel = [&](const char* name, int fallback) {
        int c = spec.channelindex(name);
        return c >= 0 ? c : fallback;
    };
    const int r = channel("R", 0), g = channel("G", 1), b = channel("B", 2);
    if (spec.nchannels < 3 || std::max({r, g, b}) >= spec.nchannels) {
        error = fmt::format("{}: needs R, G and B channels, has {}", path, spec.nchannels);
        return;
    }
    const std::size_t n = std::size_t(spec.width) * std::size_t(spec.height);
    std::vector<float> px(n * std::size_t(spec.nchannels));
    if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data())) {
        error = fmt::format("{}: {}", path, oneLine(in->geterror()));
        return;
    }
    img.width = spec.width;
    img.height = spec.height;
    img.channelNames = {"R", "G", "B"};
    img.pixels.resize(n * 3);
    for (std::size_t i = 0; i < n; ++i) {
        const float* p = &px[i * std::size_t(spec.nchannels)];
        img.pixels[3 * i] = p[r];
        img.pixels[3 * i + 1] = p[g];
        img.pixels[3 * i + 2] = p[b];
    }
}

} // namespace

extern "C" __attribute__((visibility("default"))) bool effigiReadImageRGB(const char* path, effigi::Image& out,
                                                                         std::string& error) noexcept {
    // Nothing may unwind through dlsym'ed C linkage: allocation failures become a message.
    try {
        error.clear();
        read(path, out, error);
        return error.empty();
    } catch (const std::exception& e) {
        error = fmt::format("{}: cannot read image: {}", path, oneLine(e.what()));
    } catch (...) {
        error = fmt::format("{}: cannot read image", path);
    }
    return false;
}

// The entry point's type is the one image_io.cpp casts dlsym's result to.
static_assert(std::is_same_v<decltype(&effigiReadImageRGB), effigi::app::oiio::ReadRGB>);
