// effigi — the command-line front end. Subcommands live in their own files; this one
// only dispatches and turns errors into one line and exit code 1.
#include "commands.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/module.hpp"
#include "effigi/core/worker_threads.hpp"

#include <cstdio>
#include <cstring>
#include <exception>

namespace {

void usage() {
    std::fprintf(stderr,
                 "usage: effigi <command> [options]\n"
                 "  render scene.xml [-o out.exr] [-D name=value]... [-t threads] [-v] [--seed N] [--no-progress]\n"
                 "         [--time seconds] [--spp N] [--target-relmse e] [--reference]   progressive\n"
                 "         [--checkpoint dir [--checkpoint-every 60s]] [--resume dir]   continue a killed render\n"
                 "         [--preview [port]]   watch it converge on http://127.0.0.1:port/ (8080; 0: any free port)\n"
                 "         (mpirun -np N effigi render ...: N ranks share the samples; docs/cluster.md)\n"
                 "         [--frames A:B]   a sequence: $frame = A..B, -o out_{frame:04}.exr (ranks share the frames)\n"
                 "         [--dry-run]   load the scene (every component created), render nothing\n"
                 "         [--stats]     rays per sample and per second by kind; time in tracing, shading, film\n"
                 "  converge scene.xml [--reference ref.exr] [--renderer a,b] [--variant \"name: k=v ...\"]...\n"
                 "         [-D name=value]... [--time seconds per configuration] [--spp N] [--out dir]\n"
                 "  list [tag]                 components known, by tag\n"
                 "  info tag/name              parameters of one component\n"
                 "  info --markdown            reference of every component (docs/components.md)\n"
                 "  convert in.exr out.png|out.exr [--colorspace srgb|rec2020|acescg] [--exposure e]\n"
                 "          [--tonemap none|reinhard|filmic] [--reconstruction linear|box]   spectral EXR -> RGB\n"
                 "  version\n");
}

} // namespace

int main(int argc, char** argv) {
    effigi::WorkerThreadsJoin join;  // workers joined before exit (LeakSanitizer)
    if (argc < 2 || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "help")) {
        usage();
        return argc < 2 ? 1 : 0;
    }
    std::vector<std::string> args(argv + 2, argv + argc);
    std::string cmd = argv[1];
    try {
        if (cmd == "render") return effigi::app::render(args);
        if (cmd == "list") return effigi::app::list(args);
        if (cmd == "info") return effigi::app::info(args);
        if (cmd == "convert") return effigi::app::convert(args);
        if (cmd == "converge") return effigi::app::converge(args);
        if (cmd == "version") {
            std::printf("effigi %s\n", effigi::version());
            return 0;
        }
        std::fprintf(stderr, "effigi: unknown command '%s'\n", cmd.c_str());
        usage();
        return 1;
    } catch (const effigi::Error& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "error: %s\n", e.what());
        return 1;
    }
}
