#pragma once
// `adaptive` in mode "pixels": per-pixel adaptive sampling. A renderer pass of M samples a
// pixel (renderSampled, IPixelAllocator) draws a pilot of k = f M / 8 samples in every
// pixel, then n_j more in pixel j, so that pixels spend f M on average (f = mean_share)
// and none more than M (its sample indices stay within the pass's, which later passes
// continue). Inside a pixel it is plain Monte Carlo: stratifying a pixel's path space costs
// more per sample than it saves on a path tracer's integrands.
//
// Why n_j ∝ √d_j. relMSE (image_metrics.hpp) is the mean of (x − r)² / (r² + ε) over the
// pixels; pixel j's term is d_j / n_j, d_j = Σ_c σ_c² / (μ_c² + ε) the relative variance of
// one of its samples. Minimising Σ d_j / n_j for a fixed Σ n_j gives n_j ∝ √d_j (Neyman's
// allocation, pixels as strata). Equalising the pixels' errors instead (n_j ∝ d_j: stop
// each pixel at a relative-error target) gives exactly uniform sampling's Σ d_j / n_j at
// the same total, before estimation noise; that is why `rel_error` cannot pay on an image.
//
// Estimating d_j. A pixel's own pilot is a handful of heavy-tailed path samples: its σ̂
// misses the rare bright paths as often as not, and allocating by it loses to uniform
// sampling. d̂ is therefore the mean of the pilots' relative variances over a window of
// (2R+1)² pixels (R = 2 below 8 pilot samples, else 1: at least 64 samples a window); the
// film's reconstruction filter spreads each pixel's noise over such a neighbourhood anyway
// (image-space adaptive samplers likewise allocate by a filtered error estimate, e.g.
// Rousselle, Knaus & Zwicker 2011). The share of a pixel is (1 − a) √d̂_j / mean √d̂ + a,
// a = 0.1 a defensive uniform part for pixels whose neighbourhood's pilots all missed
// their light paths; n_j = clamp(λ share_j, 1, M − k), λ found by bisection so that the
// counts add up to f M − k a pixel.
//
// Unbiased: the pilot weighs a fixed k / (f M) of each pixel and the rest 1 − k / (f M),
// both fixed before either is drawn, so E[pixel] = μ_j whatever n_j the pilots led to
// (Kirk & Arvo 1991: reusing the samples that chose n_j with weights depending on n_j
// biases the pixel). A pixel that draws fewer samples than f M − k is noisier than a
// pooled estimate would be, by little while k ≪ f M.
//
// Measured (bench/RESULTS.md, Cornell box 128²): at equal samples relMSE 0.86–0.88 of
// uniform sampling's (the best any per-pixel allocation could do there is 0.8: the box's
// relative noise is spread evenly), about 10 % less CPU time to reach a relMSE.
//
// References: J. Neyman, J. Royal Statistical Society 97(4), 1934; D. Kirk, J. Arvo,
// "Unbiased sampling techniques for image synthesis", SIGGRAPH 1991; F. Rousselle,
// C. Knaus, M. Zwicker, "Adaptive sampling and reconstruction using greedy error
// minimization", SIGGRAPH Asia 2011.
#include "effigi/interfaces/iintegrator_hooks.hpp"
#include "effigi/math/running_estimate.hpp"
#include "effigi/render/image_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <span>
#include <vector>

namespace effigi {

class PixelAllocation {
public:
    explicit PixelAllocation(double meanShare) : m_meanShare(meanShare) {}

    /// Pilot k = f M / 8 (≥ 4) weighing k / (f M); none (uniform) where f M < 32.
    IPixelAllocator::Plan plan(std::uint64_t budget) const {
        const double spend = m_meanShare * double(budget);
        if (spend < 32.0) return {};
        const std::uint64_t pilot = std::max<std::uint64_t>(4, std::uint64_t(spend / 8.0));
        return {pilot, double(pilot) / spend};
    }

    void allocate(std::span<const PixelPilot> pilots, int width, int height, std::uint64_t budget,
                  std::vector<std::uint64_t>& counts) const {
        const auto [pilot, share] = plan(budget);
        const std::size_t n = std::size_t(width) * std::size_t(height);
        const std::uint64_t cap = budget - pilot;
        const double rest = m_meanShare * double(budget) - double(pilot);
        std::vector<double> d(n, 0.0);
        for (std::size_t i = 0; i < std::min(n, pilots.size()); ++i)
            for (int c = 0; c < 3; ++c) {
                const double mu = pilots[i].mean[c], s2 = double(pilots[i].variance[c]) * pilots[i].samples;
                if (std::isfinite(s2) && s2 > 0.0) d[i] += s2 / (mu * mu + RelMSEEpsilon);
            }
        boxMean(d, width, height, pilot < 8 ? 2 : 1);
        double sum = 0.0;
        for (double& v : d) sum += (v = std::sqrt(v));
        for (double& v : d) v = (1.0 - Defensive) * (sum > 0.0 ? v * double(n) / sum : 1.0) + Defensive;
        auto countOf = [&](double lambda, double s) {
            return std::clamp<std::uint64_t>(std::uint64_t(std::llround(lambda * s)), 1, cap);
        };
        double lo = 0.0, hi = double(cap) / Defensive;  // hi: every pixel at the cap
        for (int it = 0; it < 60; ++it) {
            const double mid = 0.5 * (lo + hi);
            double total = 0.0;
            for (double s : d) total += double(countOf(mid, s));
            (total > rest * double(n) ? hi : lo) = mid;
        }
        counts.resize(n);
        for (std::size_t i = 0; i < n; ++i) counts[i] = countOf(lo, d[i]);
    }

    /// Plain Monte Carlo over the pixel (the samples' weights are the renderer's business).
    static Estimate integrate(IFunction& f, ISampler& sampler, std::uint64_t first, std::uint64_t count) {
        RunningEstimate running(f.channels());
        std::array<double, Estimate::MaxChannels> value{};
        for (std::uint64_t i = 0; i < count; ++i) {
            sampler.startSample(first + i);
            value.fill(0.0);
            f.eval(sampler, std::span<double>(value.data(), std::size_t(f.channels())));
            running.add(value);
        }
        return running.estimate();
    }

private:
    static constexpr double Defensive = 0.1;  // see above

    /// v ← its mean over the (2r+1)² window, clipped at the image's border (separable).
    static void boxMean(std::vector<double>& v, int width, int height, int r) {
        std::vector<double> tmp(v.size());
        auto pass = [&](const std::vector<double>& in, std::vector<double>& out, bool rows) {
            const int len = rows ? width : height, lines = rows ? height : width;
            for (int l = 0; l < lines; ++l)
                for (int k = 0; k < len; ++k) {
                    double s = 0.0;
                    const int a = std::max(0, k - r), b = std::min(len - 1, k + r);
                    for (int m = a; m <= b; ++m)
                        s += in[rows ? std::size_t(l) * width + m : std::size_t(m) * width + l];
                    out[rows ? std::size_t(l) * width + k : std::size_t(k) * width + l] = s / double(b - a + 1);
                }
        };
        pass(v, tmp, true);
        pass(tmp, v, false);
    }

    double m_meanShare;
};

} // namespace effigi
