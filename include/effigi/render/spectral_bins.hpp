#pragma once
// Spectral bins for spectral image output: N equal bins over [λmin, λmax], filled from
// hero-wavelength path samples, and the channel naming of the spectral OpenEXR layout of
// A. Fichet, R. Pacanowski, A. Wilkie, "An OpenEXR Layout for Spectral Images", JCGT
// 10(3), 2021: emissive, unpolarised channels are "S0.<centre><unit>", the centre written
// with a comma as decimal separator (effigi writes "S0.550,000000nm").
//
// Estimator. A bin b = [a, a + w) stores the bin average of spectral radiance,
//   S_b = (1/w) ∫_b L(λ) dλ        (W m⁻² sr⁻¹ nm⁻¹ in effigi's units).
// A path carries four wavelengths λ_i with pdfs p_i (Wilkie et al. 2014); each is an
// independent-marginal sample, so (1/4) Σ_i 1[λ_i ∈ b] L(λ_i) / p_i is unbiased for
// ∫_b L dλ, and dividing by w gives S_b. A wavelength whose pdf is 0 (secondary
// wavelengths ended at a dispersive interface) adds nothing; the hero's pdf already
// carries the factor 1/4 then (SampledWavelengths::terminateSecondary).
// Collapsing the bins to XYZ (xyzWeights) matches the film's XYZ up to the bin
// quantisation: with the box reading X = Σ_b S_b ∫_b x̄ dλ / ∫ ȳ dλ the error is the
// covariance of S and x̄ within each bin (≤ 0.8 % of Y at 32 bins for smooth saturated
// spectra); the linear reading (a slope per bin from its neighbours) cuts it to ≤ 0.1 %.
#include "effigi/math/vector.hpp"
#include "effigi/spectral/wavelengths.hpp"

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace effigi {

class SpectralBinning {
public:
    /// Upper bound of the bin count: renderers keep a bin buffer of this size on the stack.
    static constexpr int MaxBins = 128;

    SpectralBinning() = default;  // no bins
    /// `count` bins over [lambdaMin, lambdaMax] nm. Throws effigi::Error unless
    /// 0 ≤ count ≤ MaxBins and LambdaMin ≤ lambdaMin < lambdaMax ≤ LambdaMax.
    SpectralBinning(int count, float lambdaMin, float lambdaMax);

    int count() const { return m_count; }
    bool enabled() const { return m_count > 0; }
    float lambdaMin() const { return m_min; }
    float lambdaMax() const { return m_max; }
    float width() const { return m_width; }
    float center(int b) const { return m_min + (float(b) + 0.5f) * m_width; }
    /// Lower edge of bin b; edge(count()) is lambdaMax.
    float edge(int b) const { return b == m_count ? m_max : m_min + float(b) * m_width; }
    /// The bin holding λ, or −1 outside [lambdaMin, lambdaMax] (λmax belongs to the last bin).
    int binOf(float lambda) const {
        if (!(lambda >= m_min && lambda <= m_max)) return -1;
        int b = int((lambda - m_min) * m_invWidth);
        return b < m_count ? b : m_count - 1;
    }

    /// Writes this sample's estimates of the bin averages S_b into out[0, count()): zero
    /// except for the bins holding a sampled wavelength. No allocation. Returns false
    /// (and writes zeros) if an estimate is not finite.
    bool estimate(const SampledSpectrum& L, const SampledWavelengths& lambda, float* out) const;

    /// Fichet et al. channel names of the bins ("S0.<centre>nm"), in bin order.
    std::vector<std::string> channelNames() const;

private:
    int m_count = 0;
    float m_min = LambdaMin, m_max = LambdaMax, m_width = 0.f, m_invWidth = 0.f;
};

namespace spectral_exr {

/// "S0.<λ>nm" with six decimals and a comma (Fichet et al. 2021).
std::string channelName(double lambdaNm);
/// The wavelength in nm of an emissive, unpolarised (S0) channel name of the layout, in
/// any unit it allows (prefixed metres or hertz, e.g. "S0.550nm", "S0.5,5E-7m",
/// "S0.545,077THz"); nullopt for other names.
std::optional<double> parseChannelName(std::string_view name);
/// Edges of bands given by sorted, distinct centres: halfway between neighbours, the
/// outer bands as wide on their outer side as on their inner side (the layout's box
/// response). Needs ≥ 2 centres; a single band needs its width from elsewhere.
std::vector<double> edgesFromCenters(std::span<const double> centers);
/// How band means are read as a spectrum when collapsing to XYZ.
enum class Reconstruction {
    Box,     ///< constant within each band (the layout's box response)
    Linear,  ///< within each band its mean plus a slope from the neighbouring bands' means
};
/// XYZ weights of bands [edges[b], edges[b+1]]: XYZ = Σ_b S_b · weights[b], in effigi's
/// convention (∫ S x̄ dλ / ∫ ȳ dλ over all wavelengths), with the CIE 1931 tables
/// interpolated linearly and integrated exactly (zero outside 360–830 nm). Box gives
/// (∫_b x̄, ∫_b ȳ, ∫_b z̄) / ∫ ȳ; Linear keeps each band's mean and adds a slope from the
/// neighbours' means (central differences), which removes the first-order bin
/// quantisation error Σ_b S'_b ∫_b (λ − m_b) x̄ dλ of Box for spectra smooth on the band
/// scale.
std::vector<Vector3f> xyzWeights(std::span<const double> edges, Reconstruction r = Reconstruction::Linear);

} // namespace spectral_exr
} // namespace effigi
