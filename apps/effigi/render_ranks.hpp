#pragma once
// The ranks of an MPI job, `mpirun -np N effigi render scene.xml ...` (render_mpi.cpp, in
// builds with EFFIGI_MPI): every rank loads the scene and renders its share of every
// progressive pass with a seed of its own; the films' and renderers' running sums are
// reduced into rank 0, which alone draws progress, writes checkpoints and the image.
#include "effigi/render/progressive.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace effigi::app {

class Ranks : public PassSharing {
public:
    virtual int rank() const = 0;
    bool root() const { return rank() == 0; }
    /// Rendering threads of each rank unless -t says: the cores mpirun bound it to, else
    /// its node's cores over its node's ranks.
    virtual int threadsPerRank() const = 0;
    /// Stride between the ranks' seeds: rank r renders with seed + r · SeedStride, so
    /// rank 0's samples are a single process's and no rank repeats another's.
    static constexpr std::uint64_t SeedStride = 0x9e3779b97f4a7c15ull;
    /// The scene whose film and renderer sums gather() pools (IAccumulator, both).
    virtual void bind(const Scene& scene) = 0;
    /// Collective, once every rank has parsed and loaded: `error` is this rank's failure
    /// ("" if none). False when any rank failed, the lowest failing rank having printed
    /// its error (one line; every rank should then end with exit code 1).
    virtual bool agree(const std::string& error) = 0;
    /// Collective: every rank's value in rank order, in the root (empty elsewhere).
    virtual std::vector<std::uint64_t> gatherValues(std::uint64_t value) = 0;
    /// Collective: the root's values, everywhere.
    virtual void broadcast(std::vector<double>& values) = 0;
    /// What the reductions of gather() cost: their number, the bytes this rank sent in
    /// each of the last one, and the seconds spent in all of them.
    struct Traffic {
        int reductions = 0;
        double lastBytes = 0.0, seconds = 0.0;
    };
    virtual Traffic traffic() const = 0;
    /// Print "error: rank r: what" and end the whole job (exit code 1): a failure after
    /// the ranks have parted would otherwise leave the others waiting forever.
    [[noreturn]] virtual void abort(const std::string& what) = 0;
};

/// The ranks of the MPI job this process was launched in by mpirun (MPI initialised;
/// finalised when the object goes), or null when it was started on its own. The MPI side
/// (render_mpi.cpp) is the module lib/effigi/ranks-mpi.so, loaded here under mpirun only
/// (render_ranks.cpp); without it (a build without MPI) a job of several ranks is refused,
/// since every rank would render and write the whole image.
std::unique_ptr<Ranks> joinRanks();

namespace ranks_module {
inline constexpr const char* ModuleFile = "ranks-mpi.so";
inline constexpr const char* JoinSymbol = "effigi_mpi_join_ranks";
using Join = Ranks* (*)();
} // namespace ranks_module

/// The number of processes of the job this one was launched in by a process manager
/// (Open MPI's mpirun, MPICH's hydra; 1 when only PMIx says so, with no size), 0 when it
/// was started on its own.
inline int launchedRanks() {
    for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
        if (const char* v = std::getenv(name)) return std::max(1, std::atoi(v));
    return std::getenv("PMIX_RANK") ? 1 : 0;
}

} // namespace effigi::app
