// End to end: the Cornell box rendered at low spp agrees with a high-spp reference
// rendered by Mitsuba 3 scalar_spectral (an independent renderer), region by region.
// bench/compare_mitsuba.py --write-reference regenerates the reference.
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/xml/loader.hpp"

#include <catch2/catch.hpp>

#include <OpenImageIO/imageio.h>

#include <fstream>
#include <sstream>

using namespace effigi;

namespace {

struct Region {
    std::string name;
    float x0, y0, x1, y1;
};

std::vector<Region> regions() {
    std::ifstream in(EFFIGI_SOURCE_DIR "/tests/data/cornell/regions.txt");
    std::vector<Region> out;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream ss(line);
        Region r;
        ss >> r.name >> r.x0 >> r.y0 >> r.x1 >> r.y1;
        out.push_back(r);
    }
    return out;
}

/// Grey value (mean of R, G, B) per pixel.
struct Grey {
    int w = 0, h = 0;
    std::vector<double> v;
    double at(int x, int y) const { return v[std::size_t(y) * w + x]; }
};

Grey readReference() {
    auto in = OIIO::ImageInput::open(EFFIGI_SOURCE_DIR "/tests/data/cornell/mitsuba-reference.exr");
    REQUIRE(in);
    const auto& spec = in->spec();
    std::vector<float> px(std::size_t(spec.width) * spec.height * spec.nchannels);
    REQUIRE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
    Grey g{spec.width, spec.height, {}};
    for (std::size_t i = 0; i < std::size_t(spec.width) * spec.height; ++i)
        g.v.push_back((px[i * spec.nchannels] + px[i * spec.nchannels + 1] + px[i * spec.nchannels + 2]) / 3.0);
    return g;
}

struct RegionStats {
    double mean, stderr_;
};

/// Mean over a region and its standard error. Pixel noise is estimated from differences
/// of pixels two apart (which cancel the smooth image and most of the filter's
/// correlation): σ² ≈ ⟨(p(x) − p(x+2))²⟩ / 2. The residual correlation of neighbouring
/// pixels through the Gaussian filter is covered by a factor 2 on the variance.
RegionStats regionStats(const Grey& g, const Region& r) {
    int x0 = int(r.x0 * g.w), x1 = int(r.x1 * g.w), y0 = int(r.y0 * g.h), y1 = int(r.y1 * g.h);
    double sum = 0, diff2 = 0;
    int n = 0, nd = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            sum += g.at(x, y);
            ++n;
            if (x + 2 < x1) {
                double d = g.at(x, y) - g.at(x + 2, y);
                diff2 += d * d;
                ++nd;
            }
        }
    double sigma2 = nd ? diff2 / (2.0 * nd) : 0.0;
    return {sum / n, std::sqrt(2.0 * sigma2 / n)};
}

} // namespace

TEST_CASE("cornell box: image and wall means agree with Mitsuba 3", "[render][cornell]") {
    xml::ParseOptions opt;
    opt.defines = {{"spp", "16"}, {"res", "256"}};
    auto scene = loadSceneFile(EFFIGI_SOURCE_DIR "/scenes/cornell-box/scene.xml", opt);
    RenderControl control;
    control.progress = false;
    RenderStats stats = scene->renderer().render(*scene, control);
    CHECK(stats.rejectedSamples == 0);
    CHECK(stats.samples == 256u * 256u * 16u);

    Image img = scene->camera().film().develop();
    REQUIRE(img.channelNames.size() >= 3);
    Grey ours{img.width, img.height, {}};
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            ours.v.push_back((img.at(x, y, 0) + img.at(x, y, 1) + img.at(x, y, 2)) / 3.0);
    Grey ref = readReference();
    REQUIRE(ref.w == ours.w);
    REQUIRE(ref.h == ours.h);

    // Tolerance: the systematic agreement the issue asks of the two renderers at high spp
    // (1 % for the image, 2 % per wall) plus 4 standard errors of our 16-spp estimate
    // (two-sided false-alarm probability 6e-5 per region; the render is seeded, so the
    // outcome is deterministic). The reference's own noise (2048 spp) is negligible.
    for (const Region& r : regions()) {
        RegionStats a = regionStats(ours, r), b = regionStats(ref, r);
        double rel = (a.mean - b.mean) / b.mean;
        double tol = (r.name == "image" ? 0.01 : 0.02) + 4.0 * a.stderr_ / b.mean;
        INFO(r.name << ": effigi " << a.mean << " ± " << a.stderr_ << ", mitsuba " << b.mean << ", relative "
                    << rel << ", tolerance " << tol);
        CHECK(std::abs(rel) < tol);
        CHECK(tol < 0.06);  // the test must stay sharp enough to catch real errors
    }
}
