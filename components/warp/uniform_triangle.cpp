// warp "uniform_triangle" — uniform barycentric coordinates on a triangle.
//
// (b0, b1) = (1 − sqrt(u1), u2 sqrt(u1)), b2 = 1 − b0 − b1: uniform over the triangle
// {b0, b1 >= 0, b0 + b1 <= 1} of area 1/2, so the density is 2 per unit area of the
// (b0, b1) plane. Any triangle's points follow by the affine map Σ bi pi. Invertible.
//
// Parameters: none.
//
// Reference: G. Turk, "Generating Random Points in Triangles", Graphics Gems (1990);
// J. Arvo, "Stratified Sampling of 2-Manifolds", SIGGRAPH 2001 course notes.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iwarp.hpp"
#include "effigi/math/warp_functions.hpp"

namespace effigi {
namespace {

class UniformTriangle final : public Implements<IWarp> {
public:
    static Schema schema() {
        Schema s("warp", "uniform_triangle", "Uniform barycentrics (b0, b1) on a triangle; density 2.");
        s.cite("G. Turk, Generating Random Points in Triangles, Graphics Gems, 1990");
        return s;
    }
    explicit UniformTriangle(const Properties&) {}

    WarpDomain domain() const override {
        return {WarpDomain::Kind::Plane, Point2f(0.f), Point2f(1.f), "triangle b0, b1 >= 0, b0 + b1 <= 1"};
    }
    Vector3f sample(const Point2f& u) const override {
        Point2f b = warp::squareToUniformTriangle(u);
        return {b.x, b.y, 0.f};
    }
    float pdf(const Vector3f& b) const override {
        return b.x >= 0.f && b.y >= 0.f && b.x + b.y <= 1.f ? 2.f : 0.f;
    }
    bool hasInverse() const override { return true; }
    Point2f inverse(const Vector3f& b) const override {
        // b1 / (1 − b0) can round above 1 next to the b0 axis' far end; the input square is [0,1).
        Point2f u = warp::uniformTriangleToSquare({b.x, b.y});
        return {std::clamp(u.x, 0.f, OneMinusEpsilon), std::clamp(u.y, 0.f, OneMinusEpsilon)};
    }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::UniformTriangle)
