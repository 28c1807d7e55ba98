#pragma once
// A point on a surface as seen by a ray: position, normals, shading frame, texture
// coordinates, and what is attached there (BSDF, emitter).
#include "effigi/math/frame.hpp"
#include "effigi/render/ray.hpp"

namespace effigi {

class IShape;
class IBSDF;
class IEmitter;

struct SurfaceInteraction {
    Point3f p{0.f};
    float t = Infinity;
    Normal3f n{0.f, 0.f, 1.f};  ///< geometric normal (winding / outward)
    Frame shading;              ///< shading frame; shading.n may differ from n
    Point2f uv{0.f};
    /// Partial derivatives of p with respect to uv (zero where the shape has no
    /// parametrisation); bump and normal maps perturb the shading frame with them.
    Vector3f dpdu{0.f}, dpdv{0.f};
    /// The primitive's own hit coordinates (barycentrics b1, b2 on triangles): per-vertex
    /// attributes (mesh_attribute) are interpolated with them.
    Point2f primUV{0.f};
    Vector3f wo{0.f};  ///< unit direction back along the arriving ray (world)
    const IShape* shape = nullptr;
    /// The `instance` that placed `shape` (null for a shape of the scene itself; Mitsuba
    /// 3's si.instance): shape stays the member, so its mesh, media and attributes are
    /// at hand, while localGeometry() goes through the instance's transform.
    const IShape* instance = nullptr;
    const IBSDF* bsdf = nullptr;
    const IEmitter* emitter = nullptr;
    std::uint32_t prim = 0;
    /// Magnitude of the values p was computed from (offsetRayOrigin's `scale`); 0: |p|.
    float pScale = 0.f;
    /// The time of the ray that found this point (Ray::time); rays leaving it keep it.
    float time = 0.f;

    Vector3f toLocal(const Vector3f& v) const { return shading.toLocal(v); }
    Vector3f toWorld(const Vector3f& v) const { return shading.toWorld(v); }

    /// p pushed off the surface to the side of d (offsetRayOrigin).
    Point3f offsetOrigin(const Vector3f& d) const { return offsetRayOrigin(p, n, d, pScale); }
    Ray spawnRay(const Vector3f& d) const { return Ray{offsetOrigin(d), d, Infinity, time}; }
    /// Ray toward target that stops just before it (shadow rays).
    Ray spawnRayTo(const Point3f& target) const {
        Vector3f d = target - p;
        Point3f o = offsetOrigin(d);
        return Ray{o, target - o, 1.f - ShadowEpsilon, time};
    }
};

} // namespace effigi
