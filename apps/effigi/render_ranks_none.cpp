// joinRanks() of a build without MPI (EFFIGI_MPI off): a process started on its own renders
// alone; one started by mpirun refuses, since each rank would render the whole image.
#include "render_ranks.hpp"

#include "effigi/core/error.hpp"

namespace effigi::app {

std::unique_ptr<Ranks> joinRanks() {
    if (launchedRanks() > 1)
        fail("effigi was built without MPI (CMake option EFFIGI_MPI, Debian package libopenmpi-dev): under mpirun "
             "each of the {} ranks would render the whole image on its own", launchedRanks());
    return nullptr;
}

} // namespace effigi::app
