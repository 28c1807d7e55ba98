// warp "cosine_hemisphere" — directions on the hemisphere z >= 0 with density cosθ/π.
//
// Malley's method: a uniform point of the unit disk (concentric map) lifted vertically
// onto the hemisphere is distributed as cosθ/π per unit solid angle, because the
// projected solid angle of a patch is its area on the disk. The importance sampling of a
// Lambertian lobe; invertible through the disk.
//
// Parameters: none.
//
// Reference: pbrt-v4 §A.5.3 (Malley's method); P. Shirley & K. Chiu, JGT 2(3), 1997.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iwarp.hpp"
#include "effigi/math/warp_functions.hpp"

namespace effigi {
namespace {

class CosineHemisphere final : public Implements<IWarp> {
public:
    static Schema schema() {
        Schema s("warp", "cosine_hemisphere", "Cosine-weighted directions on the hemisphere z >= 0 (Malley's method).");
        s.cite("M. Pharr, W. Jakob, G. Humphreys, pbrt-v4, §A.5.3 (Malley's method)");
        return s;
    }
    explicit CosineHemisphere(const Properties&) {}

    WarpDomain domain() const override { return {WarpDomain::Kind::Sphere, {}, {}, "hemisphere z >= 0, density cosθ/π"}; }
    Vector3f sample(const Point2f& u) const override { return warp::squareToCosineHemisphere(u); }
    float pdf(const Vector3f& v) const override { return warp::squareToCosineHemispherePdf(v); }
    bool hasInverse() const override { return true; }
    Point2f inverse(const Vector3f& v) const override { return warp::cosineHemisphereToSquare(v); }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::CosineHemisphere)
