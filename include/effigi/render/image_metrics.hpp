#pragma once
// Error of an image against a reference, and the error a renderer estimates for itself.
// relMSE follows the convergence literature (e.g. Rousselle et al. 2011): the mean of
// (x − r)² / (r² + ε) with ε = 0.01, which keeps dark pixels from dominating.
#include "effigi/interfaces/ifilm.hpp"

#include <vector>

namespace effigi {

struct ErrorMetrics {
    double rmse = 0.0;    ///< √ mean (x − r)² over pixels and R, G, B
    double relMSE = 0.0;  ///< mean (x − r)² / (r² + 0.01)
    double mae = 0.0;     ///< mean |x − r|
};

inline constexpr double RelMSEEpsilon = 0.01;

/// Compare the first three channels of two images of the same size; throws otherwise.
ErrorMetrics compareImages(const Image& image, const Image& reference);

/// relMSE predicted from a renderer's variance estimate (3 per pixel, R, G, B): the mean
/// of var / (x² + 0.01) — what ErrorMetrics::relMSE would measure, without a reference.
double estimatedRelMSE(const Image& image, const std::vector<float>& rgbVariance);

/// How much a reconstruction filter reduces the variance of a pixel compared with the
/// plain average of the samples inside it, for smooth images and uniformly spread
/// samples: (∫w² / (∫w)²)² for a separable filter w(x)·w(y) — 1 for the 0.5-radius box,
/// about 0.32 for Mitsuba's default Gaussian (σ = 0.5).
double filterVarianceFactor(const IFilter& filter);

/// Per-pixel (x − r)² / (r² + 0.01) averaged over R, G, B (for false-colour error images).
std::vector<float> relativeSquaredError(const Image& image, const Image& reference);

} // namespace effigi
