#pragma once
// The image-space loop shared by renderers: the film is cut into tiles rendered in
// parallel (oneTBB), each thread with its own sampler clone and image block; tiles are
// merged into the film as they finish. Progress, thread count and SIGINT come from the
// RenderControl.
#include "effigi/core/properties.hpp"
#include "effigi/interfaces/iaccumulator.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/iintegrator.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/render/image_block.hpp"
#include "effigi/render/scene.hpp"
#include "effigi/render/spectral_bins.hpp"

#include <functional>
#include <string>
#include <vector>

namespace effigi {

/// Per-thread counters a pixel function adds to.
struct TileStats {
    std::uint64_t samples = 0;
    std::uint64_t rejected = 0;
    WorkStats work;
};

/// The sample indices a pass renders in every pixel: [first, first + count).
struct SampleRange {
    std::uint64_t first = 0, count = 0;
};

/// Renders one pixel (film coordinates of the crop window) into the block.
using PixelFunction = std::function<void(const Point2i& pixel, SampleRange samples, ISampler& sampler,
                                         ImageBlock& block, TileStats& stats)>;

/// Renders the pixels [offset, offset + extent) of one tile (film coordinates of the crop
/// window); it should check control.stopRequested() at least once per pixel's worth of work.
using TileFunction = std::function<void(const Point2i& offset, const Vector2i& extent, SampleRange samples,
                                        ISampler& sampler, ImageBlock& block, TileStats& stats)>;

/// Prepare the camera's film with `channels` (unless control.accumulate), render the
/// pass's samples of every tile in parallel, merge. `label` names the progress bar.
RenderStats renderTileBlocks(const Scene& scene, const RenderControl& control, const std::vector<std::string>& channels,
                             const std::string& label, const TileFunction& tile);

/// renderTileBlocks one pixel at a time (the stop request is checked per pixel).
RenderStats renderTiles(const Scene& scene, const RenderControl& control, const std::vector<std::string>& channels,
                        const std::string& label, const PixelFunction& pixel);

/// The start of every camera sample of the sampled renderers, in the order of their
/// sampler dimensions: hero wavelengths (1D), film position (pixel 2D), lens (2D).
struct FilmSample {
    Point2f pFilm;                ///< in the crop window's frame (what ImageBlock::put takes)
    SampledWavelengths lambda;
    SampledSpectrum weight{1.f};  ///< the camera's importance weight of the ray
    Ray ray;
};
FilmSample sampleCamera(const ICamera& camera, ISampler& sampler, const Point2i& pixel);

/// The channels a sampled renderer writes into the camera's film: X, Y, Z, the film's
/// spectral bins (their names and binning), then the renderer's own `extra` channels.
struct SampledChannels {
    SpectralBinning bins;
    std::vector<std::string> names;
};
SampledChannels sampledChannels(const IFilm& film, const std::vector<std::string>& extra = {});

/// The film's channels of one sample: X, Y, Z, the spectral bins, then a renderer's own
/// channels; shared by renderSampled and the renderers that trace many samples at once.
class SampleSplatter {
public:
    /// `extraChannels` floats follow the spectral bins. Owns its scratch buffer.
    SampleSplatter(const SpectralBinning& bins, std::size_t extraChannels);
    /// Where the renderer writes its own channels for the next put (zeroed by put).
    float* extra() { return m_values.data() + 3 + m_binCount; }
    /// Splat radiance L (weight already applied) at pFilm; returns the sample's linear
    /// sRGB. A sample with any NaN/Inf channel is kept off the film (zero) and counted.
    Vector3f put(ImageBlock& block, const Point2f& pFilm, const SampledSpectrum& L, const SampledWavelengths& lambda,
                 TileStats& stats);
    /// put() of a sample the integrator weighs by q (IWeightedSampler): into a block with
    /// one channel more than the film's, the values times q and, last, q itself.
    Vector3f put(ImageBlock& block, const Point2f& pFilm, const SampledSpectrum& L, const SampledWavelengths& lambda,
                 TileStats& stats, float q);

private:
    Vector3f splat(ImageBlock& block, const Point2f& pFilm, const SampledSpectrum& L, const SampledWavelengths& lambda,
                   TileStats& stats, const float* q);

