#pragma once
// A sample mean with its variance built one value at a time, by Welford's update, which
// stays accurate when the mean is large against the spread (the naive Σf² − (Σf)²/n
// cancels catastrophically). Shared by the `mean` integrator and the path tracer's
// wavefront, which keeps one per pixel.
// Reference: B. P. Welford, "Note on a method for calculating corrected sums of squares
// and products", Technometrics 4(3), 1962.
#include "effigi/interfaces/iintegrator.hpp"

#include <array>
#include <limits>
#include <span>

namespace effigi {

class RunningEstimate {
public:
    explicit RunningEstimate(int channels = 1) : m_channels(channels) {}

    /// One more sample: values[c] for each channel.
    void add(std::span<const double> values) {
        const double n = double(++m_n);
        for (int c = 0; c < m_channels; ++c) {
            const double delta = values[std::size_t(c)] - m_mean[std::size_t(c)];
            m_mean[std::size_t(c)] += delta / n;
            m_m2[std::size_t(c)] += delta * (values[std::size_t(c)] - m_mean[std::size_t(c)]);
        }
    }

    /// The mean and the variance of the mean, s²/n with s² the unbiased sample variance
    /// (infinite below two samples).
    Estimate estimate() const {
        Estimate e;
        e.channels = m_channels;
        e.samples = m_n;
        for (int c = 0; c < m_channels; ++c) {
            e.mean[std::size_t(c)] = m_mean[std::size_t(c)];
            e.variance[std::size_t(c)] = m_n < 2 ? std::numeric_limits<double>::infinity()
                                                 : m_m2[std::size_t(c)] / double(m_n - 1) / double(m_n);
        }
        return e;
    }

private:
    int m_channels;
    std::uint64_t m_n = 0;
    std::array<double, Estimate::MaxChannels> m_mean{}, m_m2{};  // m2: Σ (f − mean)²
};

} // namespace effigi
