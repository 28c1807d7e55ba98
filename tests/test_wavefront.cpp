// path's wavefront mode (a tile's paths advance together, rays traced in batches) against
// the one-path-at-a-time loop, the readable reference: the same estimator, so
//  - with the same seed both draw the same random numbers for every sample and the
//    images agree pixel for pixel up to float round-off (a path whose Russian roulette or
//    sampling decision flips on the last bit may differ, so a few pixels are allowed);
//  - with independent seeds, every region's mean agrees within the two renders' own
//    standard errors (the renderer's per-pixel variance estimates, box filter).
// On the Cornell box, the glossy Cornell box (rough conductor, glass) and a textured
// scene under an environment map. Also: the wavefront's ray counts (effigi render --stats).
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/render/scene.hpp"
#include "effigi/xml/loader.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

using namespace effigi;

namespace {

struct Rendered {
    Image img;
    std::vector<float> var;
    RenderStats stats;
};

Rendered render(const std::string& scene, bool wavefront, int seed, int spp) {
    xml::ParseOptions opt;
    opt.defines["wavefront"] = wavefront ? "true" : "false";
    opt.defines["seed"] = std::to_string(seed);
    opt.defines["spp"] = std::to_string(spp);
    auto s = loadSceneFile(std::string(EFFIGI_SOURCE_DIR) + "/tests/data/wavefront/" + scene, opt);
    RenderControl control;
    control.progress = false;
    Rendered r;
    r.stats = s->renderer().render(*s, control);
    r.img = s->camera().film().develop();
    REQUIRE(s->renderer().varianceEstimate(r.var));
    return r;
}

const char* const Scenes[] = {"cornell.xml", "glossy.xml", "textured_env.xml"};

} // namespace

TEST_CASE("wavefront and one-path loop draw the same samples with the same seed", "[wavefront]") {
    for (const char* scene : Scenes) {
        Rendered a = render(scene, true, 7, 16), b = render(scene, false, 7, 16);
        REQUIRE(a.img.width == b.img.width);
        REQUIRE(a.img.height == b.img.height);
        CHECK(a.stats.samples == b.stats.samples);
        std::size_t differ = 0, pixels = std::size_t(a.img.width) * std::size_t(a.img.height);
        for (int y = 0; y < a.img.height; ++y)
            for (int x = 0; x < a.img.width; ++x) {
                bool same = true;
                for (int c = 0; c < 3; ++c) {
                    float u = a.img.at(x, y, c), v = b.img.at(x, y, c);
                    same = same && std::abs(u - v) <= 1e-4f * std::max(1.f, std::abs(v));
                }
                differ += same ? 0 : 1;
            }
        INFO(scene << ": " << differ << " of " << pixels << " pixels differ");
        // A dimension drawn in another order would change nearly every pixel.
        CHECK(differ * 100 <= pixels);
    }
}

TEST_CASE("wavefront and one-path loop agree region by region with independent seeds", "[wavefront]") {
    // 4 x 4 regions and the whole image, 3 channels, 3 scenes: 153 comparisons at 4.5
    // standard errors of the difference (two-sided 6.8e-6 each, about 1e-3 for all of
    // them). Both renders are seeded, so the outcome is deterministic.
    for (const char* scene : Scenes) {
        Rendered a = render(scene, true, 1, 64), b = render(scene, false, 2, 64);
        const int w = a.img.width, h = a.img.height;
        for (int region = 0; region < 17; ++region) {
            int x0 = 0, y0 = 0, x1 = w, y1 = h;
            if (region < 16) x0 = (region % 4) * w / 4, x1 = x0 + w / 4, y0 = (region / 4) * h / 4, y1 = y0 + h / 4;
            for (int c = 0; c < 3; ++c) {
                double ma = 0, mb = 0, va = 0, vb = 0;
                for (int y = y0; y < y1; ++y)
                    for (int x = x0; x < x1; ++x) {
                        ma += a.img.at(x, y, c), mb += b.img.at(x, y, c);
                        std::size_t i = 3 * (std::size_t(y) * std::size_t(w) + std::size_t(x)) + std::size_t(c);
                        va += a.var[i], vb += b.var[i];
                    }
                const double n = double((x1 - x0) * (y1 - y0));
                const double se = std::sqrt(va + vb) / n;
                INFO(scene << " region " << region << " channel " << c << ": wavefront " << ma / n << ", loop "
                           << mb / n << ", standard error of the difference " << se);
                CHECK(std::abs(ma - mb) / n <= 4.5 * se + 1e-6);
            }
        }
    }
}

TEST_CASE("wavefront counts its rays by kind", "[wavefront]") {
    Rendered r = render("cornell.xml", true, 0, 4);
    const WorkStats& w = r.stats.work;
    REQUIRE(w.kept);
    // One camera ray per sample; in the closed box every camera ray hits, and every path
    // that reaches a diffuse wall draws a light sample, so there are extension and shadow
    // rays, but no more extension rays per sample than max_depth − 1 = 7.
    CHECK(w.rays[WorkStats::Camera] == r.stats.samples);
    CHECK(w.rays[WorkStats::Extension] > r.stats.samples);
    CHECK(w.rays[WorkStats::Extension] <= 7 * r.stats.samples);
    CHECK(w.rays[WorkStats::Shadow] > r.stats.samples);
    CHECK(w.shadeSeconds > 0.0);
    Rendered loop = render("cornell.xml", false, 0, 4);
    CHECK_FALSE(loop.stats.work.kept);  // the one-path loop keeps no counts
}
