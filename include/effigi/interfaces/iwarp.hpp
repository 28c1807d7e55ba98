#pragma once
// IWarp — a map from the unit square [0,1)^2 onto a domain (a region of the plane or of
// the sphere of directions), together with the density of the points it produces and,
// where it exists, the inverse map. Warps turn a sampler's uniform points into the
// distributions a renderer needs (EFFIGI's warp components); effigi-conform checks that
// sample() and pdf() agree (chi-square), that pdf() integrates to 1 over the domain and
// that inverse(sample(u)) = u.
#include "effigi/core/component.hpp"
#include "effigi/core/error.hpp"
#include "effigi/math/vector.hpp"

#include <string>

namespace effigi {

/// Where a warp's points live and which measure its pdf is a density of.
struct WarpDomain {
    enum class Kind {
        Plane,   ///< points (x, y, 0); pdf per unit area dx dy
        Sphere,  ///< unit vectors; pdf per unit solid angle (sr⁻¹)
    };
    Kind kind = Kind::Plane;
    /// Plane: a bounding box of every point the warp can produce (histogram bounds).
    Point2f lower{0.f}, upper{1.f};
    /// Human-readable description, e.g. "unit disk", "hemisphere z >= 0".
    std::string description;
};

class IWarp : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IWarp");
    static constexpr const char* Tag = "warp";

    /// Dimension of the input point (every warp so far maps [0,1)^2).
    virtual int inputDimension() const { return 2; }
    /// The domain of the points sample() returns.
    virtual WarpDomain domain() const = 0;

    /// The point for the uniform input u ∈ [0,1)^2; planar points have z = 0.
    virtual Vector3f sample(const Point2f& u) const = 0;
    /// Density of sample()'s output at p with respect to the domain's measure; zero
    /// outside the set of points sample() can produce.
    virtual float pdf(const Vector3f& p) const = 0;

    /// Whether inverse() is implemented.
    virtual bool hasInverse() const { return false; }
    /// The input u with sample(u) = p, for p in the warp's image.
    virtual Point2f inverse(const Vector3f& p) const {
        (void)p;
        fail("warp '{}' has no inverse", typeName());
    }
};

} // namespace effigi
