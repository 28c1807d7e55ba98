#pragma once
// IAccumulator — a component whose state after a render is a set of running sums: the
// film's filter-weighted sums, a renderer's per-pixel error statistics. Its sums can be
// saved (a checkpoint, effigi/render/checkpoint.hpp), put back (resuming a killed render)
// and pooled with another process's over the same scene by adding them element by
// element (MPI_Reduce with MPI_SUM, apps/effigi/render_mpi.cpp): whatever it keeps must
// therefore be additive — sums, never means.
//
// A renderer that implements it declares that its sums and the film's are all it carries
// from pass to pass, so that a render split into passes may be continued in another
// process, or spread over several, and give the same image (in distribution). Renderers
// with more state (SPPM's per-pixel radii, an irradiance cache, Metropolis chains) do not
// implement it; `effigi render --checkpoint/--resume` and multi-rank rendering refuse them.
#include "effigi/core/component.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace effigi {

/// The running sums of one accumulator. `layout` says what the arrays hold (sizes,
/// channel names) and must match for two sums to be added or for a load.
struct AccumulatorSums {
    std::string layout;
    std::vector<float> floats;    ///< added as floats (the film's sums)
    std::vector<double> doubles;  ///< added as doubles (statistics that need the precision)

    std::size_t bytes() const { return floats.size() * sizeof(float) + doubles.size() * sizeof(double); }
};

class IAccumulator : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IAccumulator");
    static constexpr const char* Tag = "accumulator";

    /// The sums so far (empty arrays and layout "" where nothing has been accumulated).
    virtual AccumulatorSums saveSums() const = 0;
    /// Replace the sums by `sums` (from saveSums() of an equal component, or pooled sums of
    /// several). Throws effigi::Error when the layout does not fit this component.
    virtual void loadSums(const AccumulatorSums& sums) = 0;
};

} // namespace effigi
