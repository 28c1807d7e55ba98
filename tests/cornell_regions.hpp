#pragma once
// Region means for comparing renderers on the Cornell box: the wall regions of
// tests/data/cornell/regions.txt (fractions of the image, each inside one surface) and
// the mean of a region of a developed image. Shared by the renderer tests (radiosity,
// photonmap, sppm, irradiancecache, pssmlt), and Mitsuba 3's reference image at any
// resolution that divides 256.
#include "effigi/interfaces/ifilm.hpp"

#include <OpenImageIO/imageio.h>
#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace effigi::test {

struct CornellRegion {
    std::string name;
    float x0, y0, x1, y1;
};

/// The regions of tests/data/cornell/regions.txt, in file order ("image" first).
inline std::vector<CornellRegion> cornellRegions() {
    std::ifstream in(EFFIGI_SOURCE_DIR "/tests/data/cornell/regions.txt");
    std::vector<CornellRegion> regions;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream ss(line);
        CornellRegion r;
        if (ss >> r.name >> r.x0 >> r.y0 >> r.x1 >> r.y1) regions.push_back(r);
    }
    return regions;
}

/// Mean over [x0, x1) × [y0, y1) (fractions of the image) of channel c, or of the grey
/// (R + G + B) / 3 when c < 0.
inline double regionMean(const Image& img, float fx0, float fy0, float fx1, float fy1, int channel = -1) {
    const int x0 = int(fx0 * img.width), x1 = int(fx1 * img.width), y0 = int(fy0 * img.height),
              y1 = int(fy1 * img.height);
    double sum = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
            sum += channel >= 0 ? img.at(x, y, channel) : (img.at(x, y, 0) + img.at(x, y, 1) + img.at(x, y, 2)) / 3.0;
    return sum / (double(x1 - x0) * (y1 - y0));
}

inline double regionMean(const Image& img, const CornellRegion& r) { return regionMean(img, r.x0, r.y0, r.x1, r.y1); }

/// Mitsuba 3's 256² reference box-filtered down to res² (res divides 256).
inline Image cornellReference(int res) {
    auto in = OIIO::ImageInput::open(EFFIGI_SOURCE_DIR "/tests/data/cornell/mitsuba-reference.exr");
    REQUIRE(in);
    const auto& spec = in->spec();
    REQUIRE(spec.width == 256);
    std::vector<float> px(std::size_t(spec.width) * spec.height * spec.nchannels);
    REQUIRE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
    const int f = 256 / res;
    Image img;
    img.width = img.height = res;
    img.channelNames = {"R", "G", "B"};
    img.pixels.assign(std::size_t(res) * res * 3, 0.f);
    for (int y = 0; y < 256; ++y)
        for (int x = 0; x < 256; ++x)
            for (int c = 0; c < 3; ++c)
                img.pixels[(std::size_t(y / f) * res + x / f) * 3 + c] +=
                    px[(std::size_t(y) * 256 + x) * spec.nchannels + c] / float(f * f);
    return img;
}

} // namespace effigi::test
