#pragma once
// The pathgenerator suite's test scene and what its two files share: a closed box of
// diffuse walls lit by a square area light and a point light, holding spheres of a rough
// conductor, a rough dielectric, a smooth dielectric and a smooth plastic (delta and
// non-delta lobes on one surface), seen by a perspective camera. Walks in it meet every
// kind of vertex, and none leaves the box, so max_depth is reached.
#include "conformance/bsdf_common.hpp"
#include "effigi/interfaces/ipathgenerator.hpp"
#include "effigi/render/path_context.hpp"

#include <memory>

namespace effigi::conform::pathgen {

using bsdf::modeName;
using bsdf::relativeError;
using bsdf::spec;
using bsdf::vec;

/// The box scene (loaded once per target).
std::unique_ptr<Scene> loadBoxScene();

/// A context over the scene with the generator, max_depth and no Russian roulette
/// unless rrDepth says so.
PathContext makeContext(const Scene& scene, const IPathGenerator& g, int maxDepth, int rrDepth = 1 << 20);

/// sampleDirection against pdfDirection by chi-square, at a point of each material.
void checkDirectionDistribution(Target& t, const IPathGenerator& g, const Scene& scene);

} // namespace effigi::conform::pathgen
