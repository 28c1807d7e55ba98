// Pathgenerator suite: an IPathGenerator, in each of its configurations, against the
// promises of include/effigi/interfaces/ipathgenerator.hpp, on camera and light subpaths
// walked in a closed box (pathgenerator_common.hpp):
//  - max_depth: camera subpaths hold at most max_depth + 1 vertices and light subpaths at
//    most max_depth, for max_depth 1, 2 and 5; and the longest ones are reached (the box
//    is closed and Russian roulette is off), so the check is not vacuous;
//  - recorded densities: every pdfFwd equals the density PathContext::pdf recomputes from
//    the vertices (camera, emitter origin and direction, the generator's pdfDirection at
//    surfaces) gives for the traced step, and every pdfRev the density of the reversed
//    step — the numbers every MIS weight of bdpt is made of; 1e-3 relative, directions
//    taken as traced (the next vertex's wo), so ray offsets at short segments do not count;
//  - throughput: beta at each vertex equals beta at the one before times f·|cos θ|/pdf
//    (with the shading-normal correction in importance transport), recomputed from the
//    BSDF and the generator's density; across delta vertices, which have no density to
//    recompute, the step is only required to be finite and non-negative;
//  - everything finite, including with Russian roulette from the first bounce;
//  - chi-square of sampleDirection against pdfDirection: pathgenerator_distribution.cpp.
#include "conformance/pathgenerator_common.hpp"
#include "conformance/media_common.hpp"
#include "conformance/rng_sampler.hpp"
#include "effigi/interfaces/icamera.hpp"
#include "effigi/render/tile_renderer.hpp"

#include <cmath>

