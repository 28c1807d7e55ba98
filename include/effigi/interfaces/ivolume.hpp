#pragma once
// IVolume — a 3-D texture over world space (Mitsuba 3's Volume, XML tag `volume`): the
// spatially varying data of a heterogeneous participating medium (its extinction σt,
// its albedo). A volume's domain is the unit cube [0, 1]³ carried into the world by its
// `to_world` transform; a grid fills that cube with its voxels, a constant volume has
// the same value everywhere. Points outside the domain are answered too (a grid clamps,
// repeats or mirrors its voxels there); a medium decides whether it extends beyond
// bbox() (Mitsuba's `heterogeneous` does not).
//
// Besides point values, a volume bounds itself: maxValue() over all of space and
// maxIn(box) over a world-space box, at every wavelength. A medium builds its majorants
// from these bounds (delta and ratio tracking need σ_maj ≥ σt at every point of a ray
// piece, include/effigi/render/transmittance.hpp), so they must be true bounds; tight
// ones make fewer null collisions. effigi-conform's `volume` suite checks them.
#include "effigi/core/component.hpp"
#include "effigi/math/bbox.hpp"
#include "effigi/math/transform.hpp"
#include "effigi/spectral/wavelengths.hpp"

namespace effigi {

class IVolume : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IVolume");
    static constexpr const char* Tag = "volume";

    /// Value at world point p at the path's wavelengths (finite and ≥ 0).
    virtual SampledSpectrum eval(const Point3f& p, const SampledWavelengths& lambda) const = 0;
    /// A scalar reading: a one-channel grid's value, an RGB grid's luminance, a
    /// constant spectrum's mean over the visible range (Mitsuba's eval_1).
    virtual float evalFloat(const Point3f& p) const = 0;
    /// Upper bound of eval (at every wavelength) and of evalFloat over all points.
    virtual float maxValue() const = 0;
    /// Upper bound of eval and evalFloat over the points of a world-space box (for
    /// majorant grids). Default: the global bound.
    virtual float maxIn(const BBox3f& box) const {
        (void)box;
        return maxValue();
    }
    /// The domain in the world: the world-space bounding box of toWorld()([0, 1]³).
    virtual BBox3f bbox() const = 0;
    /// The map from the unit cube to world space (to_world, and for grids read with
    /// use_grid_bbox the file's own box).
    virtual Transform toWorld() const = 0;
    /// Voxels along x, y, z of the unit cube (1, 1, 1 for a volume that is no grid).
    /// Voxel (i, j, k) has its centre at ((i + ½)/nx, (j + ½)/ny, (k + ½)/nz).
    virtual glm::ivec3 resolution() const { return {1, 1, 1}; }
    /// True when eval does not depend on the point.
    virtual bool isConstant() const { return false; }
};

} // namespace effigi
