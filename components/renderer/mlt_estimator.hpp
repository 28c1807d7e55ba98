#pragma once
// The inner estimators of primary sample space Metropolis (renderer `pssmlt`): a function
// from a point of primary sample space, read through an ISampler, to film contributions.
// A unidirectional path gives one contribution, at the film position it drew; a
// bidirectional estimator gives several (its t = 1 strategies land elsewhere on the film).
// Metropolis samples the points in proportion to the target function: the sum over the
// contributions of mltTarget(xyz), their luminance Y (Kelemen et al. 2002; pbrt-v3 uses
// the luminance of its RGB, pbrt-v4 and Mitsuba 0.6 of the spectrum). Y is floored at
// 1 % of X + Y + Z: four hero wavelengths can carry colour with no luminance (a path that
// only blue light survives), and a point with contributions but a zero target would never
// be visited — a bias; with the floor every contribution is reachable and each splat's
// weight xyz / target stays below 100 per channel.
//
// To add an estimator (bdpt): derive from MLTEstimator, draw the camera subpath from
// stream 0, the light subpath from stream 1 and connections from stream 2 (call
// mltStartStream(sampler, s) before each; streamCount() = 3), append every strategy's
// MIS-weighted contribution with the film position it projects to, leave out the paths
// shorter than minLength segments (3 when pssmlt renders direct light apart, else 1),
// and construct it in pssmlt.cpp's makeEstimator for its `technique` name.
#include "path_core.hpp"
#include "pss_sampler.hpp"

#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/spectral/cie.hpp"

#include <vector>

namespace effigi {

/// One film contribution: CIE XYZ at a film position in the crop window's frame (what
/// ImageBlock::put takes: pixel (i, j) covers [i, i+1) × [j, j+1)). The units are a
/// pixel's: over the P pixels of the crop window, pixel j = P · E[Σ xyz of the splats
/// landing in j], the expectation over uniform primary samples: a camera path drawn at a
/// uniform film position splats its radiance; a light path connected to the camera what
/// ptracer splats times ptracer's spp (its importance integrates to 1 over the film).
struct MLTSplat {
    Point2f pFilm;
    Vector3f xyz;
};

/// The target function's share of one contribution: luminance, floored (see above).
inline float mltTarget(const Vector3f& xyz) {
    return std::max(xyz.y, 0.01f * (xyz.x + xyz.y + xyz.z));
}
inline float mltTarget(const std::vector<MLTSplat>& splats) {
    float f = 0.f;
    for (const MLTSplat& s : splats) f += mltTarget(s.xyz);
    return f;
}

/// The start of every estimator's point, on stream 0: a film position uniform over the
/// crop window (crop frame; first, so a small step moves it by about sigma of the film's
/// width), hero wavelengths, the lens, and the camera ray they give.
struct MLTCameraSample {
    Point2f pFilm;
    SampledWavelengths lambda;
    SampledSpectrum weight{1.f};
    Ray ray;
};
inline MLTCameraSample mltCameraSample(const ICamera& camera, ISampler& sampler) {
    mltStartStream(sampler, 0);
    const Vector2i size = camera.film().size();
    const Point2f u = sampler.get2D();
    MLTCameraSample cs;
    cs.pFilm = Point2f(u.x * float(size.x), u.y * float(size.y));
    cs.lambda = SampledWavelengths::sampleVisible(sampler.get1D());
    cs.ray = camera.generateRay({cs.pFilm + Point2f(camera.film().cropOffset()), sampler.get2D(), 0.f}, cs.lambda,
                                cs.weight);
    return cs;
}

class MLTEstimator {
public:
    virtual ~MLTEstimator() = default;
    /// Streams the estimator reads (PrimarySampleSpaceSampler's interleaving).
    virtual int streamCount() const { return 1; }
    /// Evaluate the point `sampler` holds: append its contributions to `splats` (not
    /// cleared). Every value must come from `sampler`, so that the same values give the
    /// same contributions; non-finite contributions are the caller's to reject.
    virtual void evaluate(ISampler& sampler, std::vector<MLTSplat>& splats) const = 0;
};

/// Unidirectional path tracing (PathIntegrator, next-event estimation and MIS) from a
/// film position drawn uniformly over the crop window: the film position (2D), hero
/// wavelengths (1D), lens (2D), then the path's dimensions. The film position comes first
/// so that a small step moves the path's pixel by about sigma of the film's width.
/// With `minLength` > 1 only paths of at least that many segments count (emission found
/// at segment k, or by a shadow ray from the vertex ending segment k − 1, has length k).
class PathMLTEstimator final : public MLTEstimator {
public:
    PathMLTEstimator(const Scene& scene, int maxDepth, int rrDepth, bool hideEmitters, int minLength = 1)
        : m_scene(scene), m_camera(scene.camera()), m_path(scene, maxDepth, rrDepth, hideEmitters),
          m_minLength(minLength) {}

    void evaluate(ISampler& sampler, std::vector<MLTSplat>& splats) const override {
        MLTCameraSample cs = mltCameraSample(m_camera, sampler);
        if (cs.weight.isBlack()) return;
        const Ray& ray = cs.ray;
        const Point2f& pFilm = cs.pFilm;
        SampledWavelengths& lambda = cs.lambda;
        const SampledSpectrum& weight = cs.weight;
        const SampledSpectrum L =
            weight * (m_minLength > 1 ? longPaths(ray, lambda, sampler) : m_path.li(ray, lambda, sampler));
        if (L.isBlack()) return;
        splats.push_back({pFilm, cie::toXYZ(L, lambda)});
    }

private:
    /// PathIntegrator::li's loop keeping the paths of m_minLength segments or more.
    SampledSpectrum longPaths(const Ray& ray, SampledWavelengths& lambda, ISampler& sampler) const {
        PathState s(ray);
        SurfaceInteraction si;
        SampledSpectrum L(0.f);
        std::optional<ShadowRay> shadow;
        if (!m_scene.intersect(s.ray, si)) return L;  // environment seen directly: one segment
        for (;;) {
            const int depth = s.depth;  // segments up to si
            s.L = SampledSpectrum(0.f);
            const bool more = m_path.scatter(s, si, lambda, sampler, shadow);
            if (depth >= m_minLength) L += s.L;
            if (shadow && depth + 1 >= m_minLength)
                L += shadow->contribution * m_path.shadowTransmittance(shadow->ray, lambda);
            if (!more) break;
            if (!m_scene.intersect(s.ray, si)) {
                s.L = SampledSpectrum(0.f);
                m_path.miss(s, lambda);
                if (s.depth >= m_minLength) L += s.L;
                break;
            }
        }
        return L;
    }

    const Scene& m_scene;
    const ICamera& m_camera;
    PathIntegrator m_path;
    int m_minLength;
};

} // namespace effigi
