// warp "uniform_cone" — uniform directions in the cone of half-angle θmax about +z.
//
// z = 1 − u1 (1 − cosθmax) uniform in [cosθmax, 1] and φ = 2π u2: density
// 1/(2π (1 − cosθmax)) per unit solid angle inside the cone, zero outside. Used to
// sample spherical lights by their subtended cone. Invertible.
//
// Parameters:
//   cos_cutoff  float (default 0.5, in [−1, 0.9999])  cosθmax; −1 is the whole sphere
//
// Reference: J. Arvo, "Stratified Sampling of 2-Manifolds", SIGGRAPH 2001 course notes.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iwarp.hpp"
#include "effigi/math/warp_functions.hpp"

namespace effigi {
namespace {

class UniformCone final : public Implements<IWarp> {
public:
    static Schema schema() {
        Schema s("warp", "uniform_cone", "Uniform directions in a cone about +z; density 1/(2π(1 − cosθmax)).");
        s.cite("J. Arvo, Stratified Sampling of 2-Manifolds, SIGGRAPH 2001 course notes");
        // Above 0.9999 the cone (< 0.8° half-angle) is too narrow for float directions to
        // resolve: z = 1 − u1 (1 − cosθmax) rounds to 1.
        s.real("cos_cutoff", 0.5, "Cosine of the half-angle θmax (−1: whole sphere)").range(-1.0, 0.9999);
        s.addConformance({"narrow", {{"cos_cutoff", 0.999}}});
        s.addConformance({"hemisphere", {{"cos_cutoff", 0.0}}});
        s.addConformance({"sphere", {{"cos_cutoff", -1.0}}});
        return s;
    }
    explicit UniformCone(const Properties& p) : m_cosMax(p.getFloat("cos_cutoff")) {}

    WarpDomain domain() const override {
        return {WarpDomain::Kind::Sphere, {}, {}, fmt::format("cone z >= {} about +z, uniform", m_cosMax)};
    }
    Vector3f sample(const Point2f& u) const override { return warp::squareToUniformCone(u, m_cosMax); }
    float pdf(const Vector3f& v) const override { return warp::squareToUniformConePdf(v, m_cosMax); }
    bool hasInverse() const override { return true; }
    Point2f inverse(const Vector3f& v) const override { return warp::uniformConeToSquare(v, m_cosMax); }

private:
    float m_cosMax;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::UniformCone)