    const SpectralBinning& m_bins;
    std::size_t m_binCount;
    std::vector<float> m_values;  // the film's channels, then one slot for the weight q
};

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

/// A renderer that can estimate one camera sample on its own (Mitsuba's
/// SamplingIntegrator::sample). This is how renderers nest: a wrapper (moment, aov) draws
/// the camera ray itself and asks each nested ISampleRenderer for that sample's radiance
/// and channels, so it sees per-sample values (second moments) and can put several
/// renderers' outputs into one film in one pass. A renderer opts in by implementing this
/// next to IRenderer and rendering through renderSampled(); IRenderer::render() stays the
/// only entry point of a top-level renderer.
class ISampleRenderer : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("ISampleRenderer");
    static constexpr const char* Tag = "renderer";

    /// Names of the channels each sample writes besides colour (Mitsuba's aov_names()).
    virtual std::vector<std::string> sampleChannels() const { return {}; }
    /// Radiance arriving along the camera ray at the sample's wavelengths (a dispersive
    /// event may terminate the secondary wavelengths); further dimensions come from
    /// `sampler`. Writes sampleChannels().size() floats to `channels`.
    virtual SampledSpectrum sampleRadiance(const Scene& scene, const Ray& ray, SampledWavelengths& lambda,
                                           ISampler& sampler, float* channels) const = 0;
};

/// A renderer nested in a wrapper, under the name its channels get: the child's `name`
/// attribute, or "_arg_<i>" (its index among the unnamed ones), as Mitsuba 3 names them.
struct NestedRenderer {
    std::string name;
    Ref<ISampleRenderer> renderer;
};

/// The renderers nested in `p` (children of tag "renderer", in file order). One that
/// cannot render single samples is an error naming the wrapper `p` and the child.
std::vector<NestedRenderer> nestedRenderers(const Properties& p);

/// Each pixel's estimate pooled over the progressive passes so far (the integrator's own
/// error estimate), kept compactly (28 bytes a pixel) for IRenderer::varianceEstimate().
class PixelVariance {
public:
    /// Size the store for the film (cleared unless accumulating into the same size).
    void prepare(const IFilm& film, bool accumulate);
    /// Pool a pass's estimate into pixel `px` (disjoint pixels may merge in parallel).
    void merge(const Point2i& px, const Estimate& e);
    /// Variance of each pixel's R, G, B scaled by the film filter's factor; false if empty.
    bool get(std::vector<float>& variance) const;
    /// The store as sums that add up when two disjoint sample sets are pooled (IAccumulator):
    /// per pixel n, n·mean and M2 + n·mean² of R, G, B (7 doubles), M2 = variance·n·(n − 1),
    /// so that adding them is the pooling of Estimate::merge (Chan, Golub & LeVeque 1979).
    AccumulatorSums saveSums() const;
    /// Put back sums of saveSums() (or pooled ones); the next prepare() with accumulate
    /// keeps them if the film has their size.
    void loadSums(const AccumulatorSums& sums);

private:
    struct Pixel {
        float mean[3] = {0.f, 0.f, 0.f}, variance[3] = {0.f, 0.f, 0.f};
        std::uint32_t samples = 0;
    };
    std::vector<Pixel> m_pixels;
    int m_width = 0;
    double m_filterFactor = 1.0;
};

/// renderTiles for ISampleRenderers: every pixel is an integral over primary sample space
/// estimated by `integrator` (EFFIGI's pick and mix). A sample draws wavelengths, a film
/// position and a camera ray, asks `renderer` for its radiance and channels, and splats
/// X, Y, Z, the film's spectral bins, then renderer.sampleChannels(); the integrand's value
/// is the sample's linear sRGB, whose pooled variance goes to `variance`. NaN/Inf samples
/// are kept off the film (all their channels) and counted.
RenderStats renderSampled(const Scene& scene, const RenderControl& control, const IIntegrator& integrator,
                          const ISampleRenderer& renderer, PixelVariance& variance);

/// The default numerical integrator of renderers that nest one (`mean`).
Ref<IIntegrator> defaultIntegrator();

} // namespace effigi
