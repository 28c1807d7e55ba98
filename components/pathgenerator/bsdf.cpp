// pathgenerator "bsdf" — random walks that continue by sampling the BSDF.
//
// At every surface the walk draws the next direction from the surface's own BSDF
// (IBSDF::sample) and reports the BSDF's density (IBSDF::pdf): the walk of pbrt-v4's and
// Mitsuba 0.6's bidirectional path tracers, and the default of `bdpt` and of `pssmlt`'s
// bdpt technique. The walks, throughput and Russian roulette are IPathGenerator's
// defaults (src/render/path_generator.cpp).
//
// Parameters: none.
//
// Reference: E. Veach, Robust Monte Carlo Methods for Light Transport Simulation, PhD
// thesis, Stanford 1997, §10.2; E. Lafortune, Y. Willems, "Bi-directional path tracing",
// Compugraphics 1993.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ipathgenerator.hpp"

namespace effigi {
namespace {

class BSDFPathGenerator final : public Implements<IPathGenerator> {
public:
    static Schema schema() {
        Schema s("pathgenerator", "bsdf", "Subpaths that continue by sampling each surface's BSDF.");
        s.cite("E. Veach, Robust Monte Carlo Methods for Light Transport Simulation, PhD thesis, 1997, §10.2");
        s.addConformance({"default", {}});
        return s;
    }
    explicit BSDFPathGenerator(const Properties&) {}

    std::optional<BSDFSample> sampleDirection(const SurfaceInteraction& si, const Vector3f& wo, float uc,
                                              const Point2f& u, SampledWavelengths& lambda,
                                              TransportMode mode) const override {
        return si.bsdf->sample(si, wo, uc, u, lambda, mode);
    }
    float pdfDirection(const SurfaceInteraction& si, const Vector3f& wo, const Vector3f& wi,
                       const SampledWavelengths& lambda, TransportMode mode) const override {
        return si.bsdf->pdf(si, wo, wi, lambda, mode);
    }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::BSDFPathGenerator)
