#pragma once
// Shared plumbing of shapes: the BSDF and emitter nested in them, to_world, and the
// triangle-mesh implementation that obj, ply, rectangle and cube build on.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/imedium.hpp"
#include "effigi/interfaces/ishape.hpp"

#include <vector>

namespace effigi {

class ShapeBase : public Implements<IShape> {
public:
    /// Schema entries every shape has: to_world, bsdf, emitter, interior, exterior,
    /// flip_normals.
    static void addCommonParams(Schema& s);

    /// Reads to_world, flip_normals, the nested bsdf (a default diffuse one when absent)
    /// and emitter. The emitter is attached by attachEmitter(), not here: an emitter may
    /// ask the shape for its area while attaching, which is only known once the
    /// subclass has built its geometry.
    explicit ShapeBase(const Properties& props);

    const IBSDF* bsdf() const override { return m_bsdf.get(); }
    const IEmitter* emitter() const override { return m_emitter.get(); }
    IEmitter* emitter() override { return m_emitter.get(); }
    const IMedium* interiorMedium() const override { return m_interior.get(); }
    const IMedium* exteriorMedium() const override { return m_exterior.get(); }
    /// Whether no <bsdf> was nested, so bsdf() is the default diffuse one (a csg gives
    /// such parts its own BSDF instead).
    bool hasDefaultBsdf() const { return m_defaultBsdf; }
    /// Flat: objectP by the inverse of to_world, no normal change (sphere, cylinder and
    /// meshes override it with their normal derivatives).
    LocalGeometry localGeometry(const SurfaceInteraction& si) const override;

protected:
    /// Fill the parts of a SurfaceInteraction that come from the shape itself.
    void finish(SurfaceInteraction& si, const Ray& ray) const {
        si.wo = -ray.d;
        float l2 = dot(si.wo, si.wo);
        if (l2 > 0.f && l2 != 1.f) si.wo *= 1.f / std::sqrt(l2);
        si.shape = this;
        si.bsdf = m_bsdf.get();
        si.emitter = m_emitter.get();
    }
    /// World point p carried back through to_world's inverse (p itself where that is not
    /// finite: a to_world that flattens the shape).
    Point3f objectPoint(const Point3f& p) const;
    /// Call once the geometry is complete (end of the subclass constructor;
    /// MeshShape::setMesh does it): hands this shape to its nested emitter.
    void attachEmitter();

    Transform m_toWorld;
    Ref<IBSDF> m_bsdf;
    Ref<IEmitter> m_emitter;
    Ref<IMedium> m_interior, m_exterior;
    bool m_flipNormals = false;
    bool m_defaultBsdf = false;

private:
    SourceLocation m_emitterWhere;  // where the nested emitter was declared (errors)
};

/// A shape made of triangles. Subclasses fill m_mesh in object space and call
/// setMesh(), which applies to_world and prepares area sampling.
class MeshShape : public ShapeBase {
public:
    /// The common parameters (if not yet declared) + face_normals.
    static void addMeshParams(Schema& s);
    explicit MeshShape(const Properties& props);

    BBox3f bbox() const override { return m_bbox; }
    const TriangleMesh* mesh() const override { return &m_mesh; }
    SurfaceInteraction interaction(const Ray& ray, const Hit& hit) const override;
    float area() const override { return m_area; }
    PositionSample samplePosition(const Point2f& u) const override;
    /// ∂n/∂u, ∂n/∂v of the interpolated vertex normals over the hit triangle, in the
    /// parametrisation interaction() gives dpdu, dpdv (the mesh uv, else the barycentrics).
    LocalGeometry localGeometry(const SurfaceInteraction& si) const override;

protected:
    /// Validate (errors prefixed by `what`, e.g. the file name), apply to_world,
    /// flip_normals and face_normals, build the area CDF and bounds, attach the emitter.
    void setMesh(TriangleMesh mesh, const std::string& what);
    /// What every hit on triangle hit.prim gets alike, whatever the normals: p from the
    /// barycentrics (exact on the triangle's plane), pScale, t, prim, primUV and uv (the
    /// mesh's uv, else the barycentrics). Returns the triangle's three vertex indices.
    const std::uint32_t* hitPoint(const Hit& hit, SurfaceInteraction& si) const;

    TriangleMesh m_mesh;
    std::vector<float> m_areaCdf;  // cumulative triangle areas (zero-area ones add nothing)
    float m_area = 0.f;
    BBox3f m_bbox;
    bool m_faceNormals = false;
};

} // namespace effigi
