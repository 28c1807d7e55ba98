#pragma once
// Reading images back in tests: an EXR (or PNG) through OpenImageIO as floats, with its
// header for the metadata checks.
#include <OpenImageIO/imageio.h>
#include <catch2/catch.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace effigi::test {

struct ExrImage {
    OIIO::ImageSpec spec;
    std::vector<float> px;  // interleaved, row-major
    int channel(const std::string& name) const { return spec.channelindex(name); }
    float at(int x, int y, int c) const {
        return px[(std::size_t(y) * std::size_t(spec.width) + std::size_t(x)) * std::size_t(spec.nchannels) +
                  std::size_t(c)];
    }
    std::size_t pixels() const { return std::size_t(spec.width) * std::size_t(spec.height); }
};

inline ExrImage readExr(const std::filesystem::path& file) {
    ExrImage img;
    auto in = OIIO::ImageInput::open(file.string());
    REQUIRE(in);
    img.spec = in->spec();
    img.px.resize(img.pixels() * std::size_t(img.spec.nchannels));
    REQUIRE(in->read_image(0, 0, 0, img.spec.nchannels, OIIO::TypeDesc::FLOAT, img.px.data()));
    return img;
}

} // namespace effigi::test
