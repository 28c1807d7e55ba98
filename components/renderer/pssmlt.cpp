// renderer "pssmlt" — primary sample space Metropolis light transport (Kelemen et al. 2002).
//
// Markov chains walk the space of the random numbers ("primary samples") an ordinary
// estimator consumes: the state is a PrimarySampleSpaceSampler (pss_sampler.hpp), an
// ISampler on which the inner estimator (mlt_estimator.hpp; `technique` "path": the path
// tracer's PathIntegrator; "bdpt": every bidirectional strategy, bdpt_mlt.hpp, with the
// camera subpath, light subpath and connections on three streams) evaluates film
// contributions, and the chains visit states in
// proportion to the target f, their luminance. Kelemen's mutations: with probability
// large_step_prob a large step (every coordinate afresh), else a small step (each moved by
// a normal of standard deviation sigma, wrapped), accepted with a = min(1, f(y)/f(x)).
//  - bootstrap (pbrt-v3 §16.4.5): f at bootstrap_samples independent points, in two halves
//    (even, odd); a chain starts at a point of one half drawn in proportion to f and is
//    normalised by that half's mean b, so E[b · g(start)] = ∫ f g exactly: no burn-in, and
//    since the kernel keeps f invariant, every later state is unbiased too;
//  - splatting (Kelemen §4): every mutation splats the proposal with weight
//    (a·b + [large step]·κ) / (f(y) + p·κ) and the current state with (1 − a)·b / (f(x) + p·κ),
//    p = large_step_prob, κ the other half's mean: the Metropolis estimate and the large
//    steps' uniform samples combined by the balance heuristic (dim regions get their
//    share from the uniform samples); κ comes from the other half so that it does not
//    depend on the chain's start;
//  - direct light apart (Mitsuba 0.6's directSamples; pssmlt_parts.hpp): paths of one and
//    two segments are path-traced, direct_samples camera samples a pixel, and the chains
//    sample the longer paths only, spared the emitters seen directly, which hold a chain
//    for hundreds of mutations once found;
//  - the film: splats are filtered and each pixel divided by the filter's mass over the
//    film, the image the film makes of camera samples up to its edge (pssmlt_parts.hpp),
//    and the sum divided by the mutations per pixel.
// The image is unbiased at any sample count, only noisier where chains are few or short.
// Mutations per pixel are the sampler's sample_count (Mitsuba 0.6's convention; the
// sampler's values serve the direct light only), or the pass's count under `effigi render
// --spp/--time`: each pass is an independent run, and the film's weighted average of the
// passes is again unbiased. `chains` chains (at most one per mutation) share the mutations
// evenly, each with random streams keyed by the seed, the pass and its index; chains are
// cut into as many fixed groups as threads, each splatting into its own whole-film block,
// summed in order: the same image for a seed and thread count, and over thread counts
// equal up to float rounding. A stop request ends the chains early; the image is divided
// by the mutations taken.
// Parameters: max_depth, rr_depth, hide_emitters (as `path`), bootstrap_samples (pbrt's
// nBootstrap; at most one per mutation, at least 2), chains, large_step_prob, sigma,
// direct_samples (−1: the chains sample direct light too), technique ("path", "bdpt"),
// pathgenerator (nested: the bdpt technique's walks, default `bsdf`).
// References: Kelemen, Szirmay-Kalos, Antal, Csonka 2002, "A Simple and Robust Mutation
// Strategy for the Metropolis Light Transport Algorithm"; Veach & Guibas 1997, "Metropolis
// Light Transport"; pbrt-v3 §16.4; Mitsuba 0.6 src/integrators/pssmlt.
#include "bdpt_mlt.hpp"
#include "pssmlt_parts.hpp"

#include "effigi/core/progress.hpp"
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifilter.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/render/tile_renderer.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <memory>

