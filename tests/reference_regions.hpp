#pragma once
// End-to-end comparison against a Mitsuba 3 reference image, shared by test_plastic and
// test_mask_null: render a scene of tests/data at low spp, then compare the mean of each
// colour channel over image regions with the reference's, allowing a systematic margin
// plus a multiple of our estimate's standard error (the renderer's own variance
// estimate; the films must use the box filter).
#include "image_helpers.hpp"

#include "effigi/interfaces/ifilm.hpp"
#include "effigi/render/scene.hpp"
#include "effigi/xml/loader.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <cstdint>
#include <string>
#include <vector>

namespace effigi::test {

/// A region in fractions of the image, [x0, x1) × [y0, y1), top row first.
struct Region {
    std::string name;
    float x0, y0, x1, y1;
};

/// Mean of channel c over the region, and (from the per-pixel variances `var`, 3 per
/// pixel, when given) its standard error: pixels of a box-filtered film are independent.
template <typename At>
void regionStats(int w, int h, const Region& r, int c, const At& at, const std::vector<float>* var, double& mean,
                 double& stderror) {
    int x0 = int(r.x0 * w), x1 = int(r.x1 * w), y0 = int(r.y0 * h), y1 = int(r.y1 * h);
    double sum = 0, v = 0;
    int n = 0;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            sum += at(x, y, c);
            if (var) v += (*var)[3 * (std::size_t(y) * w + x) + c];
            ++n;
        }
    mean = sum / n;
    stderror = std::sqrt(v) / n;
}

/// Renders `scene` (relative to the source tree, or absolute) with `defines` and checks every region's
/// R, G, B means against `reference`: |ours − ref| / ref < margin + 4 standard errors
/// (two-sided false alarm 6e-5 per comparison; the render is seeded, so the outcome is
/// deterministic). The reference's own noise (4096 spp) is negligible. `maxTol` bounds the
/// relative tolerance so the comparison stays sharp; `seed` is the render's seed.
inline void compareWithReference(const std::string& scene, const std::string& reference,
                                 const std::vector<std::pair<std::string, std::string>>& defines,
                                 const std::vector<Region>& regions, double margin, double maxTol = 0.08,
                                 std::uint64_t seed = 0) {
    xml::ParseOptions opt;
    for (const auto& [k, v] : defines) opt.defines[k] = v;
    // Relative to the source tree; an absolute path (a corpus checkout) as it is.
    auto s = loadSceneFile(std::filesystem::path(EFFIGI_SOURCE_DIR) / scene, opt);
    RenderControl control;
    control.progress = false;
    control.seed = seed;
    RenderStats stats = s->renderer().render(*s, control);
    CHECK(stats.rejectedSamples == 0);
    Image img = s->camera().film().develop();
    std::vector<float> var;
    REQUIRE(s->renderer().varianceEstimate(var));  // the pixel estimates' own variances
    ExrImage ref = readExr(std::filesystem::path(EFFIGI_SOURCE_DIR) / reference);
    REQUIRE(ref.spec.width == img.width);
    REQUIRE(ref.spec.height == img.height);
    for (const Region& r : regions)
        for (int c = 0; c < 3; ++c) {
            double a, se, b, seRef;
            regionStats(img.width, img.height, r, c, [&](int x, int y, int ch) { return img.at(x, y, ch); }, &var, a, se);
            regionStats(img.width, img.height, r, c, [&](int x, int y, int ch) { return ref.at(x, y, ch); }, nullptr, b, seRef);
            double rel = (a - b) / b, tol = margin + 4.0 * se / b;
            INFO(scene << " " << r.name << " channel " << c << ": effigi " << a << " ± " << se << ", mitsuba " << b
                       << ", relative " << rel << ", tolerance " << tol);
            CHECK(std::abs(rel) < tol);
            CHECK(tol < maxTol);  // sharp enough to catch a real error (a missing term is > 10 %)
        }
}

} // namespace effigi::test
