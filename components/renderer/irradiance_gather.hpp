#pragma once
// How renderer `irradiancecache` makes a record: the stratified hemisphere gather
// (HemisphereGather, checked on its own by tests/test_irradiancecache.cpp), the sampler its
// gather paths draw from, and makeRecord (gather, E, gradients, radii).
//
// Gather (Ward & Heckbert 1992): M × N cells, M strata uniform in sin²θ (cosine-weighted
// strata) and N = 3M in φ, one jittered direction each. With L_jk the radiance of cell
// (j, k) and r_jk the distance its ray travelled:
//   E    = π/(MN) Σ L_jk
//   ∇_r E = π/(MN) Σ L_jk tanθ_jk v(φ_jk)          (v(φ) = direction φ + π/2 in the plane)
//   ∇_t E = Σ_k u_k (2π/N) Σ_{j≥1} sinθ_j− cos²θ_j− (L_jk − L_j−1,k) / min(r_jk, r_j−1,k)
//         + Σ_k v_k− Σ_j cosθ_j (cosθ_j− − cosθ_j+) (L_jk − L_j,k−1) / (sinθ_j min(r_jk, r_j,k−1))
// (θ_j±: the stratum's edges, u_k: the cell's centre direction, v_k−: normal to the cell's
// first edge; Křivánek & Gautron 2009, eqs. 2.16–2.17), and the validity radius is the
// harmonic mean distance R = MN / Σ 1/r_jk (Ward, Rubinstein & Clear 1988), limited by
// E/|∇_t E| (Křivánek et al. 2006) and clamped to [minR, maxR].
#include "irradiance_cache.hpp"
#include "path_core.hpp"

#include "effigi/interfaces/isampler.hpp"
#include "effigi/math/frame.hpp"
#include "effigi/math/rng.hpp"

namespace effigi::irrcache {

/// E and its gradients from the cells of one stratified gather.
class HemisphereGather {
public:
    HemisphereGather(int m, int n) : m_M(m), m_N(n), m_cells(std::size_t(m) * n) {}

    int thetaStrata() const { return m_M; }
    int phiStrata() const { return m_N; }
    int count() const { return int(m_cells.size()); }

    /// Jittered directions (world) around `frame.n`, one per cell, cell = j N + k.
    void generate(const Frame& frame, PCG32& rng) {
        m_frame = frame;
        for (int j = 0; j < m_M; ++j)
            for (int k = 0; k < m_N; ++k) {
                Cell& c = m_cells[std::size_t(j) * m_N + k];
                float sin2 = (float(j) + rng.nextFloat()) / float(m_M);
                c.sinTheta = std::sqrt(sin2);
                c.cosTheta = std::sqrt(std::max(0.f, 1.f - sin2));
                c.phi = 2.f * Pi * (float(k) + rng.nextFloat()) / float(m_N);
                c.d = frame.toWorld({c.sinTheta * std::cos(c.phi), c.sinTheta * std::sin(c.phi), c.cosTheta});
                c.L.fill(0.f);
                c.dist = Infinity;
            }
    }
    const Vector3f& direction(int cell) const { return m_cells[cell].d; }
    /// What the caller traced along the cell's direction: radiance per node, distance.
    void set(int cell, const NodeValues& L, float dist) { m_cells[cell].L = L, m_cells[cell].dist = dist; }

    struct Result {
        NodeValues E{};
        NodeVectors rotGrad{}, transGrad{};
        float harmonicR = Infinity, minDist = Infinity;
    };

