#include "render_checkpoint.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/input.hpp"
#include "effigi/interfaces/iaccumulator.hpp"
#include "effigi/interfaces/ifilm.hpp"

#include <cmath>

namespace effigi::app {

namespace {

IAccumulator& accumulator(IComponent& c) {
    IAccumulator* a = query<IAccumulator>(&c);
    if (!a) fail("{} keeps no running sums that a checkpoint could hold", c.typeName());
    return *a;
}

} // namespace

double parseDuration(const std::string& opt, const std::string& value) {
    static const std::pair<const char*, double> Units[] = {
        {"ms", 1e-3}, {"s", 1.0}, {"m", 60.0}, {"h", 3600.0}, {"", 1.0}};
    for (const auto& [unit, scale] : Units) {
        const std::size_t n = std::char_traits<char>::length(unit);
        if (value.size() <= n || value.compare(value.size() - n, n, unit) != 0) continue;
        try {
            std::size_t used = 0;
            const std::string number = value.substr(0, value.size() - n);
            const double v = std::stod(number, &used);
            if (used == number.size() && v > 0.0 && std::isfinite(v)) return v * scale;
        } catch (const std::exception&) {
        }
        break;  // a unit matched but not a number before it
    }
    fail("option {} expects a duration such as 60s, 500ms, 2m or 1h, got '{}'", opt, value);
}

std::vector<double> readResume(const std::filesystem::path& dir, const Scene& scene, const CheckpointBase& base) {
    Checkpoint c = readCheckpoint(dir);
    if (c.identity != base.identity)
        fail("cannot resume from {}: its checkpoint was written for another scene or other options ({}, with "
             "other -D values or --seed), not for {}",
             dir.string(), excerpt(c.scene, 200), base.scene);
    accumulator(scene.camera().film()).loadSums(c.film);
    accumulator(scene.renderer()).loadSums(c.renderer);
    // spp, seconds, samples, rejected, the budget, then each rank's sample count.
    std::vector<double> progress = {double(c.report.spp), c.report.seconds, double(c.report.stats.samples),
                                    double(c.report.stats.rejectedSamples), double(c.spp), c.timeBudget,
                                    c.targetRelMSE};
    for (std::uint64_t n : c.processSpp) progress.push_back(double(n));
    return progress;
}

void applyResume(std::vector<double> progress, CheckpointBase& base, ProgressiveOptions& prog, Ranks* ranks) {
    if (ranks) ranks->broadcast(progress);
    PassReport& r = prog.resumed;
    r.spp = std::uint64_t(progress[0]);
    r.seconds = r.stats.seconds = progress[1];
    r.stats.samples = std::uint64_t(progress[2]), r.stats.rejectedSamples = std::uint64_t(progress[3]);
    const std::size_t rank = ranks ? std::size_t(ranks->rank()) : 0;
    // A rank the checkpoint did not have starts its own seed's sequence at 0.
    r.processSpp = 7 + rank < progress.size() ? std::uint64_t(progress[7 + rank]) : 0;
    prog.filmResumed = !ranks || ranks->root();
    if (base.spp == 0 && base.timeBudget <= 0.0 && base.targetRelMSE <= 0.0) {
        base.spp = std::uint64_t(progress[4]), base.timeBudget = progress[5], base.targetRelMSE = progress[6];
        prog.spp = base.spp, prog.timeBudget = base.timeBudget, prog.targetRelMSE = base.targetRelMSE;
    }
}

std::uint64_t CheckpointWriter::write(const Scene& scene, const PassReport& report, Ranks* ranks) {
    m_last = report.seconds;
    const bool root = ranks ? ranks->gather(true) : true;
    std::vector<std::uint64_t> counts = ranks ? ranks->gatherValues(report.processSpp)
                                              : std::vector<std::uint64_t>{report.processSpp};
    if (!root) return 0;
    Checkpoint c;
    c.identity = m_base.identity, c.scene = m_base.scene;
    c.spp = m_base.spp, c.timeBudget = m_base.timeBudget, c.targetRelMSE = m_base.targetRelMSE;
    c.report = report;
    c.processSpp = std::move(counts);
    c.film = accumulator(scene.camera().film()).saveSums();
    c.renderer = accumulator(scene.renderer()).saveSums();
    return writeCheckpoint(m_dir, c);
}

} // namespace effigi::app