namespace effigi {
namespace {

using namespace pssmlt;

class PSSMLTRenderer final : public Implements<IRenderer> {
public:
    static Schema schema() {
        Schema s("renderer", "pssmlt",
                 "Primary sample space Metropolis light transport (Kelemen et al. 2002) over the path tracer.");
        s.cite("Kelemen, Szirmay-Kalos, Antal, Csonka 2002, A Simple and Robust Mutation Strategy for the Metropolis "
               "Light Transport Algorithm; pbrt-v3 §16.4");
        s.integer("max_depth", -1, "Longest path in segments (-1: unbounded; 0: black; 1: emitters only)").atLeast(-1);
        s.integer("rr_depth", 5, "Depth from which Russian roulette may end paths").atLeast(1);
        s.boolean("hide_emitters", false, "Do not show emitters seen directly by the camera");
        s.integer("bootstrap_samples", 100000,
                  "Independent points estimating the normalisation and seeding the chains (at most one per mutation)")
            .range(2, 1 << 30);
        s.integer("chains", 1000, "Markov chains sharing the mutations (at most one per mutation)").range(1, 1 << 24);
        s.real("large_step_prob", 0.3, "Probability that a mutation draws every coordinate afresh").range(0.0, 1.0);
        s.real("sigma", 0.01, "Standard deviation of a small step in primary sample space").range(0.0, 1.0);
        s.integer("direct_samples", 16,
                  "Camera samples a pixel of direct light, rendered apart by path tracing, for sample_count mutations "
                  "(-1: the chains sample it too)")
            .atLeast(-1);
        s.string("technique", "path", "Inner estimator evaluated on the primary samples: path or bdpt")
            .oneOf({"path", "bdpt"});
        s.child("pathgenerator", "pathgenerator", "Walks of the bdpt technique's subpaths (default: bsdf)");
        s.ignored("timeout", "use effigi render --time for a time budget");
        // The suite's scenes at max_depth ≤ 2 are all direct light: there the chains run
        // only with direct_samples −1.
        using Params = std::vector<std::pair<std::string, PropertyValue>>;
        const std::pair<std::string, PropertyValue> chainsOnly{"direct_samples", std::int64_t(-1)};
        auto depth = [](std::int64_t d) { return std::pair<std::string, PropertyValue>{"max_depth", d}; };
        for (auto& [name, params] : std::vector<std::pair<std::string, Params>>{
                 {"default", {}},
                 {"direct light by the chains", {chainsOnly}},
                 {"bidirectional", {{"technique", std::string("bdpt")}}},
                 {"bidirectional, chains", {{"technique", std::string("bdpt")}, chainsOnly}},
                 {"independent sampling", {{"large_step_prob", 1.0}}},
                 {"small steps only", {{"large_step_prob", 0.0}, {"chains", std::int64_t(16)}}},
                 {"tiny sigma", {{"sigma", 1e-5}, {"chains", std::int64_t(16)}}},
                 {"max_depth 1", {depth(1)}},
                 {"max_depth 1, chains", {depth(1), chainsOnly}},
                 {"max_depth 2, chains", {depth(2), chainsOnly}},
                 {"max_depth 3", {depth(3)}},
                 {"hide_emitters", {{"hide_emitters", true}}},
                 {"hide_emitters, chains", {{"hide_emitters", true}, chainsOnly}},
                 {"two bootstrap samples", {{"bootstrap_samples", std::int64_t(2)}}},
                 {"four chains", {{"chains", std::int64_t(4)}}}})
            s.addConformance({name, params});
        return s;
    }

    explicit PSSMLTRenderer(const Properties& p)
        : m_maxDepth(int(p.getInt("max_depth"))), m_rrDepth(int(p.getInt("rr_depth"))),
          m_hideEmitters(p.getBool("hide_emitters")), m_bootstrap(std::uint64_t(p.getInt("bootstrap_samples"))),
          m_chains(std::uint64_t(p.getInt("chains"))), m_largeStepProb(p.getFloat("large_step_prob")),
          m_sigma(p.getFloat("sigma")), m_directSamples(p.getInt("direct_samples")),
          m_technique(p.getString("technique")), m_generator(bdpt::pathGenerator(p)) {
        if (m_technique != "bdpt" && p.getComponent("pathgenerator"))
            failAt(p.whereOf("pathgenerator"), "{}: a 'pathgenerator' is used only by technique 'bdpt'", p.describe());
        if (!(m_sigma > 0.f)) failAt(p.whereOf("sigma"), "{}: 'sigma' must be > 0 (got {})", p.describe(), m_sigma);
        if (m_directSamples == 0)
            failAt(p.whereOf("direct_samples"), "{}: 'direct_samples' must be -1 (none apart) or at least 1",
                   p.describe());
    }

    RenderStats render(const Scene& scene, const RenderControl& control) override;

private:
    /// The inner estimator, counting paths of at least minLength segments.
    std::unique_ptr<MLTEstimator> makeEstimator(const Scene& scene, int minLength) const {
        // The schema accepts only the names constructed here.
        if (m_technique == "path")
            return std::make_unique<PathMLTEstimator>(scene, m_maxDepth, m_rrDepth, m_hideEmitters, minLength);
        if (m_technique == "bdpt")
            return std::make_unique<BdptMLTEstimator>(scene, m_maxDepth, m_rrDepth, m_hideEmitters, minLength,
                                                      *m_generator);
        fail("renderer 'pssmlt': unknown technique '{}'", m_technique);
    }

