#pragma once
// IPathGenerator — the random walks of path space (EFFIGI's path generator): it extends a
// camera subpath (radiance transport) and a light subpath (importance transport) vertex by
// vertex, and records at each vertex what bidirectional methods need for multiple
// importance sampling (Veach 1997, §10.2): the throughput `beta` up to it and, per unit
// area, the density pdfFwd with which its own walk produced it and the density pdfRev
// with which the opposite walk would have (render/path_vertex.hpp).
//
// A generator decides one thing: how a walk continues at a surface — sampleDirection()
// and its density pdfDirection(). The same density is what the renderers evaluate when
// they ask how likely a vertex was from the *other* side (PathContext::pdf), so a
// generator that samples differently from the BSDF stays unbiased and correctly weighted
// in every strategy. The walks themselves (cameraSubpath, lightSubpath) have default
// implementations in src/render/path_generator.cpp — BSDF values, shading-normal
// correction (Veach §5.3), Russian roulette from rr_depth — which a generator may replace.
//
// Directions are local to si's shading frame (as IBSDF's); wo points to the previous
// vertex. Per vertex the walk draws exactly one 1D and one 2D value for the direction
// (sampleDirection's uc, u) and one 1D value for Russian roulette past rr_depth: a fixed
// layout, which is what primary-sample-space Metropolis mutates.
// effigi-conform's `pathgenerator` suite checks the promises below on walks in a test
// scene: recorded densities equal recomputed ones, beta = ∏ f·|cos|/pdf, max_depth held,
// and sampleDirection distributed as pdfDirection (chi-square).
#include "effigi/core/component.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/render/path_vertex.hpp"

#include <optional>
#include <vector>

namespace effigi {

class ISampler;
struct PathContext;
struct PathEscape;
struct Ray;

class IPathGenerator : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IPathGenerator");
    static constexpr const char* Tag = "pathgenerator";

    /// The direction a walk continues in from the surface point si, arriving along wo:
    /// f is the BSDF's value for (wo, wi) in `mode` (without the shading correction), pdf
    /// this generator's solid-angle density of wi (for a delta lobe: its discrete
    /// probability, flags say so). Empty when the walk ends here (absorbed).
    virtual std::optional<BSDFSample> sampleDirection(const SurfaceInteraction& si, const Vector3f& wo, float uc,
                                                      const Point2f& u, SampledWavelengths& lambda,
                                                      TransportMode mode) const = 0;
    /// The solid-angle density with which sampleDirection(si, wo) gives wi (non-delta part).
    virtual float pdfDirection(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                               const SampledWavelengths& lambda, TransportMode mode) const = 0;

    /// The camera subpath of the camera ray `ray` with importance weight `weight`: its
    /// vertex on the lens and up to ctx.maxDepth surface vertices; how it left the scene
    /// goes to `escape` (the environment's strategies need it).
    virtual void cameraSubpath(const PathContext& ctx, const Ray& ray, const SampledSpectrum& weight,
                               ISampler& sampler, SampledWavelengths& lambda, std::vector<PathVertex>& path,
                               PathEscape& escape) const;
    /// A light subpath at `time` (the camera subpath's: both see the scene in one pose):
    /// a point on a finite emitter (chosen uniformly among ctx.lights) and up to
    /// ctx.maxDepth − 1 surface vertices. Draws one 1D and two 2D values first even when
    /// there is no light, so the layout of the sample does not depend on it.
    virtual void lightSubpath(const PathContext& ctx, float time, ISampler& sampler, SampledWavelengths& lambda,
                              std::vector<PathVertex>& path) const;

protected:
    /// Extend `path` (holding its start vertex) by sampleDirection until it holds
    /// maxVertices vertices, leaves the scene (recorded in *escape) or ends.
    void randomWalk(const PathContext& ctx, Ray ray, SampledSpectrum beta, float pdfDir, std::size_t maxVertices,
                    TransportMode mode, ISampler& sampler, SampledWavelengths& lambda, std::vector<PathVertex>& path,
                    PathEscape* escape) const;
};

} // namespace effigi
