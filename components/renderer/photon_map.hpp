#pragma once
// A photon map (Jensen 1996, 2001): photons left on surfaces by light paths, kept in a
// std::vector<Photon> and indexed by an IEventStore over their positions, and the
// radiance estimate that reads it back,
//     L_r(x, ωo, λ) ≈ Σ_p f(x, ωo, ωp, λ) · Φ_p(λ) · K(‖x − x_p‖)
// over the k nearest photons within the lookup radius (Jensen 2001, eq. 7.6), r being
// the distance of the (k+1)-th (see radiance()). K is Jensen's cone filter 1 − d/r
// (filter constant 1, normalised by (1 − 2/3) π r², eq. 7.7) or the 2D Epanechnikov
// kernel 2(1 − d²/r²)/(π r²).
//
// Spectral estimate. A photon holds its path's four wavelengths λ_j and Φ_j = power /
// pdf(λ_j), each slot alone an estimate of the spectral power density. A camera path at
// wavelength λ sees slot j through a box of width w in wavelength (the classic spectral
// photon map's bin, centred on the query): Φ_j · [|λ − λ_j| ≤ w/2] / (4 w), the box cut
// to 360–830 nm and renormalised at the ends. It is consistent as w → 0 with enough
// photons, and it lets the BSDF be evaluated at the camera's own wavelengths.
//
// Photons whose surface normal turns away from the query's (n · n_p < 0.5) are skipped,
// so light does not leak across thin walls or around corners (Jensen 2001, §7.2).
// Photon tracing runs in parallel (oneTBB) in fixed chunks of paths whose photons are
// concatenated in path order, each path seeded by its index: the map depends on the seed
// only, not on threads.
#include "light_path.hpp"

#include "effigi/core/progress.hpp"
#include "effigi/interfaces/ieventstore.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/math/bbox.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/render/events.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

namespace effigi {

enum class PhotonKernel { Cone, Epanechnikov };

/// Which photons an estimate uses (max_depth, and the split of global map and caustics).
struct PhotonFilter {
    int minDepth = 1, maxDepth = 1 << 30;
    bool excludeCaustic = false;
    bool accepts(const Photon& p) const {
        return p.depth >= minDepth && p.depth <= maxDepth && !(excludeCaustic && (p.flags & PhotonCaustic));
    }
};

/// Lookup parameters shared by every query of one map.
struct PhotonLookup {
    std::size_t k = 120;
    float maxRadius = 1.f;
    float bandwidth = 20.f;  ///< nm
    PhotonKernel kernel = PhotonKernel::Epanechnikov;
};

class PhotonMap {
public:
    explicit PhotonMap(Ref<IEventStore> store) : m_store(std::move(store)) {}

    /// Index `photons` (scaled by `scale`, 1 / emitted paths) in the store.
    void build(std::vector<Photon> photons, float scale, float radiusHint, std::uint64_t emittedPaths) {
        m_photons = std::move(photons);
        m_emitted = emittedPaths;
        sortSpatially();
        std::vector<Point3f> positions(m_photons.size());
        for (std::size_t i = 0; i < m_photons.size(); ++i) {
            m_photons[i].power *= scale;
            positions[i] = m_photons[i].p;
        }
        m_store->clear();
        m_store->insert(positions);
        m_store->build(radiusHint);
    }

    std::size_t size() const { return m_photons.size(); }
    std::uint64_t emittedPaths() const { return m_emitted; }
    const std::vector<Photon>& photons() const { return m_photons; }
    std::size_t memoryBytes() const { return m_store->memoryBytes() + m_photons.capacity() * sizeof(Photon); }

