// joinRanks() (render_ranks.hpp): on its own, a process renders alone; under mpirun it
// loads the MPI module lib/effigi/ranks-mpi.so (render_mpi.cpp) and joins the job, so
// that MPI's libraries are loaded by no render that does not use them (as image-oiio.so
// and preview.so). A build without MPI has no module: a job of several ranks is refused.
#include "render_ranks.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/module.hpp"

#include <dlfcn.h>

namespace effigi::app {

std::unique_ptr<Ranks> joinRanks() {
    if (launchedRanks() == 0) return nullptr;  // started on its own: no MPI
    const std::filesystem::path module = libraryDirectory() / "effigi" / ranks_module::ModuleFile;
    void* handle = dlopen(module.c_str(), RTLD_NOW | RTLD_GLOBAL);  // kept loaded: the ranks' code is in it
    if (!handle) {
        if (launchedRanks() > 1)
            fail("effigi was built without MPI (CMake option EFFIGI_MPI, Debian package libopenmpi-dev; {}): under "
                 "mpirun each of the {} ranks would render the whole image on its own",
                 dlerror(), launchedRanks());
        return nullptr;  // mpirun -np 1: one process, as on its own
    }
    const auto join = reinterpret_cast<ranks_module::Join>(dlsym(handle, ranks_module::JoinSymbol));
    if (!join) fail("{} has no entry point {}", module.string(), ranks_module::JoinSymbol);
    return std::unique_ptr<Ranks>(join());
}

} // namespace effigi::app
