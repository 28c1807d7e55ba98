#pragma once
// Parts of renderer `pssmlt` (pssmlt.cpp): the bootstrap's two halves, the chains' splats
// and their normalisation, and the direct light it renders apart.
//
// Direct light is rendered apart from the Metropolis chains as Mitsuba 0.6's MLT renderers
// do (their `directSamples`): paths of one and two segments (emitters seen directly, and
// emitters reached from the first surface by light sampling and BSDF sampling,
// MIS-weighted) by the ordinary path estimator at max_depth 2 from the camera's own
// sampler, and the chains then sample only paths of three segments and more. The
// lengths ≤ 2 part of `path` is exactly this estimator (the same two techniques, the same
// weights), so the sum is the full image. It spares the chains the emitters seen directly,
// a hundred times brighter than the walls around them, which hold a chain for hundreds of
// mutations once it gets there (the image's noise in the large).
// The pixel values are the film's own weighted average of each pixel's samples.
#include "mlt_estimator.hpp"

#include "effigi/core/progress.hpp"
#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/render/tile_renderer.hpp"
#include "effigi/spectral/cie.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <vector>

namespace effigi::pssmlt {

/// f of a point's contributions, 0 (and counted) when any is not finite.
inline float targetOf(const std::vector<MLTSplat>& splats, std::uint64_t& rejected) {
    for (const MLTSplat& s : splats)
        if (!isFinite(s.xyz) || !isFinite(Vector3f(s.pFilm.x, s.pFilm.y, 0.f))) {
            ++rejected;
            return 0.f;
        }
    const float f = mltTarget(splats);
    return std::isfinite(f) ? f : (++rejected, 0.f);
}

/// Seed of the `index`-th stream of one kind of a pass: bootstrap points (0), chains'
/// acceptance and start choice (1), chains' mutations (2).
inline std::uint64_t streamSeed(std::uint64_t passSeed, std::uint64_t kind, std::uint64_t index) {
    return mixBits(passSeed ^ mixBits(3 * index + kind + 1));
}

/// Half of the bootstrap points (even or odd indices): their f summed cumulatively, to
/// draw chain starts in proportion to f, and their mean.
struct BootstrapHalf {
    std::vector<double> cdf;
    std::vector<std::uint64_t> index;
    double mean = 0.0;