    Result process() const {
        Result r;
        const float M = float(m_M), N = float(m_N), cell = Pi / (M * N);
        double invDist = 0.0;
        for (int j = 0; j < m_M; ++j) {
            // Stratum edges θ_j− and θ_j+ and its centre θ_j (sin²θ uniform).
            const float sin2Minus = float(j) / M, sin2Plus = float(j + 1) / M, sin2Mid = (float(j) + 0.5f) / M;
            const float sinMinus = std::sqrt(sin2Minus), cosMinus = std::sqrt(1.f - sin2Minus);
            const float cosPlus = std::sqrt(std::max(0.f, 1.f - sin2Plus));
            const float sinMid = std::sqrt(sin2Mid), cosMid = std::sqrt(1.f - sin2Mid);
            for (int k = 0; k < m_N; ++k) {
                const Cell& c = at(j, k);
                const float tanTheta = c.sinTheta / std::max(c.cosTheta, 1e-4f);
                const Vector3f v = m_frame.toWorld({-std::sin(c.phi), std::cos(c.phi), 0.f});
                for (int i = 0; i < Nodes; ++i) {
                    r.E[i] += c.L[i];
                    r.rotGrad[i] += v * (c.L[i] * tanTheta * cell);
                }
                if (j >= 1) {  // across the edge θ_j− to the cell below, along u_k
                    const Cell& o = at(j - 1, k);
                    const float phiMid = 2.f * Pi * (float(k) + 0.5f) / N;
                    const Vector3f u = m_frame.toWorld({std::cos(phiMid), std::sin(phiMid), 0.f});
                    const float w = 2.f * Pi * sinMinus * cosMinus * cosMinus / (N * minDist(c, o));
                    for (int i = 0; i < Nodes; ++i) r.transGrad[i] += u * ((c.L[i] - o.L[i]) * w);
                }
                {  // across the edge φ_k− to the previous cell, along v_k−
                    const Cell& o = at(j, k == 0 ? m_N - 1 : k - 1);
                    const float phiMinus = 2.f * Pi * float(k) / N;
                    const Vector3f vm = m_frame.toWorld({-std::sin(phiMinus), std::cos(phiMinus), 0.f});
                    const float w = cosMid * (cosMinus - cosPlus) / (sinMid * minDist(c, o));
                    for (int i = 0; i < Nodes; ++i) r.transGrad[i] += vm * ((c.L[i] - o.L[i]) * w);
                }
                if (std::isfinite(c.dist) && c.dist > 0.f) invDist += 1.0 / c.dist;
                r.minDist = std::min(r.minDist, c.dist);
            }
        }
        for (float& e : r.E) e *= cell;
        r.harmonicR = invDist > 0.0 ? float(double(M * N) / invDist) : Infinity;
        return r;
    }

private:
    struct Cell {
        Vector3f d{0.f};
        float sinTheta = 0.f, cosTheta = 1.f, phi = 0.f, dist = Infinity;
        NodeValues L{};
    };
    const Cell& at(int j, int k) const { return m_cells[std::size_t(j) * m_N + k]; }
    /// The nearer of two cells' distances, kept off 0 (a ray that hit at its origin).
    static float minDist(const Cell& a, const Cell& b) { return std::max(std::min(a.dist, b.dist), 1e-6f); }