    int m_maxDepth, m_rrDepth;
    bool m_hideEmitters;
    std::uint64_t m_bootstrap, m_chains;
    float m_largeStepProb, m_sigma;
    std::int64_t m_directSamples;
    std::string m_technique;
    Ref<IPathGenerator> m_generator;
};

/// One group of chains: the whole-film block it splats into, its counts.
struct ChainGroup {
    ImageBlock block;
    std::uint64_t mutations = 0, rejected = 0;
};

RenderStats PSSMLTRenderer::render(const Scene& scene, const RenderControl& control) {
    const ICamera& camera = scene.camera();
    IFilm& film = camera.film();
    if (!control.accumulate) film.prepare({"X", "Y", "Z"});
    RenderStats stats;
    const auto start = std::chrono::steady_clock::now();
    const Vector2i size = film.size();
    const std::uint64_t pixels = std::uint64_t(size.x) * std::uint64_t(size.y);
    const std::uint64_t spp = std::uint64_t(camera.sampler().samplesPerPixel());
    const std::uint64_t mpp = control.sampleCount ? control.sampleCount : spp;
    const std::uint64_t total = mpp * pixels;
    if (total == 0) return stats;
    // Direct light apart (paths of ≤ 2 segments), unless asked not to or nothing longer exists.
    const bool apart = m_directSamples > 0 && m_maxDepth != 0;
    const int minLength = apart ? 3 : 1;
    const bool chainsRun = m_maxDepth < 0 || m_maxDepth >= minLength;
    const std::uint64_t directSpp = apart ? std::max<std::uint64_t>(1, (m_directSamples * mpp + spp - 1) / spp) : 0;
    const std::uint64_t nBoot = chainsRun ? std::max<std::uint64_t>(2, std::min(m_bootstrap, total)) : 0;
    const std::uint64_t nChains = chainsRun ? std::min(m_chains, total) : 0;

    std::unique_ptr<tbb::global_control> limit;
    if (control.threads > 0)
        limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism,
                                                      std::size_t(control.threads));
    const std::uint64_t threads = tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism);
    const std::uint64_t passSeed = mixBits(control.seed ^ mixBits(control.sampleOffset + 0x9e3779b97f4a7c15ull));
    const std::unique_ptr<MLTEstimator> estimator = makeEstimator(scene, minLength);
    const int streams = estimator->streamCount();
    ProgressBar progress("Metropolis", directSpp * pixels + nBoot + (chainsRun ? total : 0), control.progress);
    std::vector<Vector3f> direct;
    if (apart)
        direct = renderDirectLight(scene, m_maxDepth, m_rrDepth, m_hideEmitters, directSpp, passSeed, threads, control,
                                   progress, stats.samples, stats.rejectedSamples);

    // Bootstrap: f at nBoot independent points (each regenerated later from its seed).
    struct Local {
        PrimarySampleSpaceSampler sampler;
        std::vector<MLTSplat> splats;
        std::uint64_t rejected = 0;
    };
    tbb::enumerable_thread_specific<Local> locals(
        [&] { return Local{PrimarySampleSpaceSampler(m_sigma, m_largeStepProb, streams), {}, 0}; });
    std::vector<float> f(nBoot);
    tbb::parallel_for(tbb::blocked_range<std::uint64_t>(0, nBoot, 256), [&](const auto& r) {
        Local& l = locals.local();
        for (std::uint64_t i = r.begin(); i != r.end(); ++i) {
            l.sampler.reset(streamSeed(passSeed, 0, i));
            l.splats.clear();
            estimator->evaluate(l.sampler, l.splats);
            f[i] = targetOf(l.splats, l.rejected);
        }
        progress.update(r.size());
    });
    for (const Local& l : locals) stats.rejectedSamples += l.rejected;
    // Two halves, crossed: a chain starts from one half, normalised by its mean b, and its
    // splats' large-step weights use the other half's mean κ, independent of its start, so
    // that E[b · g(start)] = ∫ f g holds for the g they make (Kelemen's weights with b).
    const std::array<BootstrapHalf, 2> halves = splitBootstrap(f);

