// warp "square_to_disk" — uniform points on the unit disk by the concentric map.
//
// Maps concentric squares of [0,1)^2 to concentric circles of the unit disk, so strata
// of the square stay compact on the disk (lower distortion than the polar map
// r = sqrt(u1), φ = 2π u2). Density 1/π per unit area inside the disk; invertible.
//
// Parameters: none.
//
// Reference: P. Shirley & K. Chiu, "A Low Distortion Map Between Disk and Square",
// Journal of Graphics Tools 2(3), 1997. Math in effigi/math/warp_functions.hpp.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iwarp.hpp"
#include "effigi/math/warp_functions.hpp"

namespace effigi {
namespace {

class SquareToDisk final : public Implements<IWarp> {
public:
    static Schema schema() {
        Schema s("warp", "square_to_disk", "Uniform points on the unit disk (concentric map); density 1/π.");
        s.cite("P. Shirley, K. Chiu, A Low Distortion Map Between Disk and Square, JGT 2(3), 1997");
        return s;
    }
    explicit SquareToDisk(const Properties&) {}

    WarpDomain domain() const override {
        return {WarpDomain::Kind::Plane, Point2f(-1.f), Point2f(1.f), "unit disk x² + y² <= 1"};
    }
    Vector3f sample(const Point2f& u) const override {
        Point2f p = warp::squareToUniformDiskConcentric(u);
        return {p.x, p.y, 0.f};
    }
    float pdf(const Vector3f& p) const override { return warp::squareToUniformDiskPdf({p.x, p.y}); }
    bool hasInverse() const override { return true; }
    Point2f inverse(const Vector3f& p) const override { return warp::uniformDiskToSquareConcentric({p.x, p.y}); }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::SquareToDisk)
