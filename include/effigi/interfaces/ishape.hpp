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

/// What a shader may ask of the surface under a hit beyond the SurfaceInteraction, on
/// request (IShape::localGeometry): nothing of it is computed while tracing, so a render
/// whose BSDFs and textures do not ask pays nothing for it.
struct LocalGeometry {
    /// The hit point in the shape's object space: before its to_world (and, through an
    /// instance, before the instance's to_world too).
    Point3f objectP{0.f};
    /// ∂n/∂u, ∂n/∂v: the change of the unit SHADING normal (si.shading.n) along the
    /// parametrisation of si.dpdu, si.dpdv, in world space. Zero on flat surfaces.
    Vector3f dndu{0.f}, dndv{0.f};
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

    /// Object-space point and normal derivatives at si, a point this shape's interaction()
    /// produced (call the free function localGeometry(si), which routes instanced hits
    /// through their instance). Only on request: renderers never call it. The default
    /// is a flat surface: objectP = si.p, dndu = dndv = 0.
    virtual LocalGeometry localGeometry(const SurfaceInteraction& si) const;

    /// True when the shape is somewhere else at other times (Ray::time): an instance with
    /// an animated to_world, or one of a group that holds such a shape.
    virtual bool moves() const { return false; }
};

/// The local geometry of the surface under si (IShape::localGeometry of the instance that
/// placed the hit, else of its shape); a flat surface at si.p when si has no shape.
inline LocalGeometry localGeometry(const SurfaceInteraction& si) {
    if (const IShape* s = si.instance ? si.instance : si.shape) return s->localGeometry(si);
    return LocalGeometry{si.p, Vector3f(0.f), Vector3f(0.f)};
}

/// Curvatures of the surface at a point (inverse scene units; Gaussian: their square).
/// Sign convention: positive where the surface bends away from its shading normal, so a
/// sphere with outward normals has mean curvature 1/r, Gaussian 1/r², k1 = k2 = 1/r
/// (flip_normals turns the mean and principal curvatures negative, not the Gaussian).
struct Curvature {
    float mean = 0.f;      ///< H = (k1 + k2) / 2
    float gaussian = 0.f;  ///< K = k1 · k2
    float k1 = 0.f, k2 = 0.f;  ///< principal curvatures, k1 ≥ k2
};

/// Curvature from si.dpdu, si.dpdv and g.dndu, g.dndv by the Weingarten equations (first
/// and second fundamental forms; do Carmo 1976, §3-3). A degenerate parametrisation (zero
/// or parallel ∂p/∂u, ∂p/∂v, e.g. a sphere's pole) gives zeros, never NaN.
Curvature curvature(const SurfaceInteraction& si, const LocalGeometry& g);

} // namespace effigi