    /// Radiance reflected at si toward wo (local) at the camera's wavelengths, from the
    /// photons that `filter` accepts. `scratch` holds at least lookup.k entries.
    SampledSpectrum radiance(const SurfaceInteraction& si, const IBSDF& bsdf, const Vector3f& wo,
                             const SampledWavelengths& lambda, const PhotonLookup& lookup, const PhotonFilter& filter,
                             std::vector<EventNeighbour>& scratch) const {
        SampledSpectrum L(0.f);
        if (m_photons.empty() || lookup.k == 0) return L;
        // k + 1 neighbours: the (k+1)-th sets the radius and the k inside it are summed,
        // which for a kernel vanishing at r is the unbiased k / (π r²) of a Poisson
        // process (Jensen's k / (π r_k²) with the k-th photon on the rim is not). Fewer
        // within maxRadius: a fixed-radius estimate over all of them.
        const std::size_t want = lookup.k + 1;
        if (scratch.size() < want) scratch.resize(want);
        std::size_t n = m_store->knn(si.p, want, lookup.maxRadius, scratch.data());
        float r2 = lookup.maxRadius * lookup.maxRadius;
        if (n == want) r2 = scratch[--n].dist2;
        if (n == 0 || !(r2 > 0.f)) return L;
        const float r = std::sqrt(r2), halfW = 0.5f * lookup.bandwidth;
        // The box in wavelength, cut to the sampled range at its ends and renormalised,
        // so that a flat spectrum is not darkened near 360 and 830 nm.
        SampledSpectrum invW;
        for (int c = 0; c < NSpectrumSamples; ++c) {
            float lo = std::max(lambda[c] - halfW, LambdaMin), hi = std::min(lambda[c] + halfW, LambdaMax);
            invW[c] = hi > lo ? 1.f / (float(NSpectrumSamples) * (hi - lo)) : 0.f;
        }
        for (std::size_t i = 0; i < n; ++i) {
            const Photon& ph = m_photons[scratch[i].index];
            if (!filter.accepts(ph) || dot(ph.n, si.n) < 0.5f) continue;
            float kw = lookup.kernel == PhotonKernel::Cone ? 1.f - std::sqrt(scratch[i].dist2) / r
                                                           : 1.f - scratch[i].dist2 / r2;
            if (!(kw > 0.f)) continue;
            SampledSpectrum phi(0.f);
            bool any = false;
            for (int c = 0; c < NSpectrumSamples; ++c)
                for (int j = 0; j < NSpectrumSamples; ++j)
                    if (ph.power[j] != 0.f && std::abs(lambda[c] - ph.lambda[j]) <= halfW) {
                        phi[c] += ph.power[j];
                        any = true;
                    }
            if (!any) continue;
            SampledSpectrum f = bsdf.f(si, wo, si.toLocal(ph.wi), lambda, TransportMode::Radiance);
            L += f * phi * invW * kw;
        }
        // Cone (k = 1): ∫ (1 − d/r) dA = π r² / 3; Epanechnikov: ∫ (1 − d²/r²) dA = π r² / 2.
        const float norm = lookup.kernel == PhotonKernel::Cone ? 3.f : 2.f;
        return L * (norm / (Pi * r2));
    }

private:
    /// Morton order (10 bits an axis): neighbours in space sit near each other in
    /// memory, so a lookup touches few cache lines (it is memory-bound). Deterministic:
    /// ties keep the tracing order.
    void sortSpatially() {
        if (m_photons.size() < 2) return;
        BBox3f box;
        for (const Photon& p : m_photons) box.expand(p.p);
        const Vector3f extent = glm::max(box.max - box.min, Vector3f(1e-20f));
        auto spread = [](std::uint32_t v) {
            std::uint64_t x = v & 0x3ff;
            x = (x | x << 16) & 0x30000ff;
            x = (x | x << 8) & 0x300f00f;
            x = (x | x << 4) & 0x30c30c3;
            return (x | x << 2) & 0x9249249;
        };
        auto cell = [](float t) { return std::uint32_t(std::clamp(t, 0.f, 1.f) * 1023.f); };
        std::vector<std::pair<std::uint64_t, std::uint32_t>> keys(m_photons.size());
        for (std::size_t i = 0; i < m_photons.size(); ++i) {
            Vector3f t = (m_photons[i].p - box.min) / extent;
            keys[i] = {spread(cell(t.x)) | spread(cell(t.y)) << 1 | spread(cell(t.z)) << 2, std::uint32_t(i)};
        }
        std::sort(keys.begin(), keys.end());
        std::vector<Photon> sorted(m_photons.size());
        for (std::size_t i = 0; i < keys.size(); ++i) sorted[i] = m_photons[keys[i].second];
        m_photons = std::move(sorted);
    }

