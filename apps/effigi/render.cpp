// effigi render: load a scene, render it with its renderer, write the film.
#include "commands.hpp"
#include "output_check.hpp"

#include "effigi/core/log.hpp"
#include "effigi/core/module.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/isampler.hpp"
#include "effigi/render/progressive.hpp"
#include "effigi/xml/loader.hpp"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <sys/resource.h>

#include "spectral_exr.hpp"  // components/film: the name of the spectral EXR beside the output

namespace effigi::app {

namespace {

std::atomic<bool> g_stop{false};
extern "C" void onSigint(int) { g_stop.store(true); }

std::string needValue(const std::vector<std::string>& args, std::size_t& i) {
    if (i + 1 >= args.size()) fail("option {} needs a value", args[i]);
    return args[++i];
}

long parseLong(const std::string& opt, const std::string& v) {
    try {
        std::size_t used = 0;
        long r = std::stol(v, &used);
        if (used == v.size()) return r;
    } catch (const std::exception&) {
    }
    fail("option {} expects an integer, got '{}'", opt, v);
}

double parseDouble(const std::string& opt, const std::string& v) {
    try {
        std::size_t used = 0;
        double r = std::stod(v, &used);
        if (used == v.size() && r > 0.0 && std::isfinite(r)) return r;
    } catch (const std::exception&) {
    }
    fail("option {} expects a positive number, got '{}'", opt, v);
}

double peakMemoryMiB() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return double(ru.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

/// --stats: rays per sample and per second by kind, and where the threads' time went.
void printWorkStats(const RenderStats& stats) {
    const WorkStats& w = stats.work;
    if (!w.kept || stats.samples == 0) {
        std::printf("stats: renderer keeps no ray counts (path keeps them in its wavefront mode)\n");
        return;
    }
    const char* names[WorkStats::RayKinds] = {"camera", "extension", "shadow"};
    const double samples = double(stats.samples);
    double trace = 0, rays = 0;
    for (int k = 0; k < WorkStats::RayKinds; ++k) trace += w.traceSeconds[k], rays += double(w.rays[k]);
    const double total = trace + w.cameraSeconds + w.shadeSeconds + w.filmSeconds;
    auto share = [&](double s) { return total > 0 ? 100.0 * s / total : 0.0; };
    std::printf("rays per sample: %.2f (", rays / samples);
    for (int k = 0; k < WorkStats::RayKinds; ++k)
        std::printf("%s%s %.2f", k ? ", " : "", names[k], double(w.rays[k]) / samples);
    std::printf(")\nrays/s per thread in batch calls: ");
    for (int k = 0; k < WorkStats::RayKinds; ++k)
        std::printf("%s%s %.1f M", k ? ", " : "", names[k],
                    w.traceSeconds[k] > 0 ? double(w.rays[k]) / w.traceSeconds[k] * 1e-6 : 0.0);
    std::printf("\ntime (%.2f thread-s): tracing %.0f %% (camera %.0f, extension %.0f, shadow %.0f), "
                "shading %.0f %%, camera samples %.0f %%, film %.0f %%\n",
                total, share(trace), share(w.traceSeconds[0]), share(w.traceSeconds[1]), share(w.traceSeconds[2]),
                share(w.shadeSeconds), share(w.cameraSeconds), share(w.filmSeconds));
}

/// The files the film will write for -o `out` (hdrfilm: the EXR, the PNG beside it, the
/// spectral EXR when it has bins), each probed now: a path that cannot be written fails
/// before the render, not after it. A dry run creates no folder.
void checkOutputs(std::filesystem::path out, const IFilm& film, bool dryRun) {
    if (!out.has_extension()) out += ".exr";  // as the film does
    std::vector<std::filesystem::path> files{out};
    std::string ext = out.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext == ".exr") files.push_back(std::filesystem::path(out).replace_extension(".png"));
    if (film.spectralBins() > 0) files.push_back(spectral_exr::spectralPath(out));
    for (const auto& f : files) requireWritable(f, !dryRun);
}

} // namespace

int render(const std::vector<std::string>& args) {
    std::string scenePath, outPath;
    xml::ParseOptions opt;
    RenderControl control;
    ProgressiveOptions prog;
    bool verbose = false, progressive = false, reference = false, dryRun = false, showStats = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "-o") outPath = needValue(args, i);
        else if (a == "-D") {
            std::string kv = needValue(args, i);
            auto eq = kv.find('=');
            if (eq == std::string::npos || eq == 0) fail("-D expects name=value, got '{}'", kv);
            opt.defines[kv.substr(0, eq)] = kv.substr(eq + 1);
        } else if (a == "-t") control.threads = int(parseLong(a, needValue(args, i)));
        else if (a == "--seed") control.seed = std::uint64_t(parseLong(a, needValue(args, i)));
        else if (a == "-v") verbose = true;
        else if (a == "--time") prog.timeBudget = parseDouble(a, needValue(args, i)), progressive = true;
        else if (a == "--spp") prog.spp = std::uint64_t(parseLong(a, needValue(args, i))), progressive = true;
        else if (a == "--target-relmse")
            prog.targetRelMSE = parseDouble(a, needValue(args, i)), progressive = true;
        else if (a == "--reference") reference = true;
        else if (a == "--no-progress") control.progress = false;
        else if (a == "--dry-run") dryRun = true;
        else if (a == "--stats") showStats = true;
        else if (!a.empty() && a[0] == '-') fail("render: unknown option '{}'", a);
        else if (scenePath.empty()) scenePath = a;
        else fail("render: more than one scene given ('{}', '{}')", scenePath, a);
    }
    if (scenePath.empty()) fail("render: no scene file given");
    // From here on SIGINT only asks the renderer to stop; a render interrupted before it
    // starts writes an empty image.
    std::signal(SIGINT, onSigint);
    control.stop = &g_stop;
    if (verbose) log::setLevel(log::Level::Info);
    if (outPath.empty()) outPath = std::filesystem::path(scenePath).stem().string() + ".exr";

    auto t0 = std::chrono::steady_clock::now();
    std::unique_ptr<Scene> scene = loadSceneFile(scenePath, opt);
    double loadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    checkOutputs(outPath, scene->camera().film(), dryRun);
    if (dryRun) {
        // Load only: every element parsed and every component created (so every error a
        // render would report up front is reported), nothing rendered or written.
        Vector2i size = scene->camera().film().size();
        std::printf("loaded %s: %zu shapes, %zu emitters, %dx%d, renderer %s (load %.2f s)\n", scenePath.c_str(),
                    scene->shapes().size(), scene->emitters().size(), size.x, size.y,
                    scene->renderer().typeName().c_str(), loadSeconds);
        return 0;
    }

    RenderStats stats;
    std::uint64_t spp = scene->camera().sampler().samplesPerPixel();
    double estimate = -1.0;
    if (progressive) {
        prog.progress = control.progress;
        stats = renderProgressive(*scene, control, prog, [&](const PassReport& r) {
            spp = r.spp;
            estimate = r.estimatedRelMSE;
            return true;
        });
    } else {
        stats = scene->renderer().render(*scene, control);
    }
    std::signal(SIGINT, SIG_DFL);

    IFilm& film = scene->camera().film();
    FilmMetadata meta{{"effigi/version", version()},
                      {"effigi/scene", std::filesystem::absolute(scenePath).string()},
                      {"effigi/renderer", scene->renderer().typeName()},
                      {"effigi/spp", std::to_string(spp)},
                      {"effigi/reference", reference ? "true" : "false"},
                      {"effigi/samples", std::to_string(stats.samples)},
                      {"effigi/seconds", fmt::format("{:.3f}", stats.seconds)},
                      {"effigi/interrupted", stats.interrupted ? "true" : "false"}};
    std::filesystem::path out(outPath);
    if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path());
    for (const auto& f : film.write(out, meta)) std::printf("wrote %s\n", f.string().c_str());

    if (verbose) {
        std::fprintf(stderr, "modules loaded:\n");
        for (const auto& m : Registry::instance().loadedModules()) std::fprintf(stderr, "  %s\n", m.c_str());
    }
    Vector2i size = film.size();
    std::printf("%dx%d, %llu samples in %.2f s (load %.2f s): %.3f M samples/s, %llu NaN/Inf samples rejected, "
                "peak memory %.0f MiB%s\n",
                size.x, size.y, (unsigned long long)stats.samples, stats.seconds, loadSeconds,
                stats.seconds > 0 ? double(stats.samples) / stats.seconds * 1e-6 : 0.0,
                (unsigned long long)stats.rejectedSamples, peakMemoryMiB(),
                stats.interrupted ? " (interrupted: partial image)" : "");
    if (showStats) printWorkStats(stats);
    if (prog.targetRelMSE > 0.0)
        std::printf("estimated relMSE %.3g (target %.3g) reached after %.2f s at %llu spp\n", estimate,
                    prog.targetRelMSE, stats.seconds, (unsigned long long)spp);
    return stats.interrupted ? 130 : 0;
}

} // namespace effigi::app
