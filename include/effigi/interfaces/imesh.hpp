#pragma once
// IMesh — the surfaces of a scene cut into small planar elements that carry stored
// values: for radiosity, each element's spectral reflectance ρ, emission E and radiosity
// B in wavelength bins (Cohen & Wallace, "Radiosity and Realistic Image Synthesis", 1993,
// ch. 8: meshing). Elements are triangles or parallelograms; vertices are shared between
// neighbouring elements of one plane, so values can be interpolated across them
// (Gouraud shading of the solution).
//
// Which surfaces are meshed: those of triangle-mesh shapes whose BSDF is not purely
// specular, and every emitting one. Each element is ONE-SIDED: it reflects and emits on
// the side of its normal (the winding normal of its shape's triangles), as effigi's
// `diffuse` BSDF and `area` emitter do.
//
// Spectral values are bin averages over bins().count() equal bins of [LambdaMin,
// LambdaMax]; the arrays below hold bins().count() values per element, element-major.
#include "effigi/core/component.hpp"
#include "effigi/render/interaction.hpp"
#include "effigi/render/spectral_bins.hpp"

#include <array>
#include <cstdint>
#include <optional>
#include <span>

namespace effigi {

class IShape;

struct MeshElement {
    static constexpr std::uint32_t NoVertex = 0xffffffffu;
    /// Corners, counter-clockwise seen from the front; vertices[3] == NoVertex for a triangle.
    std::array<std::uint32_t, 4> vertices{NoVertex, NoVertex, NoVertex, NoVertex};
    Point3f centre{0.f};         ///< centroid
    Normal3f n{0.f, 0.f, 1.f};   ///< unit normal of the front side
    float area = 0.f;            ///< m² (scene units squared)
    std::uint32_t shape = 0;     ///< index into the shapes given to build()

    int corners() const { return vertices[3] == NoVertex ? 3 : 4; }
};

/// A surface point located on the mesh: its element and the interpolation weights of
/// the element's corners (p = Σ weights[k] · vertex[k]; weights[3] = 0 for triangles).
struct MeshPoint {
    std::uint32_t element = 0;
    std::array<float, 4> weights{0.f, 0.f, 0.f, 0.f};
};

class IMesh : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IMesh");
    static constexpr const char* Tag = "mesh";

    /// Mesh the surfaces of `shapes` (see above) and fill reflectance and emission; B is
    /// set to E. MeshElement::shape indexes this span, the same indexing as Hit::shape of
    /// an accelerator built over it. Replaces a previous mesh. Throws effigi::Error when
    /// nothing can be meshed.
    virtual void build(std::span<const IShape* const> shapes) = 0;

    virtual const SpectralBinning& bins() const = 0;
    virtual std::span<const MeshElement> elements() const = 0;
    virtual std::span<const Point3f> vertices() const = 0;
    /// The elements that share vertex v (adjacency, for interpolation).
    virtual std::span<const std::uint32_t> vertexElements(std::uint32_t v) const = 0;

    /// ρ per element and bin, in [0, 1].
    virtual std::span<const float> reflectance() const = 0;
    /// Emitted radiosity E = π L_e per element and bin [W m⁻² nm⁻¹].
    virtual std::span<const float> emission() const = 0;
    /// Radiosity B per element and bin [W m⁻² nm⁻¹]; solvers write it, then call
    /// radiosityChanged().
    virtual std::span<float> radiosity() = 0;
    virtual std::span<const float> radiosity() const = 0;
    /// Recompute what derives from B (vertex values).
    virtual void radiosityChanged() = 0;
    /// B at each vertex per bin: the area-weighted mean of the elements around it.
    virtual std::span<const float> vertexRadiosity() const = 0;

    /// The element under a surface point found by ray casting (si.shape, si.prim, si.p),
    /// or nullopt when the point's shape was not meshed.
    virtual std::optional<MeshPoint> locate(const SurfaceInteraction& si) const = 0;

    std::size_t elementCount() const { return elements().size(); }
};

} // namespace effigi
