#pragma once
// The image-space loop shared by renderers: the film is cut into tiles rendered in
// parallel (oneTBB), each thread with its own sampler clone and image block; tiles are
// merged into the film as they finish. Progress, thread count and SIGINT come from the
// RenderControl.
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/render/image_block.hpp"
#include "effigi/render/scene.hpp"

#include <functional>
#include <string>
#include <vector>

namespace effigi {

/// Per-thread counters a pixel function adds to.
struct TileStats {
    std::uint64_t samples = 0;
    std::uint64_t rejected = 0;
};

/// The sample indices a pass renders in every pixel: [first, first + count).
struct SampleRange {
    std::uint64_t first = 0, count = 0;
};

/// Renders one pixel (film coordinates of the crop window) into the block.
using PixelFunction = std::function<void(const Point2i& pixel, SampleRange samples, ISampler& sampler,
                                         ImageBlock& block, TileStats& stats)>;

/// Prepare the camera's film with `channels` (unless control.accumulate), render the
/// pass's samples of every pixel, merge. `label` names the progress bar.
RenderStats renderTiles(const Scene& scene, const RenderControl& control, const std::vector<std::string>& channels,
                        const std::string& label, const PixelFunction& pixel);

/// renderTiles for renderers that average independent camera samples into X, Y, Z: per
/// sample a film position, hero wavelengths and a camera ray, then `xyzOf(ray, lambda,
/// weight, sampler)` gives the sample's XYZ, `weight` being the camera's importance
/// weight of the ray. NaN/Inf samples are kept off the film and counted.
template <typename XYZOf>
RenderStats renderCameraSamples(const Scene& scene, const RenderControl& control, XYZOf&& xyzOf) {
    const ICamera& camera = scene.camera();
    const Point2f offset(camera.film().cropOffset());
    return renderTiles(
        scene, control, {"X", "Y", "Z"}, "Rendering",
        [&](const Point2i& px, SampleRange range, ISampler& sampler, ImageBlock& block, TileStats& ts) {
            sampler.startPixel(px);
            for (std::uint64_t k = range.first; k < range.first + range.count; ++k) {
                sampler.startSample(k);
                const Point2f pFilm = Point2f(px) + sampler.getPixel2D();
                SampledWavelengths lambda = SampledWavelengths::sampleVisible(sampler.get1D());
                SampledSpectrum weight(1.f);
                Ray ray = camera.generateRay({pFilm + offset, sampler.get2D(), 0.f}, lambda, weight);
                Vector3f xyz = xyzOf(ray, lambda, weight, sampler);
                if (!isFinite(xyz)) {
                    ++ts.rejected;
                    xyz = Vector3f(0.f);
                }
                ++ts.samples;
                block.put(pFilm, &xyz.x);
            }
        });
}

} // namespace effigi
