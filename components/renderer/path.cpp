// renderer "path" — unidirectional spectral path tracing with next-event estimation.
//
// Each pixel is an integral over primary sample space, estimated by the numerical
// IIntegrator nested in the renderer (default `mean`) from the camera's sampler: EFFIGI's
// "pick and mix". A path samples four hero wavelengths, adds emission found by BSDF
// sampling and by light sampling, weighted by multiple importance sampling with the power
// heuristic (Veach & Guibas 1995), and is ended by Russian roulette after rr_depth.
// Parameters: max_depth (longest path in segments, −1 = unbounded; 1 = emitters seen
// directly, 2 = direct lighting — Mitsuba's convention), rr_depth, hide_emitters.
// Reference: Kajiya 1986, "The Rendering Equation"; Veach 1997, PhD thesis, ch. 9.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/iintegrator.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/render/image_metrics.hpp"
#include "effigi/render/spectral_bins.hpp"
#include "effigi/render/tile_renderer.hpp"
#include "effigi/spectral/cie.hpp"
#include "effigi/spectral/colorspace.hpp"

namespace effigi {
namespace {

inline float powerHeuristic(float a, float b) {
    float a2 = a * a, b2 = b * b;
    return a2 + b2 > 0.f ? a2 / (a2 + b2) : 0.f;
}

class PathTracer {
public:
    PathTracer(const Scene& scene, int maxDepth, int rrDepth, bool hideEmitters)
        : m_scene(scene), m_maxDepth(maxDepth < 0 ? std::numeric_limits<int>::max() : maxDepth),
          m_rrDepth(rrDepth), m_hideEmitters(hideEmitters) {}

    SampledSpectrum li(Ray ray, SampledWavelengths& lambda, ISampler& sampler) const {
        SampledSpectrum L(0.f), beta(1.f);
        bool specular = false;
        float prevPdf = 1.f, etaScale = 1.f;
        Point3f prevP = ray.o;
        SurfaceInteraction si;

        for (int depth = 1;; ++depth) {  // depth = segments traced so far
            if (!m_scene.intersect(ray, si)) {
                for (const IEmitter* env : m_scene.environments()) {
                    SampledSpectrum Le = env->evalEnvironment(ray.d, lambda);
                    if (depth == 1 && m_hideEmitters) continue;
                    float w = 1.f;
                    if (depth > 1 && !specular)
                        w = powerHeuristic(prevPdf, m_scene.emitterProbability(env) * env->pdfEnvironment(prevP, ray.d));
                    L += beta * Le * w;
                }
                break;
            }
            if (si.emitter && !(depth == 1 && m_hideEmitters)) {
                SampledSpectrum Le = si.emitter->eval(si, lambda);
                if (!Le.isBlack()) {
                    float w = 1.f;
                    if (depth > 1 && !specular)
                        w = powerHeuristic(prevPdf, m_scene.emitterProbability(si.emitter) *
                                                        si.emitter->pdfDirect(prevP, si));
                    L += beta * Le * w;
                }
            }
            if (depth >= m_maxDepth || !si.bsdf) break;

            const IBSDF& bsdf = *si.bsdf;
            Vector3f wo = si.toLocal(si.wo);
            // Always draw the light-sampling dimensions so every path uses the same layout.
            float uLight = sampler.get1D();
            Point2f uLight2 = sampler.get2D();
            if (!bsdf.isPureSpecular()) L += beta * directLight(si, bsdf, wo, uLight, uLight2, lambda);

            float uc = sampler.get1D();
            Point2f u = sampler.get2D();
            std::optional<BSDFSample> bs = bsdf.sample(si, wo, uc, u, lambda, TransportMode::Radiance);
            if (!bs || bs->pdf <= 0.f || bs->f.isBlack()) break;
            beta *= bs->f * (std::abs(bs->wi.z) / bs->pdf);
            specular = bs->isSpecular();
            prevPdf = bs->pdf;
            prevP = si.p;
            if (bs->isTransmission()) etaScale *= sqr(bs->eta);
            ray = si.spawnRay(si.toWorld(bs->wi));

            // Russian roulette on the throughput with the radiance scale of refraction
            // removed, so paths inside glass are not killed for being "bright".
            if (depth >= m_rrDepth) {
                float q = std::min(beta.maxValue() * etaScale, 0.95f);
                if (sampler.get1D() >= q) break;
                beta *= 1.f / q;
            }
        }
        return L;
    }

private:
    SampledSpectrum directLight(const SurfaceInteraction& si, const IBSDF& bsdf, const Vector3f& wo, float uSel,
                                const Point2f& u, const SampledWavelengths& lambda) const {
        float selPdf;
        const IEmitter* emitter = m_scene.sampleEmitter(uSel, selPdf);
        if (!emitter) return SampledSpectrum(0.f);
        EmitterSample es = emitter->sampleDirect(si.p, u, lambda);
        if (es.pdf <= 0.f || es.L.isBlack()) return SampledSpectrum(0.f);
        Vector3f wi = si.toLocal(es.wi);
        SampledSpectrum f = bsdf.f(si, wo, wi, lambda, TransportMode::Radiance) * std::abs(wi.z);
        if (f.isBlack()) return SampledSpectrum(0.f);
        Ray shadow = std::isinf(es.dist) ? si.spawnRay(es.wi) : si.spawnRayTo(es.p);
        if (m_scene.occluded(shadow)) return SampledSpectrum(0.f);
        float lightPdf = selPdf * es.pdf;
        float w = es.delta ? 1.f : powerHeuristic(lightPdf, bsdf.pdf(si, wo, wi, lambda, TransportMode::Radiance));
        return f * es.L * (w / lightPdf);
    }

