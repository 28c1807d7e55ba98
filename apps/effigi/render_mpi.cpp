// The ranks of an MPI job (EFFIGI_MPI builds; Open MPI from Debian), in the module
// lib/effigi/ranks-mpi.so that joinRanks() (render_ranks.cpp) loads only under mpirun, so
// that MPI's libraries (libmpi, Open RTE/PAL, hwloc, libevent) load in no other process.
// A rank renders its
// share of every progressive pass, and the ranks' running sums (IAccumulator: the film's
// filter-weighted sums, the renderer's per-pixel error statistics) are added into rank 0
// with MPI_Reduce, everyone else's cleared, whenever the job's image or error estimate
// is needed (a noise target, a checkpoint, the end). Sums and not images are reduced, so
// the result is the film a single process would have accumulated from all the samples.
//
// Why passes and not tiles: sample passes keep every rank busy to the end of a time
// budget with no scheduling (each renders the whole image, a share of the samples), and
// the error estimate and checkpoints are those of a single process; the price is one
// reduction of the whole film per rank instead of each rank sending its tiles, a few
// MB that take milliseconds against renders of seconds to hours (bench/RESULTS.md).
#include "render_ranks.hpp"

#include "effigi/core/error.hpp"
#include "effigi/interfaces/iaccumulator.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/render/scene.hpp"

#include <mpi.h>
#include <sched.h>

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdio>
#include <thread>

namespace effigi::app {

namespace {

/// MPI counts are ints: large films go in chunks.
constexpr std::size_t Chunk = std::size_t(1) << 28;

template <typename T> MPI_Datatype mpiType();
template <> MPI_Datatype mpiType<float>() { return MPI_FLOAT; }
template <> MPI_Datatype mpiType<double>() { return MPI_DOUBLE; }

class MpiRanks final : public Ranks {
public:
    MpiRanks() {
        int provided = 0;
        MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);  // only the main thread calls MPI
        MPI_Comm_rank(MPI_COMM_WORLD, &m_rank);
        MPI_Comm_size(MPI_COMM_WORLD, &m_size);
        MPI_Comm node;
        MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, m_rank, MPI_INFO_NULL, &node);
        MPI_Comm_size(node, &m_nodeRanks);
        MPI_Comm_free(&node);
    }
    ~MpiRanks() override { MPI_Finalize(); }

    int rank() const override { return m_rank; }
    int threadsPerRank() const override {
        // mpirun binds a rank to cores (Open MPI: to one core when np <= 2): then those;
        // else the node's cores shared among its ranks.
        const int cores = std::max(1, int(std::thread::hardware_concurrency()));
        cpu_set_t set;
        CPU_ZERO(&set);
        const int bound = ::sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : cores;
        return bound > 0 && bound < cores ? bound : std::max(1, cores / std::max(1, m_nodeRanks));
    }
    void bind(const Scene& scene) override {
        m_film = query<IAccumulator>(&scene.camera().film());
        m_renderer = query<IAccumulator>(&scene.renderer());
    }

    std::uint64_t processes() const override { return std::uint64_t(m_size); }
    std::uint64_t share(std::uint64_t spp) const override {
        const std::uint64_t n = std::uint64_t(m_size), r = std::uint64_t(m_rank);
        return spp / n + (r < spp % n ? 1 : 0);
    }

