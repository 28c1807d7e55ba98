// warp "uniform_sphere" — uniform directions on the whole unit sphere.
//
// z = 1 − 2u1 uniform in [−1, 1] and φ = 2π u2 (Archimedes' hat-box theorem): density
// 1/(4π) per unit solid angle. Invertible.
//
// Parameters: none.
//
// Reference: J. Arvo, "Stratified Sampling of 2-Manifolds", SIGGRAPH 2001 course notes.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iwarp.hpp"
#include "effigi/math/warp_functions.hpp"

namespace effigi {
namespace {

class UniformSphere final : public Implements<IWarp> {
public:
    static Schema schema() {
        Schema s("warp", "uniform_sphere", "Uniform directions on the unit sphere; density 1/(4π).");
        s.cite("J. Arvo, Stratified Sampling of 2-Manifolds, SIGGRAPH 2001 course notes");
        return s;
    }
    explicit UniformSphere(const Properties&) {}

    WarpDomain domain() const override { return {WarpDomain::Kind::Sphere, {}, {}, "unit sphere, uniform"}; }
    Vector3f sample(const Point2f& u) const override { return warp::squareToUniformSphere(u); }
    float pdf(const Vector3f& v) const override { return warp::squareToUniformSpherePdf(v); }
    bool hasInverse() const override { return true; }
    Point2f inverse(const Vector3f& v) const override { return warp::uniformSphereToSquare(v); }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::UniformSphere)