    int m_M, m_N;
    Frame m_frame;
    std::vector<Cell> m_cells;
};

/// A PCG32 stream per (key, sample index): each gather ray's path draws the same numbers
/// at each of its wavelength passes, so the passes follow the same directions.
class GatherSampler final : public Implements<ISampler> {
public:
    int samplesPerPixel() const override { return 1 << 30; }
    void startPixel(const Point2i& p) override {
        m_key = mixBits((std::uint64_t(std::uint32_t(p.x)) << 32) | std::uint32_t(p.y));
    }
    void setKey(std::uint64_t key) { m_key = key; }
    void startSample(std::uint64_t index) override { m_rng.seed(mixBits(m_key ^ mixBits(index + 1)), m_key); }
    float get1D() override { return m_rng.nextFloat(); }
    Point2f get2D() override {
        float x = m_rng.nextFloat();
        return {x, m_rng.nextFloat()};
    }
    Ref<ISampler> clone(std::uint64_t) const override { return std::make_shared<GatherSampler>(); }

private:
    std::uint64_t m_key = 0;
    PCG32 m_rng;
};


/// What makeRecord needs of the renderer's settings.
struct RecordSettings {
    int maxDepth = -1, rrDepth = 5;  ///< the camera path's (as renderer path)
    bool gradients = true, clampScreen = true;
    float aOverture = 0.2f;          ///< Ward's error a at which records are placed
    float diagonal = 1.f;            ///< of the scene's bounding box
};

/// A record at the surface point si, gathered on the side n; `footprint` is the pixel's
/// size there (infinite: unknown). The gather ray is the camera path's segment 2, so
/// segment k of a gather path is segment k + 1 of the camera path, and the emission at its
/// first hit (direct light, which the render pass samples) is left out: hideEmitters.
inline IrradianceRecord makeRecord(const Scene& scene, const SurfaceInteraction& si, const Vector3f& n,
                                   float footprint, std::uint64_t key, const RecordSettings& rs,
                                   HemisphereGather& hg, GatherSampler& sampler) {
    PCG32 rng(mixBits(key), key);
    hg.generate(Frame(n), rng);
    const PathIntegrator gi(scene, rs.maxDepth < 0 ? -1 : rs.maxDepth - 1, std::max(1, rs.rrDepth - 1), true);
    sampler.setKey(key);
    for (int cell = 0; cell < hg.count(); ++cell) {
        const Ray ray = si.spawnRay(hg.direction(cell));
        SurfaceInteraction hit;
        NodeValues L{};
        float dist = Infinity;
        if (scene.intersect(ray, hit)) {
            dist = length(hit.p - si.p);
            for (int g = 0; g < 4; ++g) {  // nodes g, g + 4, g + 8, g + 12, same random numbers
                std::array<float, 4> nodes{nodeLambda(g), nodeLambda(g + 4), nodeLambda(g + 8), nodeLambda(g + 12)};
                SampledWavelengths lambda = SampledWavelengths::fromNodes(nodes, {1.f, 1.f, 1.f, 1.f});
                sampler.startSample(std::uint64_t(cell));
                SampledSpectrum v = gi.liFromHit(PathState(ray), hit, lambda, sampler);
                // Dispersion kept only the first node: trace the others alone.
                for (int i = 1; i < 4 && lambda.secondaryTerminated(); ++i) {
                    SampledWavelengths one = SampledWavelengths::constant(nodes[i]);
                    sampler.startSample(std::uint64_t(cell));
                    v[i] = gi.liFromHit(PathState(ray), hit, one, sampler)[0];
                }
                for (int i = 0; i < 4; ++i) L[g + 4 * i] = std::isfinite(v[i]) ? std::max(v[i], 0.f) : 0.f;
            }
        }
        hg.set(cell, L, dist);
    }
    HemisphereGather::Result res = hg.process();
    for (int i = 0; i < Nodes; ++i)  // a non-finite value would reach every pixel the record serves
        if (!std::isfinite(res.E[i]) || !isFinite(res.rotGrad[i]) || !isFinite(res.transGrad[i]))
            res.E[i] = 0.f, res.rotGrad[i] = res.transGrad[i] = Vector3f(0.f);
    IrradianceRecord r;
    r.p = si.p, r.n = n, r.E = res.E, r.rotGrad = res.rotGrad, r.transGrad = res.transGrad;
    float Ebar = 0.f;
    Vector3f gbar(0.f);
    for (int i = 0; i < Nodes; ++i) Ebar += r.E[i] / Nodes, gbar += r.transGrad[i] / float(Nodes);
    float raw = std::min(res.harmonicR, rs.diagonal);
    if (rs.gradients && length(gbar) > 0.f) raw = std::min(raw, Ebar / length(gbar));  // Křivánek 2006
    // Validity a·R between 1.5 and 10 pixels (Tabellion & Lamorlette 2004), else scene-relative.
    if (rs.clampScreen && std::isfinite(footprint) && footprint > 0.f)
        r.minR = 1.5f * footprint / rs.aOverture, r.maxR = 10.f * footprint / rs.aOverture;
    else
        r.minR = 1e-4f * rs.diagonal, r.maxR = rs.diagonal;
    r.maxR = std::max(r.maxR, r.minR);
    r.rawR = std::max(raw, 0.f);
    // A radius raised to minR would carry the gradient beyond where it was measured.
    const float scale = !rs.gradients ? 0.f : r.minR > 0.f ? std::min(1.f, r.rawR / r.minR) : 1.f;
    for (int i = 0; i < Nodes; ++i) {
        r.transGrad[i] *= scale;
        if (!rs.gradients) r.rotGrad[i] = Vector3f(0.f);
    }
    return r;
}

} // namespace effigi::irrcache