namespace effigi::conform::pathgen {

namespace {

using media::nonNegative;

/// Record an error against its tolerance (NaN counts as failing).
void noteError(Tally& t, double err, double tolerance, const std::string& what) {
    if (std::isnan(err)) err = 1e9;
    t.worst = std::max(t.worst, err);
    t.note(err <= tolerance, what);
}

/// What scattered at v, for messages.
std::string where(const PathVertex& v) {
    if (v.type != PathVertexType::Surface) return v.type == PathVertexType::Camera ? "the camera" : "the light";
    return fmt::format("{} at {}", v.si.bsdf ? v.si.bsdf->typeName() : std::string("no bsdf"), vec(Vector3f(v.p())));
}

struct Walks {
    std::vector<std::vector<PathVertex>> camera, light;
};

/// n camera subpaths (through random pixels) and n light subpaths.
Walks walk(const PathContext& ctx, std::uint64_t n, std::uint64_t seed, std::vector<SampledWavelengths>* lambdas) {
    RngSampler sampler(seed);
    Walks w;
    const Vector2i res = ctx.scene.camera().film().size();
    for (std::uint64_t i = 0; i < n; ++i) {
        sampler.startSample(i);
        Point2i pixel(int(sampler.get1D() * float(res.x)) % res.x, int(sampler.get1D() * float(res.y)) % res.y);
        FilmSample fs = sampleCamera(ctx.scene.camera(), sampler, pixel);
        PathEscape escape;
        w.camera.emplace_back();
        ctx.generator.cameraSubpath(ctx, fs.ray, fs.weight, sampler, fs.lambda, w.camera.back(), escape);
        w.light.emplace_back();
        ctx.generator.lightSubpath(ctx, fs.ray.time, sampler, fs.lambda, w.light.back());
        if (lambdas) lambdas->push_back(fs.lambda);
    }
    return w;
}

void checkDepth(Target& t, const Scene& scene, const IPathGenerator& g) {
    Tally held;
    std::string reached;
    bool allReached = true;
    for (int depth : {1, 2, 5}) {
        const PathContext ctx = makeContext(scene, g, depth);
        const Walks w = walk(ctx, t.count(2000, 400), t.derivedSeed(fmt::format("depth {}", depth)), nullptr);
        std::size_t longestCam = 0, longestLight = 0;
        for (const auto& p : w.camera) {
            held.note(p.size() <= std::size_t(depth) + 1,
                      fmt::format("max_depth {}: camera subpath of {} vertices", depth, p.size()));
            longestCam = std::max(longestCam, p.size());
        }
        for (const auto& p : w.light) {
            held.note(p.size() <= std::size_t(depth), fmt::format("max_depth {}: light subpath of {} vertices", depth, p.size()));
            longestLight = std::max(longestLight, p.size());
        }
        allReached &= longestCam == std::size_t(depth) + 1 && longestLight == std::size_t(depth);
        reached += fmt::format("{}max_depth {}: longest {} + {}", reached.empty() ? "" : ", ", depth, longestCam,
                               longestLight);
    }
    t.expect("max_depth", held.bad == 0 && allReached, reached,
             held.detail("camera ≤ max_depth + 1 and light ≤ max_depth vertices, the longest reached (" + reached + ")"));
}

/// The direction a walk left p[i] in, exactly as traced: back along the next vertex's wo.
Vector3f leaving(const std::vector<PathVertex>& p, std::size_t i) { return -p[i + 1].si.wo; }

/// The solid-angle density of the step from p[i] to p[i + 1], recomputed from the
/// traced directions (positions would add the ray offsets' error at short segments).
float stepDensity(const PathContext& ctx, const std::vector<PathVertex>& p, std::size_t i, TransportMode mode,
                  const SampledWavelengths& lambda) {
    const PathVertex& v = p[i];
    const Vector3f wi = leaving(p, i);
    if (v.type == PathVertexType::Camera) return ctx.camera.pdfDirection(v.p(), wi);
    if (v.type == PathVertexType::Light) {
        float pdfPos = 0.f, pdfDir = 0.f;
        return v.light->pdfEmission(v.p(), v.si.n, wi, pdfPos, pdfDir) ? pdfDir : 0.f;
    }
    return ctx.generator.pdfDirection(v.si, v.si.toLocal(v.si.wo), v.si.toLocal(wi), lambda, mode);
}

void checkDensities(Target& t, const Scene& scene, const IPathGenerator& g) {
    const PathContext ctx = makeContext(scene, g, 6);
    std::vector<SampledWavelengths> lambdas;
    const Walks w = walk(ctx, t.count(3000, 600), t.derivedSeed("densities"), &lambdas);
    Tally fwd, rev;
    for (std::size_t k = 0; k < w.camera.size(); ++k)
        for (const auto* path : {&w.camera[k], &w.light[k]}) {
            const std::vector<PathVertex>& p = *path;
            const bool camera = path == &w.camera[k];
            const TransportMode mode = camera ? TransportMode::Radiance : TransportMode::Importance;
            const char* side = camera ? "camera" : "light";
            if (!p.empty() && p[0].type == PathVertexType::Light) {
                const float origin = ctx.pdfLightOrigin(p[0]);
                noteError(fwd, relativeError(p[0].pdfFwd, origin), 1e-3,
                          fmt::format("light origin: pdfFwd {} vs {}", p[0].pdfFwd, origin));
            }
            for (std::size_t i = 1; i < p.size(); ++i) {
                if (p[i - 1].delta) continue;  // a delta step records no density
                const float f = p[i - 1].toArea(stepDensity(ctx, p, i - 1, mode, lambdas[k]), p[i]);
                noteError(fwd, relativeError(p[i].pdfFwd, f), 1e-3,
                          fmt::format("{} vertex {} (from {}): pdfFwd {} vs recomputed {}", side, i, where(p[i - 1]),
                                      p[i].pdfFwd, f));
                if (i + 1 >= p.size() || p[i].delta) continue;
                // The reversed step at p[i]: arriving along the direction to p[i + 1], leaving toward p[i - 1].
                const SurfaceInteraction& si = p[i].si;
                const float dir =
                    ctx.generator.pdfDirection(si, si.toLocal(leaving(p, i)), si.toLocal(si.wo), lambdas[k], mode);
                const float r = p[i].toArea(dir, p[i - 1]);
                noteError(rev, relativeError(p[i - 1].pdfRev, r), 1e-3,
                          fmt::format("{} vertex {} (from {}): pdfRev {} vs recomputed {}", side, i - 1, where(p[i]),
                                      p[i - 1].pdfRev, r));
            }
        }
    t.expect("forward densities", fwd.bad == 0, fmt::format("max rel. error {:.2g}", fwd.worst),
             fwd.detail("pdfFwd = the density of the traced step, recomputed (1e-3)"));
    t.expect("reverse densities", rev.bad == 0, fmt::format("max rel. error {:.2g}", rev.worst),
             rev.detail("pdfRev = the reversed step's density, recomputed (1e-3)"));
}

/// beta[i + 1] / beta[i] recomputed at the surface vertex p[i] (non-delta).
SampledSpectrum step(const PathContext& ctx, const std::vector<PathVertex>& p, std::size_t i, TransportMode mode,
                     const SampledWavelengths& lambda) {
    const SurfaceInteraction& si = p[i].si;
    const Vector3f wi = leaving(p, i);
    const float pdf = stepDensity(ctx, p, i, mode, lambda);
    SampledSpectrum f = si.bsdf->f(si, si.toLocal(si.wo), si.toLocal(wi), lambda, mode);
    if (mode == TransportMode::Importance) f *= shadingCorrection(si, si.wo, wi);
    return pdf > 0.f ? f * (std::abs(dot(wi, Vector3f(si.shading.n))) / pdf) : SampledSpectrum(0.f);
}

void checkThroughput(Target& t, const Scene& scene, const IPathGenerator& g) {
    const PathContext ctx = makeContext(scene, g, 6);
    std::vector<SampledWavelengths> lambdas;
    const Walks w = walk(ctx, t.count(3000, 600), t.derivedSeed("throughput"), &lambdas);
    Tally tally, finite;
    std::size_t deltaSteps = 0;
    for (std::size_t k = 0; k < w.camera.size(); ++k)
        for (const auto* path : {&w.camera[k], &w.light[k]}) {
            const std::vector<PathVertex>& p = *path;
            const bool camera = path == &w.camera[k];
            const TransportMode mode = camera ? TransportMode::Radiance : TransportMode::Importance;
            for (std::size_t i = 0; i + 1 < p.size(); ++i) {
                finite.note(p[i + 1].beta.isFinite() && nonNegative(p[i + 1].beta),
                            fmt::format("vertex {}: beta {}", i + 1, spec(p[i + 1].beta)));
                SampledSpectrum expected;
                if (p[i].type == PathVertexType::Camera) expected = p[i].beta;
                else if (p[i].type == PathVertexType::Light) {
                    const float pdfDir = stepDensity(ctx, p, i, mode, lambdas[k]);
                    const float cosTheta = p[i].onSurface ? std::abs(dot(p[i].si.n, leaving(p, i))) : 1.f;
                    expected = pdfDir > 0.f ? p[i].beta * (cosTheta / pdfDir) : SampledSpectrum(0.f);
                } else if (p[i].delta) {
                    ++deltaSteps;
                    continue;
                } else expected = p[i].beta * step(ctx, p, i, mode, lambdas[k]);
                double worst = 0.0;
                for (int c = 0; c < NSpectrumSamples; ++c)
                    worst = std::max(worst, relativeError(p[i + 1].beta[c], expected[c], 1e-6 * expected.maxValue()));
                noteError(tally, worst, 1e-3,
                          fmt::format("{} vertex {} (after {}): beta {} but the product gives {}",
                                      camera ? "camera" : "light", i + 1, where(p[i]), spec(p[i + 1].beta),
                                      spec(expected)));
            }
        }
    t.expect("throughput", tally.bad == 0, fmt::format("max rel. error {:.2g}", tally.worst),
             tally.detail(fmt::format("beta = ∏ f·|cos θ|/pdf (1e-3); {} delta steps not recomputed", deltaSteps)));
    // Russian roulette from the first bounce: only finiteness can be asked of it here.
    const PathContext rr = makeContext(scene, g, 8, 1);
    const Walks wr = walk(rr, t.count(2000, 400), t.derivedSeed("throughput rr"), nullptr);
    for (const auto& paths : {&wr.camera, &wr.light})
        for (const auto& p : *paths)
            for (const PathVertex& v : p)
                finite.note(v.beta.isFinite() && nonNegative(v.beta) && std::isfinite(v.pdfFwd) && std::isfinite(v.pdfRev),
                            fmt::format("rr_depth 1: beta {}, pdfFwd {}, pdfRev {}", spec(v.beta), v.pdfFwd, v.pdfRev));
    t.expect("finite", finite.bad == 0, finite.figure(),
             finite.detail("beta finite and ≥ 0, densities finite (also with Russian roulette from rr_depth 1)"));
}

void runPathGeneratorSuite(Target& t) {
    Ref<IPathGenerator> g = t.as<IPathGenerator>();
    if (!g) {
        t.expect("interface", false, "-", "component does not implement IPathGenerator");
        return;
    }
    std::unique_ptr<Scene> scene = loadBoxScene();
    checkDepth(t, *scene, *g);
    checkDensities(t, *scene, *g);
    checkThroughput(t, *scene, *g);
    checkDirectionDistribution(t, *g, *scene);
}

} // namespace

} // namespace effigi::conform::pathgen

EFFIGI_CONFORMANCE_SUITE("pathgenerator",
                         "max_depth; recorded densities and throughput recomputed from the vertices; chi-square of "
                         "the direction sampling",
                         effigi::conform::pathgen::runPathGeneratorSuite);
