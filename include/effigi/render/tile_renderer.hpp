#pragma once
// The image-space loop shared by renderers: the film is cut into tiles rendered in
// parallel (oneTBB), each thread with its own sampler clone and image block; tiles are
// merged into the film as they finish. Progress, thread count and SIGINT come from the
// RenderControl.
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/interfaces/isampler.hpp"
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

} // namespace effigi
