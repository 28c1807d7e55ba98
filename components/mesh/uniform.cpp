// mesh "uniform" — the scene's diffuse and emitting surfaces cut into elements of one
// size, carrying spectral reflectance, emission and radiosity in wavelength bins; once
// solved it is also the solution as an illumination map (IMesh + IIlluminationMap).
//
// Quads (pairs of triangles forming a parallelogram) are split into parallelograms and
// triangles into k² triangles so that no element edge exceeds the edge length L: given
// as max_edge, or chosen so that the element count comes closest to element_count from
// below. Vertices of one plane are shared, for Gouraud interpolation of the solution.
// RGB reflectances and emissions are upsampled (Jakob & Hanika 2019) and averaged over
// each of `bins` equal bins of 360–830 nm.
//
// Parameters:
//   max_edge       float (default 0 = use element_count)  longest element edge [scene units]
//   element_count  int (default 2000, >= 1)  target number of elements
//   bins           int (default 32, 1..128)  wavelength bins of the stored spectra
//
// Reference: M. F. Cohen, J. R. Wallace, "Radiosity and Realistic Image Synthesis",
// Academic Press 1993, ch. 8 (meshing) and ch. 9 (rendering: Gouraud interpolation).
#include "effigi/core/registry.hpp"
#include "effigi/render/radiosity_mesh.hpp"

namespace effigi {
namespace {

RadiosityMeshOptions optionsFrom(const Properties& p) {
    RadiosityMeshOptions o;
    o.maxEdge = p.getFloat("max_edge");
    o.targetElements = std::uint64_t(p.getInt("element_count"));
    o.bins = int(p.getInt("bins"));
    return o;
}

class UniformMesh final : public RadiosityMesh {
public:
    static Schema schema() {
        Schema s("mesh", "uniform",
                 "Elements of one size over the diffuse and emitting surfaces, with spectral radiosity in bins; "
                 "the solved mesh is an illumination map.");
        s.cite("M. F. Cohen, J. R. Wallace, Radiosity and Realistic Image Synthesis, 1993, ch. 8-9");
        s.real("max_edge", 0.0, "Longest element edge; 0: chosen from element_count").atLeast(0.0).withUnit(
            "scene units");
        s.integer("element_count", 2000, "Target element count (from below) when max_edge is 0").range(1, 1e8);
        s.integer("bins", 32, "Wavelength bins over 360-830 nm").range(1, SpectralBinning::MaxBins);
        return s;
    }

    explicit UniformMesh(const Properties& p) : RadiosityMesh(optionsFrom(p)) {}
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::UniformMesh)
