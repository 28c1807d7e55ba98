#pragma once
// RadiosityMesh — the element mesh of a radiosity solution and the solution itself: an
// IMesh (elements, vertices, spectral ρ, E, B in bins) and an IIlluminationMap (the
// light leaving a surface point, looked up in the mesh). The `mesh` components
// (components/mesh/*) are this class with their own schema.
//
// Meshing. Each triangle-mesh shape is cut into planar patches: two consecutive
// triangles that form a parallelogram (rectangles, cube faces, quads of OBJ files)
// become one quad patch, any other triangle a triangle patch. A quad patch is split into
// nu × nv parallelograms, nu = ⌈|e1| / L⌉, nv = ⌈|e2| / L⌉; a triangle patch into k²
// triangles, k = ⌈longest edge / L⌉, for an edge length L that is given or found by
// bisection to come closest to a target element count from below. Vertices at the same
// place with the same normal are welded (also across patches and shapes), so values
// interpolate across patch seams of one plane but not around corners.
//
// Spectra. ρ (IBSDF::albedo) and L_e (IEmitter::eval toward the normal) are evaluated at
// the element's centre at 8 wavelengths per bin (bin midpoints) and averaged: bin b then
// holds the bin average, and E = π L_e.
#include "effigi/core/component.hpp"
#include "effigi/interfaces/iilluminationmap.hpp"
#include "effigi/interfaces/imesh.hpp"

#include <filesystem>
#include <unordered_map>
#include <vector>

namespace effigi {

struct RadiosityMeshOptions {
    float maxEdge = 0.f;                ///< > 0: no element edge longer than this
    std::uint64_t targetElements = 0;   ///< used when maxEdge is 0
    int bins = 32;                      ///< wavelength bins over [LambdaMin, LambdaMax]
};

class RadiosityMesh : public Implements<IMesh, IIlluminationMap> {
public:
    explicit RadiosityMesh(const RadiosityMeshOptions& options);

    // IMesh
    void build(std::span<const IShape* const> shapes) override;
    const SpectralBinning& bins() const override { return m_bins; }
    std::span<const MeshElement> elements() const override { return m_elements; }
    std::span<const Point3f> vertices() const override { return m_vertices; }
    std::span<const std::uint32_t> vertexElements(std::uint32_t v) const override {
        return {m_adjacency.data() + m_adjacencyStart[v], m_adjacency.data() + m_adjacencyStart[v + 1]};
    }
    std::span<const float> reflectance() const override { return m_rho; }
    std::span<const float> emission() const override { return m_emission; }
    std::span<float> radiosity() override { return m_radiosity; }
    std::span<const float> radiosity() const override { return m_radiosity; }
    void radiosityChanged() override;
    std::span<const float> vertexRadiosity() const override { return m_vertexRadiosity; }
    std::optional<MeshPoint> locate(const SurfaceInteraction& si) const override;

    // IIlluminationMap: B/π interpolated from the vertices (Gouraud), per wavelength bin.
    bool covers(const SurfaceInteraction& si) const override;
    SampledSpectrum radiance(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override;
    SampledSpectrum irradiance(const SurfaceInteraction& si, const SampledWavelengths& lambda) const override;

    /// The element edge length L the last build() used.
    float edgeLength() const { return m_edge; }

    /// A planar source polygon: o + s e1 + t e2 with (s, t) in the unit square (quad) or
    /// the unit triangle s + t ≤ 1 (triangle); its elements and vertices are numbered
    /// from firstElement and firstVertex.
    struct Patch {
        std::uint32_t shape = 0;
        std::uint32_t tri[2] = {0, 0};
        bool quad = false;
        Point3f o{0.f};
        Vector3f e1{0.f}, e2{0.f}, n{0.f};
        Vector3f d1{0.f}, d2{0.f};  ///< dual basis: s = d1·(p − o), t = d2·(p − o)
        /// The corners as the shape has them: quad (s,t) = (0,0), (1,0), (1,1), (0,1);
        /// triangle o, o + e1, o + e2 (corner[3] unused).
        Point3f corner[4] = {Point3f(0.f), Point3f(0.f), Point3f(0.f), Point3f(0.f)};
        std::uint32_t nu = 1, nv = 1, firstElement = 0, firstVertex = 0;
    };

private:
    void subdivide(std::vector<Patch>& patches, float edge);
    void weld();
    void evaluateMaterials(std::span<const IShape* const> shapes);
    /// B interpolated at p, bin b.
    float interpolated(const MeshPoint& p, int b) const;

    RadiosityMeshOptions m_options;
    SpectralBinning m_bins;
    float m_edge = 0.f;
    std::vector<Patch> m_patches;
    std::vector<MeshElement> m_elements;
    std::vector<Point3f> m_vertices;
    std::vector<Normal3f> m_vertexNormals;
    std::vector<std::uint32_t> m_adjacencyStart, m_adjacency;
    std::vector<float> m_rho, m_emission, m_radiosity, m_vertexRadiosity;
    // Locating hits: shape pointer -> index; (shape, triangle) -> patch.
    std::unordered_map<const IShape*, std::uint32_t> m_shapeIndex;
    std::vector<std::uint64_t> m_triangleStart;   // per shape: first entry in m_trianglePatch
    std::vector<std::uint32_t> m_trianglePatch;   // NoPatch where a triangle was not meshed
    static constexpr std::uint32_t NoPatch = 0xffffffffu;
};

/// Write B of a mesh to a file, with a fingerprint of the mesh (element count, bins,
/// geometry hash) so that loading checks it belongs to the same mesh. Throws effigi::Error.
void saveRadiositySolution(const IMesh& mesh, const std::filesystem::path& file);
/// Read B written by saveRadiositySolution into a mesh built the same way; throws
/// effigi::Error naming the file when it is missing, corrupt or for another mesh.
void loadRadiositySolution(IMesh& mesh, const std::filesystem::path& file);

} // namespace effigi
