// warp "uniform_hemisphere" — uniform directions on the hemisphere z >= 0.
//
// Archimedes' hat-box theorem: z uniform in [0, 1] and φ uniform in [0, 2π) give equal
// areas, so the density is 1/(2π) per unit solid angle. Invertible.
//
// Parameters: none.
//
// Reference: J. Arvo, "Stratified Sampling of 2-Manifolds", SIGGRAPH 2001 course notes.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iwarp.hpp"
#include "effigi/math/warp_functions.hpp"

namespace effigi {
namespace {

class UniformHemisphere final : public Implements<IWarp> {
public:
    static Schema schema() {
        Schema s("warp", "uniform_hemisphere", "Uniform directions on the hemisphere z >= 0; density 1/(2π).");
        s.cite("J. Arvo, Stratified Sampling of 2-Manifolds, SIGGRAPH 2001 course notes");
        return s;
    }
    explicit UniformHemisphere(const Properties&) {}

    WarpDomain domain() const override { return {WarpDomain::Kind::Sphere, {}, {}, "hemisphere z >= 0, uniform"}; }
    Vector3f sample(const Point2f& u) const override { return warp::squareToUniformHemisphere(u); }
    float pdf(const Vector3f& v) const override { return warp::squareToUniformHemispherePdf(v); }
    bool hasInverse() const override { return true; }
    Point2f inverse(const Vector3f& v) const override { return warp::uniformHemisphereToSquare(v); }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::UniformHemisphere)
