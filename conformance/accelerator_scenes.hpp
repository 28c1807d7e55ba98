#pragma once
// The scenes of the accelerator suite (accelerator_suite.cpp) and the double-precision
// arbiter that decides, for a ray on which two accelerators disagree, which answers the
// geometry allows. Scenes are generated from the run's seed and their own name only, so
// every accelerator is asked the same questions and reference answers can be shared.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ishape.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace effigi::conform {

struct AccelScene {
    std::string name;
    std::string description;
    std::vector<Ref<IShape>> owned;
    std::vector<const IShape*> shapes;
    std::vector<Ray> rays;
    /// bruteforce answers rays [0, referenceRays); the large mesh has too many triangles
    /// for all of them, so it is checked there on a random subset and against the other
    /// accelerators (embree, bvh, kdtree) pairwise on every ray.
    std::size_t referenceRays = 0;
    bool large = false;
    std::size_t triangles = 0;
    double extent = 0.0;  ///< diagonal of the scene's bounding box
};

/// Scene names in report order.
const std::vector<std::string>& accelSceneNames();
/// Builds one scene; `registry` creates the analytic shapes, the Cornell box's shapes and
/// the bruteforce used to place rays whose tMax equals a hit distance.
AccelScene makeAccelScene(const std::string& name, Registry& registry, std::uint64_t seed, bool quick);

/// What an accelerator answered for one ray.
struct AccelAnswer {
    Hit hit;               ///< closest hit (shape = Hit::None on a miss)
    bool returned = false; ///< intersect()'s return value
    bool occluded = false; ///< occluded()'s answer
};

/// Decides in double precision which answers a ray admits (docs/conformance.md, the
/// accelerator suite). Only a few float ulps of the geometry are ever in doubt: the float
/// triangle tests work on vertices relative to the ray origin, so their decisions are
/// good to δ = 16 u L (u = 2⁻²⁴, L = the largest distance from the origin to the
/// triangle's corners). An answer is *possible* when the ray passes within δ of the
/// reported triangle (seen along the ray) and its t lies within the slack
/// (δ + e) / (|d| |cos θ|) of the plane's distance, e being how far a test that computes
/// the normal may tilt the plane of a sliver. A primitive is *certainly* hit when the ray
/// pierces it with a margin of δ on every edge (edges shared with a neighbour that
/// continues the surface on the other side need no margin: watertight tests must hit
/// one of the two), away from its corners, with t ± slack inside (0, tMax).
class AccelArbiter {
public:
    explicit AccelArbiter(const AccelScene& scene) : m_scene(scene) {}
    /// Closest-hit answer acceptable: a miss when nothing is certainly hit; a hit on a
    /// primitive it possibly hits, with uv consistent with that point, no farther than
    /// any certain hit (plus its slack).
    bool acceptClosest(const Ray& ray, const AccelAnswer& a) const;
    /// Any-hit answer acceptable: false when nothing is certainly hit before tMax; true
    /// when the accelerator's own closest hit for the ray is a possible hit.
    bool acceptAny(const Ray& ray, const AccelAnswer& a) const;
    /// Whether (shape, prim) is possibly hit at t with barycentrics / uv uv.
    bool possible(const Ray& ray, const Hit& h) const;
    /// The farthest the closest hit can be: min over certain hits of t + slack (∞: none).
    double certainBound(const Ray& ray) const;

private:
    const AccelScene& m_scene;
};

} // namespace effigi::conform