    void combine(RenderStats& s, double& seconds) override {
        const WorkStats& w = s.work;
        double sum[13] = {double(s.samples), double(s.rejectedSamples), double(w.rays[0]), double(w.rays[1]),
                          double(w.rays[2]), w.traceSeconds[0], w.traceSeconds[1], w.traceSeconds[2],
                          w.cameraSeconds, w.shadeSeconds, w.filmSeconds, w.kept ? 1.0 : 0.0, 0.0};
        double max[2] = {seconds, s.interrupted ? 1.0 : 0.0};
        MPI_Allreduce(MPI_IN_PLACE, sum, 13, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
        MPI_Allreduce(MPI_IN_PLACE, max, 2, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
        s.samples = std::uint64_t(sum[0]), s.rejectedSamples = std::uint64_t(sum[1]);
        for (int k = 0; k < WorkStats::RayKinds; ++k)
            s.work.rays[k] = std::uint64_t(sum[2 + k]), s.work.traceSeconds[k] = sum[5 + k];
        s.work.cameraSeconds = sum[8], s.work.shadeSeconds = sum[9], s.work.filmSeconds = sum[10];
        s.work.kept = sum[11] > 0.0;
        seconds = max[0];
        s.interrupted = max[1] > 0.0;
    }

    bool gather(bool errorStatistics) override {
        const auto start = std::chrono::steady_clock::now();
        double bytes = reduce(*m_film);
        if (errorStatistics) bytes += reduce(*m_renderer);
        m_traffic.reductions += 1;
        m_traffic.lastBytes = bytes;
        m_traffic.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return root();
    }

    double fromRoot(double value) override {
        MPI_Bcast(&value, 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
        return value;
    }

    bool agree(const std::string& error) override {
        int failing = error.empty() ? INT_MAX : m_rank;
        MPI_Allreduce(MPI_IN_PLACE, &failing, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
        if (failing == INT_MAX) return true;
        // Printed here, as main() would: a rank that has failed ends at once and mpirun
        // then kills the rest, which would not get to unwind to main().
        if (failing == m_rank) std::fprintf(stderr, "error: %s\n", error.c_str()), std::fflush(stderr);
        MPI_Barrier(MPI_COMM_WORLD);
        return false;
    }

    std::vector<std::uint64_t> gatherValues(std::uint64_t value) override {
        std::vector<std::uint64_t> all(root() ? std::size_t(m_size) : 0);
        MPI_Gather(&value, 1, MPI_UINT64_T, all.data(), 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
        return all;
    }

    void broadcast(std::vector<double>& values) override {
        std::uint64_t n = values.size();
        MPI_Bcast(&n, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD);
        values.resize(n);
        bcastChunks(values.data(), n);
    }

    Traffic traffic() const override { return m_traffic; }

    [[noreturn]] void abort(const std::string& what) override {
        std::fprintf(stderr, "error: rank %d: %s\n", m_rank, what.c_str());
        std::fflush(stderr);
        MPI_Abort(MPI_COMM_WORLD, 1);
        std::exit(1);  // MPI_Abort does not return
    }

private:
    /// Add every rank's sums of `a` into the root's and clear the others'; the bytes this
    /// rank sent. A rank that has rendered nothing yet (a pass smaller than the job)
    /// sends zeros of the root's size.
    double reduce(IAccumulator& a) {
        AccumulatorSums s = a.saveSums();
        std::uint64_t counts[2] = {s.floats.size(), s.doubles.size()};
        MPI_Bcast(counts, 2, MPI_UINT64_T, 0, MPI_COMM_WORLD);
        const bool empty = s.layout.empty();
        if (empty) s.floats.assign(counts[0], 0.f), s.doubles.assign(counts[1], 0.0);
        if (s.floats.size() != counts[0] || s.doubles.size() != counts[1])
            abort(fmt::format("the running sums ({} + {} values) differ from rank 0's ({} + {})", s.floats.size(),
                              s.doubles.size(), counts[0], counts[1]));
        reduceChunks(s.floats);
        reduceChunks(s.doubles);
        if (root()) {
            if (!empty) a.loadSums(s);
        } else if (!empty) {
            std::fill(s.floats.begin(), s.floats.end(), 0.f);
            std::fill(s.doubles.begin(), s.doubles.end(), 0.0);
            a.loadSums(s);
        }
        return double(s.bytes());
    }

    template <typename T> void reduceChunks(std::vector<T>& v) {
        for (std::size_t at = 0; at < v.size(); at += Chunk) {
            const int n = int(std::min(Chunk, v.size() - at));
            T* p = v.data() + at;
            MPI_Reduce(root() ? MPI_IN_PLACE : p, p, n, mpiType<T>(), MPI_SUM, 0, MPI_COMM_WORLD);
        }
    }
    void bcastChunks(double* p, std::size_t size) {
        for (std::size_t at = 0; at < size; at += Chunk)
            MPI_Bcast(p + at, int(std::min(Chunk, size - at)), MPI_DOUBLE, 0, MPI_COMM_WORLD);
    }

    int m_rank = 0, m_size = 1, m_nodeRanks = 1;
    IAccumulator* m_film = nullptr;
    IAccumulator* m_renderer = nullptr;
    Traffic m_traffic;
};

} // namespace

} // namespace effigi::app

/// The module's entry point (render_ranks.hpp, ranks_module): MPI initialised.
extern "C" __attribute__((visibility("default"))) effigi::app::Ranks* effigi_mpi_join_ranks() {
    return new effigi::app::MpiRanks();
}
