// integrator "adaptive" — adaptive (dynamic) stratification in rounds, after MISER
// (Press & Farrar 1990) and pbrt-style adaptive sampling, with honest error bars.
//
// Boxes (strata) partition the first D dimensions. The budget is spent in rounds of
// doubling size (n₀ = max(2m, N/64), 2n₀, …, the last taking the rest). In a round,
// stratum s (volume V_s) gets m = `min_samples` samples plus a share 0.5 V_s σ_s / Σ V σ
// + 0.5 V_s of the rest (Neyman allocation, σ_s the standard deviation of f over the
// samples s holds, half proportional so that a stratum whose samples missed a peak is
// still sampled), and estimates I_r = Σ V_s f̄_s, variance Σ V_s² s_s²/n_s, from its own
// samples. Between rounds the stratum whose halving most reduces Σ V σ (the Neyman
// variance; in practice the largest contributor) is halved along the dimension that
// reduces it most (ties: the longest side), judged from the samples it holds (≥ 8 per
// half), and so on, children included, up to n_{r+1} / (2m) strata. The estimate
// combines the rounds holding ≥ 1/8 of the samples (the last two or three) by their
// sizes. A round's strata and allocation depend only on earlier rounds, so estimate and
// error bar are unbiased; early rounds only guide (a peak they miss would dominate the
// error, unreported). MISER allocates from the samples it then uses: biased on peaks.
// With `rel_error` > 0, before each round from the fourth the call predicts that round's
// error, √Σ V_s² σ_s² / n_s over Σ_c f_c; if it is ≤ rel_error · |estimate so far| ≠ 0,
// that round is the last and the estimate that round alone: decided on earlier rounds
// only, so unbiased (stopping once the estimated error is small biases low on peaks:
// z = −4 in effigi-conform). A call then draws fewer samples than its budget; a renderer's
// film normalises each pixel by its samples' weights V_s n_r / n_s (IWeightedSampler; all
// rounds count there). That round's error bar rests on few samples per stratum: targets
// of 1–5 % cover 85–89 % on `step` (corner). Per-pixel targets cannot pay on an image
// (adaptive_pixels.hpp says why); mode "pixels" spreads a render pass over the pixels.
//
// D = min(dimension(), max_dimensions), or for integrands of open dimension (0: a pixel's
// path space) the fewest dimensions any sample of the first round drew. Strata are never
// narrower than 2^-20. Rounds, strata and χ²/dof reach an IIntegrationObserver integrand.
//
// Parameters:
//   rel_error       float (default 0: off, in [0, 1])   relative error target
//   min_samples     int (default 4, in [2, 4096])       samples per stratum and round
//   max_dimensions  int (default 8, in [1, 64])         dimensions that are stratified
//   mode            string (default strata)             strata | pixels (adaptive_pixels.hpp)
//   mean_share      float (default 0.5, in [0.1, 0.9])  pixels: mean share of the budget spent
//
// References: W. H. Press, G. R. Farrar, Computers in Physics 4(2), 1990 (MISER); J. Neyman,
// J. Royal Statistical Society 97(4), 1934; Pharr, Jakob, Humphreys, PBR 3rd ed., §7.1;
// D. Kirk, J. Arvo, SIGGRAPH 1991 (mode pixels).
#include "adaptive_pixels.hpp"
#include "adaptive_strata.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/iintegrator.hpp"
#include "effigi/interfaces/iintegrator_hooks.hpp"
#include "effigi/math/running_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>
#include <tuple>
#include <vector>

namespace effigi {
namespace {

constexpr double MinWidth = 1.0 / (1 << 20), SplitMin = 8, Defensive = 0.5;  // see above

class AdaptiveIntegrator final : public Implements<IIntegrator, IPixelAllocator> {
public:
    static Schema schema() {
        Schema s("integrator", "adaptive",
                 "Adaptive stratification in rounds (MISER-like), optional relative-error target; or "
                 "per-pixel adaptive sampling (mode pixels).");
        s.cite("W. H. Press, G. R. Farrar, Computers in Physics 4(2), 1990 (MISER); Neyman 1934; Kirk & Arvo 1991");
        s.real("rel_error", 0.0, "Stop once the relative standard error is below this (0: use the budget)")
            .range(0.0, 1.0);
        s.integer("min_samples", 4, "Samples every stratum gets in every round").range(2, 4096);
        s.integer("max_dimensions", 8, "How many leading dimensions are stratified").range(1, 64);
        s.string("mode", "strata",
                 "strata: stratify each integral; pixels: spread a render pass's samples over the pixels by their "
                 "relative variance (n ∝ σ/μ), plain Monte Carlo inside each")
            .oneOf({"strata", "pixels"});
        s.real("mean_share", 0.5, "Mode pixels: the share of the budget (spp) a pixel spends on average, none more "
                                  "than the budget (below 32 samples a pixel on average: uniform)")
            .range(0.1, 0.9);
        s.addConformance({"default", {}});
        s.addConformance({"min_samples 2", {{"min_samples", std::int64_t(2)}}});
        s.addConformance({"min_samples 1000", {{"min_samples", std::int64_t(1000)}}});
        s.addConformance({"max_dimensions 1", {{"max_dimensions", std::int64_t(1)}}});
        s.addConformance({"rel_error 0.003", {{"rel_error", 0.003}}});
        s.addConformance({"mode pixels", {{"mode", std::string("pixels")}}});
        return s;
    }

