#pragma once
// IShape — geometry. A shape is either a triangle mesh (handed to accelerators as
// triangles) or analytic (intersected by its own code through the accelerator). Any
// shape can carry a BSDF and an area emitter; it can be sampled by area and by solid
// angle from a reference point, which is what makes any geometry a light (Spectrum).
#include "effigi/core/component.hpp"
#include "effigi/math/bbox.hpp"
#include "effigi/render/interaction.hpp"
#include "effigi/render/mesh.hpp"

namespace effigi {

class IBSDF;
class IEmitter;
class IMedium;

struct PositionSample {
    Point3f p{0.f};
    Normal3f n{0.f, 0.f, 1.f};
    Point2f uv{0.f};
    float pdf = 0.f;  ///< area density
};

/// A point on the shape sampled as seen from a reference point.
struct DirectionSample : PositionSample {
    Vector3f wi{0.f};  ///< unit direction from the reference point to p
    float dist = 0.f;  ///< distance from the reference point to p
    /// pdf is a solid-angle density here.
};

class IShape : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IShape");
    static constexpr const char* Tag = "shape";

    virtual BBox3f bbox() const = 0;
    /// Triangles in world space, or null for an analytic shape.
    virtual const TriangleMesh* mesh() const { return nullptr; }
    /// Analytic shapes: closest intersection with the ray in (0, ray.tMax); uv is the
    /// shape's own parametrisation, passed back to interaction().
    virtual bool intersect(const Ray& ray, float& t, Point2f& uv) const;

    /// Full surface description at a hit found by an accelerator.
    virtual SurfaceInteraction interaction(const Ray& ray, const Hit& hit) const = 0;

    virtual float area() const = 0;
    /// Uniform point by area.
    virtual PositionSample samplePosition(const Point2f& u) const = 0;
    /// Point sampled with a solid-angle density as seen from ref. The default samples by
    /// area and converts; shapes with a better strategy (spheres: the visible cone) override.
    virtual DirectionSample sampleDirection(const Point3f& ref, const Point2f& u) const;
    /// Solid-angle density of sampleDirection(ref) producing the point si (seen along si.wo).
    virtual float pdfDirection(const Point3f& ref, const SurfaceInteraction& si) const;

    virtual const IBSDF* bsdf() const = 0;
    virtual const IEmitter* emitter() const = 0;
    virtual IEmitter* emitter() = 0;

    /// The participating media inside and outside the surface (Mitsuba's `interior` and
    /// `exterior`); null is vacuum. A shape with either is a medium boundary: a ray
    /// leaving it along d is in the exterior medium when d·n > 0, else in the interior
    /// one. Other shapes leave a ray's medium unchanged.
    virtual const IMedium* interiorMedium() const { return nullptr; }
    virtual const IMedium* exteriorMedium() const { return nullptr; }
    bool isMediumTransition() const { return interiorMedium() || exteriorMedium(); }

    /// True when the shape is somewhere else at other times (Ray::time): an instance with
    /// an animated to_world, or one of a group that holds such a shape.
    virtual bool moves() const { return false; }
};

} // namespace effigi