    const Scene& m_scene;
    int m_maxDepth, m_rrDepth;
    bool m_hideEmitters;
};

/// One pixel's integrand in primary sample space: a film position, wavelengths and a
/// path, splatted into the block as XYZ; its value for the integrator is the sample's
/// linear RGB, so the integrator's variance is the pixel's per channel.
class PixelIntegrand final : public Implements<IFunction> {
public:
    PixelIntegrand(const PathTracer& tracer, const ICamera& camera, Point2f filmOffset, const SpectralBinning& bins)
        : m_tracer(tracer), m_camera(camera), m_filmOffset(filmOffset), m_bins(bins) {}

    void reset(Point2i pixel, ImageBlock* block, TileStats* stats) {
        m_pixel = pixel;
        m_block = block;
        m_stats = stats;
    }
    int dimension() const override { return 0; }
    int channels() const override { return 3; }
    void eval(ISampler& sampler, std::span<double> out) override {
        SampledWavelengths lambda = SampledWavelengths::sampleVisible(sampler.get1D());
        Point2f pFilm = Point2f(m_pixel) + sampler.getPixel2D();
        CameraSample cs{pFilm + m_filmOffset, sampler.get2D(), 0.f};
        SampledSpectrum weight(1.f);
        Ray ray = m_camera.generateRay(cs, lambda, weight);
        SampledSpectrum L = weight * m_tracer.li(ray, lambda, sampler);
        Vector3f xyz = cie::toXYZ(L, lambda);
        // X, Y, Z, then the film's spectral bins, if it records any (fixed size: no allocation).
        float v[3 + SpectralBinning::MaxBins];
        if (!isFinite(xyz) || !m_bins.estimate(L, lambda, v + 3)) {  // keep NaN/Inf off the film; counted
            ++m_stats->rejected;
            xyz = Vector3f(0.f);
            std::fill(v + 3, v + 3 + m_bins.count(), 0.f);
        }
        v[0] = xyz.x, v[1] = xyz.y, v[2] = xyz.z;
        ++m_stats->samples;
        m_block->put(pFilm, v);
        Vector3f rgb = xyzToLinearSRGB(xyz);
        out[0] = rgb.x, out[1] = rgb.y, out[2] = rgb.z;
    }

private:
    const PathTracer& m_tracer;
    const ICamera& m_camera;
    Point2f m_filmOffset;
    const SpectralBinning& m_bins;
    Point2i m_pixel{0};
    ImageBlock* m_block = nullptr;
    TileStats* m_stats = nullptr;
};

class PathRenderer final : public Implements<IRenderer> {
public:
    static Schema schema() {
        Schema s("renderer", "path", "Unidirectional spectral path tracer with next-event estimation and MIS.");
        s.cite("Veach 1997, Robust Monte Carlo Methods for Light Transport Simulation, ch. 9");
        s.integer("max_depth", -1, "Longest path in segments (-1: unbounded; 1: emitters only)").atLeast(-1);
        s.integer("rr_depth", 5, "Depth from which Russian roulette may end paths").atLeast(1);
        s.boolean("hide_emitters", false, "Do not show emitters seen directly by the camera");
        s.child("integrator", "integrator", "Numerical integrator estimating each pixel (default: mean)");
        return s;
    }