    Ref<IEventStore> m_store;
    std::vector<Photon> m_photons;
    std::uint64_t m_emitted = 0;
};

/// What one photon-tracing pass stores: every non-delta vertex (global map) or only the
/// first non-delta vertex after one or more delta bounces, L S+ D (caustic map).
enum class PhotonPass { Global, Caustic };

struct PhotonTraceResult {
    std::vector<Photon> photons;
    std::uint64_t emittedPaths = 0;
};

/// The camera side of photon mapping (photonmap, sppm): follow `ray`, at camera depth
/// `depth` (segments, `ray` included), through delta bounces (at most 64): miss(d, beta, depth) where it escapes, hit(si,
/// beta, depth) at every surface, surface(si, bsdf, wo, beta, depth) where a non-delta
/// lobe exists and one more segment is allowed; a BSDF sample then continues the
/// path only if it takes a delta lobe (its weight estimates that lobe alone).
template <typename Miss, typename Hit, typename Surface>
void followDeltaBounces(const Scene& scene, Ray ray, SampledSpectrum beta, SampledWavelengths& lambda,
                        ISampler& sampler, int depth, int maxDepth, Miss&& miss, Hit&& hit, Surface&& surface) {
    SurfaceInteraction si;
    for (int bounces = 0; bounces <= 64; ++bounces, ++depth) {
        if (!scene.intersect(ray, si)) return miss(ray.d, beta, depth);
        hit(si, beta, depth);
        if (!si.bsdf || depth >= maxDepth) return;
        const IBSDF& bsdf = *si.bsdf;
        const Vector3f wo = si.toLocal(si.wo);
        if (!bsdf.isPureSpecular()) surface(si, bsdf, wo, beta, depth);
        float uc = sampler.get1D();
        Point2f u = sampler.get2D();
        std::optional<BSDFSample> bs = bsdf.sample(si, wo, uc, u, lambda, TransportMode::Radiance);
        if (!bs || !(bs->pdf > 0.f) || !(bs->isSpecular() || (bs->flags & BSDFNull))) return;
        beta *= bs->f * (std::abs(bs->wi.z) / bs->pdf);
        if (beta.isBlack()) return;
        ray = si.spawnRay(si.toWorld(bs->wi));
    }
}

namespace photon_detail {

/// Light path i of a pass draws from its own PCG32 stream, keyed by (seed, i).
class PathSampler final : public Implements<ISampler> {
public:
    explicit PathSampler(std::uint64_t seed) : m_seed(mixBits(seed + 0x5851f42d4c957f2dull)) {}
    int samplesPerPixel() const override { return 1; }
    void startPixel(const Point2i&) override {}
    void startSample(std::uint64_t index) override { m_rng.seed(mixBits(m_seed ^ mixBits(index + 1)), m_seed); }
    float get1D() override { return m_rng.nextFloat(); }
    Point2f get2D() override {
        float a = m_rng.nextFloat();
        return {a, m_rng.nextFloat()};
    }
    Ref<ISampler> clone(std::uint64_t offset) const override { return std::make_shared<PathSampler>(m_seed + offset); }

private:
    std::uint64_t m_seed;
    PCG32 m_rng;
};

} // namespace photon_detail

/// The photon a light path leaves at vertex v: its power per slot divided by the slot's
/// wavelength pdf (events.hpp), flagged caustic when every bounce before v was delta.
inline Photon photonAt(const LightVertex& v) {
    Photon ph;
    ph.p = v.si.p, ph.wi = v.si.wo, ph.n = v.si.n;
    for (int j = 0; j < NSpectrumSamples; ++j) ph.lambda[j] = v.lambda[j];
    ph.power = safeDiv(v.beta, v.lambda.pdf());
    ph.depth = std::uint16_t(std::min(v.depth, 65535));
    ph.flags = v.depth > 1 && v.specularChain ? PhotonCaustic : 0;
    return ph;
}

/// Trace light paths until at least `target` photons are stored (whole chunks of paths;
/// the power is for one emitted path: divide by emittedPaths), or until `target` paths
/// stored none (no such light paths in the scene; at most 65536 paths are tried), or a
/// cap of 64·target paths. A caustic pass in a scene without delta lobes traces nothing.
inline PhotonTraceResult tracePhotons(const Scene& scene, PhotonPass pass, std::uint64_t target,
                                      const LightPathLimits& limits, std::uint64_t seed, const RenderControl& control) {
    constexpr std::uint64_t Chunk = 4096;
    PhotonTraceResult result;
    if (target == 0 || scene.emitters().empty()) return result;
    if (pass == PhotonPass::Caustic) {  // nothing to trace where no surface has a delta lobe
        bool maybe = false;
        for (const IShape* shape : scene.shapes())
            maybe = maybe || !shape->bsdf() || (shape->bsdf()->flags() & (BSDFSpecular | BSDFNull));
        if (!maybe) return result;
    }
    const std::uint64_t cap = 64 * std::max<std::uint64_t>(target, Chunk);
    ProgressBar progress(pass == PhotonPass::Global ? "Global photons" : "Caustic photons", target, control.progress);
    std::uint64_t chunksPerRound = 16;
    for (bool done = false; !done && !control.stopRequested();) {
        const std::uint64_t firstChunk = result.emittedPaths / Chunk;
        std::vector<std::vector<Photon>> chunks(chunksPerRound);
        tbb::parallel_for(std::uint64_t(0), chunksPerRound, [&](std::uint64_t c) {
            photon_detail::PathSampler sampler(seed + (pass == PhotonPass::Caustic ? 0x9e3779b9ull : 0ull));
            std::vector<Photon>& out = chunks[c];
            for (std::uint64_t i = 0; i < Chunk; ++i) {
                sampler.startSample((firstChunk + c) * Chunk + i);
                SampledWavelengths lambda = SampledWavelengths::sampleVisible(sampler.get1D());
                traceLightPath(scene, sampler, lambda, limits, [&](const LightVertex& v) {
                    if (pass == PhotonPass::Caustic && !v.specularChain) return false;
                    if (v.bsdf.isPureSpecular()) return true;
                    const bool caustic = v.depth > 1 && v.specularChain;
                    if (pass == PhotonPass::Global || caustic) {
                        Photon ph = photonAt(v);
                        if (ph.power.isFinite() && !ph.power.isBlack()) out.push_back(ph);
                    }
                    return pass == PhotonPass::Global;
                });
            }
        });
        // Concatenate in path order; stop at the first chunk boundary that reaches the target.
        const std::uint64_t before = result.photons.size();
        for (std::vector<Photon>& c : chunks) {
            result.photons.insert(result.photons.end(), c.begin(), c.end());
            result.emittedPaths += Chunk;
            const std::uint64_t n = result.photons.size();
            if (n >= target || (n == 0 && result.emittedPaths >= std::min<std::uint64_t>(target, 16 * Chunk)) || result.emittedPaths >= cap) {
                done = true;
                break;
            }
        }
        progress.update(std::min<std::uint64_t>(result.photons.size(), target) - std::min(before, target));
        // Size the next round from the rate so far (deterministic: counts only).
        const double rate = double(result.photons.size()) / double(result.emittedPaths);
        const double need = rate > 0.0 ? double(target - std::min<std::uint64_t>(target, result.photons.size())) / rate
                                       : double(target);
        chunksPerRound = std::clamp<std::uint64_t>(std::uint64_t(need / double(Chunk)) + 1, 1, 256);
    }
    progress.finish();
    return result;
}

} // namespace effigi
