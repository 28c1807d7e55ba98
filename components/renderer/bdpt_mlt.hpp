#pragma once
// The bidirectional inner estimator of renderer `pssmlt` (its `technique` "bdpt"):
// every strategy of bidirectional path tracing (bdpt_sample.hpp) evaluated on a point of
// primary sample space, the camera subpath read from stream 0, the light subpath from
// stream 1 and the connections from stream 2, so that a mutation of one subpath leaves the
// other's coordinates where they were (Kelemen et al. 2002 §5; pbrt-v3 §16.4.4).
// The camera-side strategies give one contribution at the film position drawn; each
// light-tracing strategy (t = 1) one where it lands, scaled from bdpt's convention
// (importance normalised over the full film) to MLTSplat's (pixel = P · E[splats], P the
// crop window's pixels): by (full-film pixels) / P.
#include "bdpt_sample.hpp"
#include "mlt_estimator.hpp"

#include <vector>

namespace effigi {

class BdptMLTEstimator final : public MLTEstimator {
public:
    BdptMLTEstimator(const Scene& scene, int maxDepth, int rrDepth, bool hideEmitters, int minLength,
                     const IPathGenerator& generator)
        : m_ctx(makePathContext(scene, maxDepth, rrDepth, generator, "renderer 'pssmlt' with technique 'bdpt'")),
          m_camera(scene.camera()), m_hideEmitters(hideEmitters), m_minLength(minLength),
          m_offset(scene.camera().film().cropOffset()) {
        const Vector2i full = scene.camera().film().fullSize(), size = scene.camera().film().size();
        m_splatScale = float(double(full.x) * double(full.y) / (double(size.x) * double(size.y)));
    }

    int streamCount() const override { return 3; }

    void evaluate(ISampler& sampler, std::vector<MLTSplat>& splats) const override {
        // Per-thread storage: evaluate() is called from every chain's thread.
        thread_local bdpt::Subpaths paths;
        thread_local std::vector<std::pair<Point2f, SampledSpectrum>> lightTraced;
        lightTraced.clear();
        MLTCameraSample cs = mltCameraSample(m_camera, sampler);
        if (cs.weight.isBlack()) return;
        SampledWavelengths& lambda = cs.lambda;
        SampledSpectrum L(0.f);
        // A strategy (s, t) samples paths of s + t − 1 segments.
        bdpt::sample(
            m_ctx, m_hideEmitters, cs.ray, cs.weight, sampler, lambda, paths, [&](int k) { mltStartStream(sampler, k); },
            [&](int s, int t, const SampledSpectrum& c) {
                if (s + t - 1 >= m_minLength) L += c;
            },
            [&](int s, const SampledSpectrum& c, const Point2f& pFull) {
                if (s >= m_minLength) lightTraced.emplace_back(pFull - m_offset, c);
            });
        // The wavelengths are final only now (dispersion may end the secondary ones).
        if (!L.isBlack()) splats.push_back({cs.pFilm, cie::toXYZ(L, lambda)});
        for (const auto& [p, c] : lightTraced) splats.push_back({p, cie::toXYZ(c, lambda) * m_splatScale});
    }

private:
    bdpt::Context m_ctx;
    const ICamera& m_camera;
    bool m_hideEmitters;
    int m_minLength;
    Point2f m_offset;
    float m_splatScale = 1.f;
};

} // namespace effigi