    // The chains, in fixed groups; chain c takes mutations [c·total/nChains, …).
    FilterTable filter(film.filter());
    NormalisedSplatter splatter(filter, size);
    const std::uint64_t groupCount = std::max<std::uint64_t>(1, std::min(threads, nChains));
    std::vector<ChainGroup> groups(groupCount);
    for (ChainGroup& g : groups) g.block = film.createBlock(Point2i(0), size);
    tbb::parallel_for(std::uint64_t(0), nChains ? groupCount : 0, [&](std::uint64_t gi) {
        ChainGroup& g = groups[gi];
        PrimarySampleSpaceSampler sampler(m_sigma, m_largeStepProb, streams);
        std::vector<MLTSplat> current, proposal;
        std::uint64_t sinceUpdate = 0;
        for (std::uint64_t c = gi * nChains / groupCount; c < (gi + 1) * nChains / groupCount; ++c) {
            const std::uint64_t first = c * total / nChains, last = (c + 1) * total / nChains;
            const BootstrapHalf& own = halves[c % 2];
            const float b = float(own.mean), kappa = float(halves[(c + 1) % 2].mean), pk = m_largeStepProb * kappa;
            if (control.stopRequested()) break;
            if (!(b > 0.f)) {  // no light found: the chain's estimate is 0
                g.mutations += last - first;
                continue;
            }
            PCG32 rng(streamSeed(passSeed, 1, c), c);
            sampler.reset(streamSeed(passSeed, 0, own.draw(rng.nextDouble())));
            current.clear();
            estimator->evaluate(sampler, current);
            float fCurrent = targetOf(current, g.rejected);
            sampler.reseed(streamSeed(passSeed, 2, c));
            for (std::uint64_t m = first; m < last; ++m) {
                sampler.startIteration();
                proposal.clear();
                estimator->evaluate(sampler, proposal);
                const float fProposal = targetOf(proposal, g.rejected);
                const float a = fCurrent > 0.f ? std::min(1.f, fProposal / fCurrent) : 1.f;
                // Kelemen's weights: the Metropolis estimate (density f / b) and the large
                // steps' uniform samples combined by the balance heuristic.
                const float large = sampler.largeStep() ? kappa : 0.f;
                if (fProposal > 0.f && a * b + large > 0.f)
                    splatter.put(g.block, proposal, (a * b + large) / (fProposal + pk));
                if (a < 1.f && fCurrent > 0.f) splatter.put(g.block, current, (1.f - a) * b / (fCurrent + pk));
                if (rng.nextFloat() < a) {
                    sampler.accept();
                    std::swap(current, proposal);
                    fCurrent = fProposal;
                } else {
                    sampler.reject();
                }
                ++g.mutations;
                if (++sinceUpdate == 4096) {
                    progress.update(sinceUpdate);
                    sinceUpdate = 0;
                    if (control.stopRequested()) break;
                }
            }
        }
        progress.update(sinceUpdate);
    });
    progress.finish();

    // Sum the groups' blocks in order, add the direct light; every pixel weighs the
    // mutations per pixel taken, so the film divides the splats by them.
    ImageBlock sum = film.createBlock(Point2i(0), size);
    std::vector<float>& data = sum.data();
    std::uint64_t mutations = 0;
    for (const ChainGroup& g : groups) {
        const std::vector<float>& d = g.block.data();
        for (std::size_t k = 0; k < data.size(); ++k) data[k] += d[k];
        mutations += g.mutations;
        stats.rejectedSamples += g.rejected;
    }
    // A pass cut short weighs by the mutations it took (none: it adds nothing).
    const float weight = float(double(chainsRun ? mutations : total) / double(pixels));
    const Vector2i stored = sum.storageSize();
    for (int y = 0; y < stored.y; ++y)
        for (int x = 0; x < stored.x; ++x) {
            float* p = data.data() + (std::size_t(y) * stored.x + x) * std::size_t(sum.stride());
            const int fx = x - sum.border(), fy = y - sum.border();
            if (fx >= 0 && fy >= 0 && fx < size.x && fy < size.y) {
                splatter.normalise(p, fx, fy);
                if (!direct.empty())
                    for (int k = 0; k < 3; ++k) p[k] += weight * direct[std::size_t(fy) * size.x + fx][k];
            }
            p[3] = weight;
        }
    film.put(sum);
    stats.samples += nBoot + mutations;
    stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats.interrupted = control.stopRequested();
    return stats;
}

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::PSSMLTRenderer)
