// The tests' main(): Catch2's, with oneTBB's workers joined before exit (see
// effigi/core/worker_threads.hpp: LeakSanitizer's exit check in the asan preset).
#define CATCH_CONFIG_RUNNER
#include "effigi/core/worker_threads.hpp"

#include <catch2/catch.hpp>

int main(int argc, char* argv[]) {
    effigi::WorkerThreadsJoin join;
    return Catch::Session().run(argc, argv);
}