    explicit AdaptiveIntegrator(const Properties& p)
        : m_relError(p.getFloat("rel_error")), m_min(std::uint64_t(p.getInt("min_samples"))),
          m_maxDims(int(p.getInt("max_dimensions"))), m_pixels(p.getString("mode") == "pixels"),
          m_allocation(p.getFloat("mean_share")) {
        if (m_pixels && m_relError > 0.0)
            failAt(p.whereOf("rel_error"), "integrator 'adaptive': rel_error applies to mode 'strata' only");
    }

    Plan plan(std::uint64_t budget) const override { return m_pixels ? m_allocation.plan(budget) : Plan{}; }
    void allocate(std::span<const PixelPilot> pilots, int width, int height, std::uint64_t budget,
                  std::vector<std::uint64_t>& counts) const override {
        m_allocation.allocate(pilots, width, height, budget, counts);
    }

    Estimate integrate(IFunction& f, ISampler& sampler, std::uint64_t firstIndex, std::uint64_t count) const override {
        const int channels = f.channels();
        if (channels < 1 || channels > Estimate::MaxChannels)
            fail("integrator 'adaptive': function '{}' has {} channels; 1 to {} are supported", f.typeName(),
                 channels, Estimate::MaxChannels);
        Estimate e;
        e.channels = channels;
        if (count == 0) return e;
        IIntegrationObserver* observer = query<IIntegrationObserver>(&f);
        if (m_pixels) {
            e = PixelAllocation::integrate(f, sampler, firstIndex, count);
            if (observer) {
                IntegrationReport report;
                report.stages = {e};
                observer->integrated(report);
            }
            return e;
        }
        std::vector<std::uint64_t> sizes{std::min(count, std::max(2 * m_min, (count + 63) / 64))};
        for (std::uint64_t rest = count - sizes[0], next = 2 * sizes[0]; rest > 0; next *= 2) {
            const std::uint64_t n = rest > 2 * next ? next : rest;
            sizes.push_back(n), rest -= n;
        }
        // Recorded dimensions; open dimension: up to max_dimensions, split only what all drew.
        const int dims = f.dimension() > 0 ? std::min(f.dimension(), m_maxDims) : m_maxDims;
        int active = dims;
        std::vector<Stratum> strata{Stratum{std::vector<double>(std::size_t(dims), 0.0),
                                            std::vector<double>(std::size_t(dims), 1.0), 1.0, {}, {}, 0}};
        StratumSampler place(sampler, dims);
        std::vector<Estimate> stages;
        std::array<double, Estimate::MaxChannels> value{};
        std::uint64_t index = firstIndex, used = 0;
        std::size_t first = 0;  // the first round in the estimate
        bool stop = false;      // rel_error met: this round is the last and the estimate alone
        for (std::size_t r = 0; r < sizes.size() && !stop; ++r) {
            const std::uint64_t n = sizes[r];
            allocate(strata, n);
            if (m_relError > 0.0 && r >= 3 && r + 1 < sizes.size()) {
                double target = 0.0, predicted = 0.0;  // of Σ_c mean_c, from earlier rounds only
                for (int c = 0; c < channels; ++c) target += e.mean[c];
                for (const Stratum& s : strata) predicted += s.volume * s.volume * s.seen.variance() / double(s.alloc);
                stop = target != 0.0 && std::sqrt(predicted) <= m_relError * std::abs(target);
            }
            Estimate round;
            round.channels = channels, round.samples = n;
            int fewest = std::numeric_limits<int>::max();
            for (Stratum& s : strata) {
                place.place(&s, s.volume * double(n) / double(s.alloc));
                RunningEstimate running(channels);
                for (std::uint64_t i = 0; i < s.alloc; ++i) {
                    place.startSample(index++);
                    value.fill(0.0);
                    f.eval(place, std::span<double>(value.data(), std::size_t(channels)));
                    running.add(value);
                    const double g = std::accumulate(value.begin(), value.begin() + channels, 0.0);
                    s.seen.add(g);
                    fewest = std::min(fewest, place.drawn());
                    for (int j = 0; j < dims; ++j) s.points.push_back(j < place.drawn() ? place.x(j) : s.lower[j]);
                    s.points.push_back(g);
                }
                const Estimate se = running.estimate();
                for (int c = 0; c < channels; ++c) {
                    round.mean[c] += s.volume * se.mean[c];
                    round.variance[c] += s.volume * s.volume * se.variance[c];
                }
            }
            stages.push_back(round);
            used += n;
            if (r == 0 && f.dimension() <= 0) active = std::min(fewest, dims);  // what every sample drew
            if (stop) first = r, e = round;
            else e = combine(stages, used, channels, first);
            if (!stop && r + 1 < sizes.size())
                split(strata, dims, active, std::max<std::uint64_t>(1, sizes[r + 1] / (2 * m_min)));
        }
        e.samples = used;

        if (!observer) return e;
        IntegrationReport report{stages, int(first), stageChi2PerDof(stages, first, channels), {}, {}};
        for (const Stratum& s : strata)
            report.strata.push_back({s.lower, s.upper, std::uint64_t(s.seen.n), s.seen.sigma()});
        observer->integrated(report);
        return e;
    }

private:
    /// The rounds holding at least 1/8 of the `used` samples, weighted by their sizes.
    static Estimate combine(const std::vector<Estimate>& stages, std::uint64_t used, int channels, std::size_t& first) {
        first = 0;
        while (8 * stages[first].samples < used) ++first;
        Estimate e;
        e.channels = channels;
        double kept = 0.0;
        for (std::size_t k = first; k < stages.size(); ++k) kept += double(stages[k].samples);
        for (std::size_t k = first; k < stages.size(); ++k)
            for (int c = 0; c < channels; ++c) {
                const double share = double(stages[k].samples) / kept;
                e.mean[c] += share * stages[k].mean[c], e.variance[c] += share * share * stages[k].variance[c];
            }
        return e;
    }