    explicit PathRenderer(const Properties& p)
        : m_maxDepth(int(p.getInt("max_depth"))), m_rrDepth(int(p.getInt("rr_depth"))),
          m_hideEmitters(p.getBool("hide_emitters")), m_integrator(p.get<IIntegrator>("integrator")) {
        if (!m_integrator) {
            Properties ip("integrator", "mean");
            m_integrator = query<IIntegrator>(Registry::instance().create("integrator", "mean", ip));
        }
    }

    RenderStats render(const Scene& scene, const RenderControl& control) override {
        PathTracer tracer(scene, m_maxDepth, m_rrDepth, m_hideEmitters);
        const ICamera& camera = scene.camera();
        Point2f offset(camera.film().cropOffset());
        const auto [lambdaMin, lambdaMax] = camera.film().spectralRange();
        const SpectralBinning bins(camera.film().spectralBins(), lambdaMin, lambdaMax);
        std::vector<std::string> channels{"X", "Y", "Z"};
        for (std::string& c : bins.channelNames()) channels.push_back(std::move(c));
        Vector2i size = camera.film().size();
        if (!control.accumulate || m_pixels.size() != std::size_t(size.x) * size.y)
            m_pixels.assign(std::size_t(size.x) * size.y, PixelEstimate{});
        m_filterFactor = filterVarianceFactor(camera.film().filter());
        return renderTiles(scene, control, channels, "Rendering",
                           [&](const Point2i& px, SampleRange range, ISampler& sampler, ImageBlock& block,
                               TileStats& stats) {
                               PixelIntegrand f(tracer, camera, offset, bins);
                               f.reset(px, &block, &stats);
                               sampler.startPixel(px);
                               Estimate e = m_integrator->integrate(f, sampler, range.first, range.count);
                               m_pixels[std::size_t(px.y) * size.x + px.x].merge(e);
                           });
    }

    bool varianceEstimate(std::vector<float>& variance) const override {
        // The integrator's variance is that of the samples drawn for the pixel; the film
        // pixel is a filtered average over neighbouring pixels' samples too.
        variance.resize(3 * m_pixels.size());
        for (std::size_t i = 0; i < m_pixels.size(); ++i)
            for (int c = 0; c < 3; ++c) variance[3 * i + c] = float(m_pixels[i].variance[c] * m_filterFactor);
        return !m_pixels.empty();
    }

private:
    int m_maxDepth, m_rrDepth;
    bool m_hideEmitters;
    Ref<IIntegrator> m_integrator;

    /// Each pixel's estimate pooled over the passes so far: the integrator's own error
    /// estimate, which `effigi converge` and noise-target rendering read.
    /// Compact per-pixel pooled estimate (28 bytes: a 4K film needs 230 MB as Estimates).
    struct PixelEstimate {
        float mean[3] = {0.f, 0.f, 0.f}, variance[3] = {0.f, 0.f, 0.f};
        std::uint32_t samples = 0;
        void merge(const Estimate& e) {
            Estimate pooled;
            pooled.channels = 3;
            pooled.samples = samples;
            for (int c = 0; c < 3; ++c) pooled.mean[c] = mean[c], pooled.variance[c] = variance[c];
            pooled.merge(e);
            for (int c = 0; c < 3; ++c) mean[c] = float(pooled.mean[c]), variance[c] = float(pooled.variance[c]);
            samples = std::uint32_t(std::min<std::uint64_t>(pooled.samples, 0xffffffffu));
        }
    };
    std::vector<PixelEstimate> m_pixels;  // written by disjoint pixels in parallel
    double m_filterFactor = 1.0;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::PathRenderer)