    /// The point a chain starts at for the uniform number u: P(i) = f(i) / Σ f.
    std::uint64_t draw(double u) const {
        const double x = u * cdf.back();
        std::size_t k = std::size_t(std::upper_bound(cdf.begin(), cdf.end(), x) - cdf.begin());
        k = std::min(k, cdf.size() - 1);
        while (k > 0 && cdf[k] == cdf[k - 1]) --k;  // rounding at the end: the last f > 0
        return index[k];
    }
};


/// The bootstrap points' f split into halves of even and odd index.
inline std::array<BootstrapHalf, 2> splitBootstrap(const std::vector<float>& f) {
    std::array<BootstrapHalf, 2> halves;
    for (std::size_t i = 0; i < f.size(); ++i) {
        BootstrapHalf& h = halves[i % 2];
        h.cdf.push_back((h.cdf.empty() ? 0.0 : h.cdf.back()) + double(f[i]));
        h.index.push_back(i);
    }
    for (BootstrapHalf& h : halves) h.mean = h.cdf.empty() ? 0.0 : h.cdf.back() / double(h.cdf.size());
    return halves;
}

/// Splats onto a whole-film block: each splat adds value · w(centre − p) to the pixels
/// within the filter's radius of its position p, and normalise() then divides pixel c by
/// ∫ w(c − p) dp over the film. In expectation that is the filtered image the film makes of
/// camera samples (Σ w L / Σ w per pixel), up to the film's edge, where the weights are
/// cut off: splats normalised to sum to 1 wherever they land (ptracer, Mitsuba's
/// normalised image block) darken the edge pixels by the filter's mass beyond the edge
/// (16 % for the default Gaussian) and shift them where the image has a gradient.
class NormalisedSplatter {
public:
    NormalisedSplatter(const FilterTable& filter, Vector2i size)
        : m_mass{mass(filter, size.x), mass(filter, size.y)} {}
    static void put(ImageBlock& block, const std::vector<MLTSplat>& splats, float scale) {
        for (const MLTSplat& s : splats) {
            Vector3f v = s.xyz * scale;
            block.put(s.pFilm, &v.x);
        }
    }
    /// Pixel (x, y) of the film, in the block's storage, divided by its filter mass.
    void normalise(float* pixel, int x, int y) const {
        const float m = m_mass[0][std::size_t(x)] * m_mass[1][std::size_t(y)];
        for (int k = 0; k < 3; ++k) pixel[k] = m > 0.f ? pixel[k] / m : 0.f;
    }

private:
    /// ∫ w(i + 0.5 − p) dp over p in [0, n), for each pixel i (midpoint rule, 64 steps a pixel).
    static std::vector<float> mass(const FilterTable& filter, int n) {
        std::vector<float> out(std::size_t(n), 0.f);
        constexpr int Steps = 64;
        const int reach = int(std::ceil(filter.radius()));
        for (int i = 0; i < n; ++i) {
            double sum = 0.0;
            for (int k = std::max(0, i - reach) * Steps; k < std::min(n, i + reach + 1) * Steps; ++k)
                sum += filter(float(i) + 0.5f - (float(k) + 0.5f) / Steps);
            out[std::size_t(i)] = float(sum / Steps);
        }
        return out;
    }
    std::vector<float> m_mass[2];
};

/// Pixel values (XYZ, crop window, row-major) of paths of at most two segments (fewer
/// when maxDepth < 2) from `spp` camera samples a pixel; `groups` fixed row groups, each
/// with its own block, summed in order (the same image for a seed and group count).
inline std::vector<Vector3f> renderDirectLight(const Scene& scene, int maxDepth, int rrDepth, bool hideEmitters,
                                               std::uint64_t spp, std::uint64_t seed, std::uint64_t groups,
                                               const RenderControl& control, ProgressBar& progress,
                                               std::uint64_t& samples, std::uint64_t& rejected) {
    const ICamera& camera = scene.camera();
    const IFilm& film = camera.film();
    const Vector2i size = film.size();
    const PathIntegrator path(scene, maxDepth < 0 || maxDepth > 2 ? 2 : maxDepth, rrDepth, hideEmitters);
    groups = std::max<std::uint64_t>(1, std::min<std::uint64_t>(groups, std::uint64_t(size.y)));
    std::vector<ImageBlock> blocks(groups);
    std::vector<std::uint64_t> taken(groups, 0), bad(groups, 0);
    tbb::parallel_for(std::uint64_t(0), groups, [&](std::uint64_t g) {
        blocks[g] = film.createBlock(Point2i(0), size);
        Ref<ISampler> sampler = camera.sampler().clone(seed);
        for (int y = int(g * size.y / groups); y < int((g + 1) * size.y / groups); ++y) {
            if (control.stopRequested()) break;
            for (int x = 0; x < size.x; ++x) {
                sampler->startPixel({x, y});
                for (std::uint64_t k = 0; k < spp; ++k) {
                    sampler->startSample(k);
                    FilmSample cs = sampleCamera(camera, *sampler, {x, y});
                    Vector3f xyz = cie::toXYZ(cs.weight * path.li(cs.ray, cs.lambda, *sampler), cs.lambda);
                    if (!isFinite(xyz)) ++bad[g], xyz = Vector3f(0.f);
                    blocks[g].put(cs.pFilm, &xyz.x);
                }
            }
            taken[g] += std::uint64_t(size.x) * spp;
            progress.update(std::uint64_t(size.x) * spp);
        }
    });
    std::vector<Vector3f> out(std::size_t(size.x) * std::size_t(size.y), Vector3f(0.f));
    for (std::uint64_t g = 0; g < groups; ++g) {
        samples += taken[g], rejected += bad[g];
        if (g == 0) continue;
        std::vector<float>& d0 = blocks[0].data();
        const std::vector<float>& d = blocks[g].data();
        for (std::size_t k = 0; k < d0.size(); ++k) d0[k] += d[k];
    }
    for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) {
            const float* p = blocks[0].pixel(x, y);
            if (p[3] > 0.f) out[std::size_t(y) * size.x + x] = Vector3f(p[0], p[1], p[2]) / p[3];
        }
    return out;
}

} // namespace effigi::pssmlt
