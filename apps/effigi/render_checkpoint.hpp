#pragma once
// effigi render --checkpoint DIR [--checkpoint-every T] and --resume DIR: when to write a
// checkpoint (effigi/render/checkpoint.hpp), what goes into it, and how a resumed render
// picks up its progress and sums. Under MPI the writes and the resume are collective:
// rank 0 writes the reduced sums and reads the checkpoint; every rank learns its progress.
#include "render_ranks.hpp"

#include "effigi/render/checkpoint.hpp"
#include "effigi/render/scene.hpp"

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace effigi::app {

/// "60s", "500ms", "2m", "1h" or plain seconds (> 0); an error naming `opt` otherwise.
double parseDuration(const std::string& opt, const std::string& value);

/// The budget and the identity a checkpoint records.
struct CheckpointBase {
    std::uint64_t identity = 0;
    std::string scene;
    std::uint64_t spp = 0;
    double timeBudget = 0.0, targetRelMSE = 0.0;
};

/// Resuming from `dir`, in the root (or the only process): read the checkpoint, refuse
/// one written for another scene or options, load its sums into the scene's film and
/// renderer. Returns the progress the ranks need (see applyResume).
std::vector<double> readResume(const std::filesystem::path& dir, const Scene& scene, const CheckpointBase& base);

/// Collective under MPI: the root's `progress` (from readResume) to every rank, into
/// `prog`: the job's report and the rank's own first sample index. A budget of `base`
/// left at 0 everywhere takes the checkpoint's.
void applyResume(std::vector<double> progress, CheckpointBase& base, ProgressiveOptions& prog, Ranks* ranks);

/// Writes the checkpoints of one render into its directory.
class CheckpointWriter {
public:
    CheckpointWriter(std::filesystem::path dir, double every, CheckpointBase base, const PassReport& start)
        : m_dir(std::move(dir)), m_every(every), m_base(std::move(base)), m_last(start.seconds),
          m_previous(start.seconds) {}

    /// Whether a checkpoint is due after this pass: whether waiting for the next one
    /// (up to twice this one: passes double, and are cut to the interval) would leave
    /// more than the interval since the last checkpoint. The same answer in every rank:
    /// the job's time decides.
    bool due(const PassReport& report) {
        const double pass = report.seconds - m_previous;
        m_previous = report.seconds;
        return report.seconds - m_last + std::min(2.0 * pass, m_every) > m_every;
    }
    /// Pool the sums (collective under MPI) and write them from the root; returns the
    /// bytes written (0 outside the root).
    std::uint64_t write(const Scene& scene, const PassReport& report, Ranks* ranks);

private:
    std::filesystem::path m_dir;
    double m_every;
    CheckpointBase m_base;
    double m_last;      // job seconds at the last checkpoint
    double m_previous;  // job seconds after the previous pass
};

} // namespace effigi::app