    /// min_samples each, the rest by 0.5 V σ / Σ V σ + 0.5 V (cumulative rounding).
    void allocate(std::vector<Stratum>& strata, std::uint64_t n) const {
        if (strata.size() == 1) return void(strata[0].alloc = n);
        const std::uint64_t free = n - strata.size() * m_min;  // split() keeps this >= 0
        double spread = 0.0, share = 0.0;
        for (const Stratum& s : strata) spread += s.volume * s.seen.sigma();
        std::uint64_t given = 0;
        for (Stratum& s : strata) {
            const double neyman = spread > 0.0 ? s.volume * s.seen.sigma() / spread : s.volume;
            share += (1.0 - Defensive) * neyman + Defensive * s.volume;
            std::uint64_t upto = std::clamp<std::uint64_t>(std::llround(share * double(free)), given, free);
            if (&s == &strata.back()) upto = free;
            s.alloc = m_min + (upto - given), given = upto;
        }
    }

    /// The split of s that most reduces V σ (ties: the longest side): gain and dimension.
    std::pair<double, int> bestSplit(const Stratum& s, int dims, int active) const {
        std::pair<double, int> best{0.0, -1};
        double bestWidth = 0.0;
        const std::size_t stride = std::size_t(dims) + 1;
        for (int j = 0; j < active; ++j) {
            const double width = s.upper[j] - s.lower[j], mid = s.lower[j] + 0.5 * width;
            if (width < 2 * MinWidth) continue;
            Moments lo, hi;
            for (std::size_t i = 0; i < s.points.size(); i += stride)
                (s.points[i + std::size_t(j)] < mid ? lo : hi).add(s.points[i + stride - 1]);
            if (lo.n < SplitMin || hi.n < SplitMin) continue;
            const double gain = s.volume * (s.seen.sigma() - 0.5 * (lo.sigma() + hi.sigma()));
            if (gain > best.first || (gain == best.first && gain > 0.0 && width > bestWidth))
                best = {gain, j}, bestWidth = width;
        }
        return best;
    }

    /// Halve the strata whose split most reduces Σ V σ, children again, until `limit`.
    void split(std::vector<Stratum>& strata, int dims, int active, std::uint64_t limit) const {
        std::priority_queue<std::tuple<double, std::size_t, int>> heap;  // gain, stratum, dimension
        auto consider = [&](std::size_t i) {
            const auto [gain, dim] = bestSplit(strata[i], dims, active);
            if (dim >= 0) heap.emplace(gain, i, dim);
        };
        for (std::size_t i = 0; i < strata.size(); ++i) consider(i);
        const std::size_t stride = std::size_t(dims) + 1;
        while (!heap.empty() && strata.size() < limit) {
            const auto [gain, i, dim] = heap.top();
            heap.pop();
            Stratum upper;
            Stratum& s = strata[i];
            const std::size_t j = std::size_t(dim);
            const double mid = 0.5 * (s.lower[j] + s.upper[j]);
            upper.lower = s.lower, upper.upper = s.upper;
            s.upper[j] = upper.lower[j] = mid;
            s.volume = upper.volume = 0.5 * s.volume;
            std::vector<double> points;
            points.swap(s.points);
            s.seen = Moments{};
            for (auto p = points.begin(); p != points.end(); p += std::ptrdiff_t(stride)) {
                Stratum& to = p[std::ptrdiff_t(j)] < mid ? s : upper;
                to.points.insert(to.points.end(), p, p + std::ptrdiff_t(stride));
                to.seen.add(p[std::ptrdiff_t(stride) - 1]);
            }
            strata.push_back(std::move(upper));
            consider(i), consider(strata.size() - 1);
        }
    }

    double m_relError;
    std::uint64_t m_min;
    int m_maxDims;
    bool m_pixels;
    PixelAllocation m_allocation;
};

} // namespace
} // namespace effigi

EFFIGI_EXPORT_COMPONENT(effigi::AdaptiveIntegrator)
