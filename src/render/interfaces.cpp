// Default methods of the rendering interfaces IBSDF and IEmitter: what a component
// gets when it has nothing better to say.
#include "effigi/core/error.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/iemitter.hpp"

#include <cstdint>

namespace effigi {

namespace {

/// Van der Corput radical inverse in base 2 (Hammersley's second coordinate): a
/// well-stratified lobe-selection value decorrelated from the direction strata.
float radicalInverse2(std::uint32_t i) {
    i = (i << 16u) | (i >> 16u);
    i = ((i & 0x00ff00ffu) << 8u) | ((i & 0xff00ff00u) >> 8u);
    i = ((i & 0x0f0f0f0fu) << 4u) | ((i & 0xf0f0f0f0u) >> 4u);
    i = ((i & 0x33333333u) << 2u) | ((i & 0xccccccccu) >> 2u);
    i = ((i & 0x55555555u) << 1u) | ((i & 0xaaaaaaaau) >> 1u);
    return std::min(float(i) * 0x1p-32f, OneMinusEpsilon);
}

} // namespace

// Directional albedo ρ(wo) = ∫ f(wo, wi) |cos θi| dωi at normal incidence, estimated by
// importance sampling the BSDF on a fixed N×N stratified grid: the result is
// deterministic (no noise between calls), exact for a Lambertian lobe sampled by
// cosine weighting, and correct for delta lobes whose f·cos/pdf is their weight.
SampledSpectrum IBSDF::albedo(const SurfaceInteraction& si, const SampledWavelengths& lambda) const {
    constexpr int N = 16;
    const Vector3f wo(0.f, 0.f, 1.f);
    SampledSpectrum sum(0.f);
    for (int i = 0; i < N; ++i) {
        for (int j = 0; j < N; ++j) {
            Point2f u((float(i) + 0.5f) / N, (float(j) + 0.5f) / N);
            float uc = radicalInverse2(std::uint32_t(i * N + j));
            SampledWavelengths l = lambda;  // sample() may terminate secondary wavelengths
            std::optional<BSDFSample> bs = sample(si, wo, uc, u, l, TransportMode::Radiance);
            if (!bs || !(bs->pdf > 0.f)) continue;
            SampledSpectrum w = bs->f * (Frame::absCosTheta(bs->wi) / bs->pdf);
            if (w.isFinite()) sum += w;
        }
    }
    return sum / float(N * N);
}

void IEmitter::attach(const IShape* shape) {
    (void)shape;
    fail("{} cannot be attached to a shape", typeName().empty() ? std::string("this emitter") : typeName());
}

float IEmitter::pdfDirect(const Point3f&, const SurfaceInteraction&) const { return 0.f; }

bool IEmitter::pdfEmission(const Point3f&, const Normal3f&, const Vector3f&, float& pdfPosition,
                           float& pdfDirection) const {
    pdfPosition = pdfDirection = 0.f;
    return false;
}

SampledSpectrum IEmitter::eval(const SurfaceInteraction&, const SampledWavelengths&) const {
    return SampledSpectrum(0.f);
}

SampledSpectrum IEmitter::evalEnvironment(const Vector3f&, const SampledWavelengths&) const {
    return SampledSpectrum(0.f);
}

float IEmitter::pdfEnvironment(const Point3f&, const Vector3f&) const { return 0.f; }

} // namespace effigi
