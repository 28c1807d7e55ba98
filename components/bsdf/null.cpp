// bsdf "null" — an invisible surface (Mitsuba 3's null BSDF): light passes through it
// unchanged in direction and value, as through an interface between two media of the same
// index. It has only the pass-through lobe (BSDFNull): f() and pdf() are zero, sample()
// returns wi = −wo with weight 1, and evalNullTransmission() is 1, so shadow rays cross
// it. Renderers that know BSDFNull do not count the crossing as a bounce (renderer/path).
// Used to bound participating media and to hide a shape while keeping it in the scene.
//
// Parameters: none.
//
// Reference: Mitsuba 3 documentation, "Null material (null)".
#include "delta_bsdf.hpp"
#include "null_lobe.hpp"

#include "effigi/core/registry.hpp"

namespace effigi {
namespace {

class NullBSDF final : public DeltaBSDF {
public:
    static Schema schema() {
        Schema s("bsdf", "null", "Invisible surface: light passes straight through (a BSDFNull lobe only).");
        s.cite("Mitsuba 3 documentation, Null material (null)");
        s.addConformance({"default", {}});
        return s;
    }

    explicit NullBSDF(const Properties&) {}

    std::uint32_t flags() const override { return BSDFNull; }

    std::optional<BSDFSample> sample(const SurfaceInteraction&, const Vector3f& wo, float, const Point2f&,
                                     SampledWavelengths&, TransportMode) const override {
        return nullLobeSample(wo, 1.f, SampledSpectrum(1.f));
    }

    /// Nothing is reflected.
    SampledSpectrum albedo(const SurfaceInteraction&, const SampledWavelengths&) const override {
        return SampledSpectrum(0.f);
    }

    SampledSpectrum evalNullTransmission(const SurfaceInteraction&, const SampledWavelengths&) const override {
        return SampledSpectrum(1.f);
    }
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::NullBSDF)
