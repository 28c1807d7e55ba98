// effigi render: load a scene, render it with its renderer, write the film.
#include "commands.hpp"
#include "output_check.hpp"
#include "render_checkpoint.hpp"
#include "render_ranks.hpp"
#include "preview_server.hpp"

#include "effigi/core/log.hpp"
#include "effigi/core/module.hpp"
#include "effigi/interfaces/iaccumulator.hpp"
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
#include <optional>
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

/// Everything `effigi render` was asked.
struct RenderOptions {
    std::string scenePath, outPath, checkpointDir, resumeDir;
    xml::ParseOptions parse;
    RenderControl control;
    ProgressiveOptions prog;
    double checkpointEvery = 60.0;
    int previewPort = -1;  // --preview: the live page's port (-1: no page)
    bool verbose = false, progressive = false, reference = false, dryRun = false, showStats = false;
};

RenderOptions parseOptions(const std::vector<std::string>& args) {
    RenderOptions o;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "-o") o.outPath = needValue(args, i);
        else if (a == "-D") {
            std::string kv = needValue(args, i);
            auto eq = kv.find('=');
            if (eq == std::string::npos || eq == 0) fail("-D expects name=value, got '{}'", kv);
            o.parse.defines[kv.substr(0, eq)] = kv.substr(eq + 1);
        } else if (a == "-t") o.control.threads = int(parseLong(a, needValue(args, i)));
        else if (a == "--seed") o.control.seed = std::uint64_t(parseLong(a, needValue(args, i)));
        else if (a == "-v") o.verbose = true;
        else if (a == "--time") o.prog.timeBudget = parseDouble(a, needValue(args, i)), o.progressive = true;
        else if (a == "--spp") o.prog.spp = std::uint64_t(parseLong(a, needValue(args, i))), o.progressive = true;
        else if (a == "--target-relmse")
            o.prog.targetRelMSE = parseDouble(a, needValue(args, i)), o.progressive = true;
        else if (a == "--checkpoint") o.checkpointDir = needValue(args, i);
        else if (a == "--checkpoint-every") o.checkpointEvery = parseDuration(a, needValue(args, i));
        else if (a == "--resume") o.resumeDir = needValue(args, i);
        else if (a == "--preview") o.previewPort = previewPortOption(args, i);
        else if (a == "--reference") o.reference = true;
        else if (a == "--no-progress") o.control.progress = false;
        else if (a == "--dry-run") o.dryRun = true;
        else if (a == "--stats") o.showStats = true;
        else if (!a.empty() && a[0] == '-') fail("render: unknown option '{}'", a);
        else if (o.scenePath.empty()) o.scenePath = a;
        else fail("render: more than one scene given ('{}', '{}')", o.scenePath, a);
    }
    if (o.scenePath.empty()) fail("render: no scene file given");
    if (o.outPath.empty()) o.outPath = std::filesystem::path(o.scenePath).stem().string() + ".exr";
    if (o.checkpointDir.empty()) o.checkpointDir = o.resumeDir;  // a resumed render goes on checkpointing there
    return o;
}

} // namespace

int render(const std::vector<std::string>& args) {
    return hasFramesOption(args) ? renderFrames(args) : renderOne(args, true);
}

int renderOne(const std::vector<std::string>& args, bool joinMpi) {
    // Under mpirun every rank runs this; errors up to the render are agreed on, so that
    // one line is printed and every rank ends with exit code 1.
    std::unique_ptr<Ranks> ranks = joinMpi ? joinRanks() : nullptr;
    const bool root = !ranks || ranks->root();
    if (!root) log::setLevel(log::Level::Error);  // warnings once, from rank 0
    RenderOptions o;
    std::unique_ptr<Scene> scene;
    CheckpointBase base;
    std::vector<double> resumed;
    bool sums = false;  // the render's running sums are saved or pooled: checkpoints, resume, ranks
    double loadSeconds = 0.0;
    std::string early;
    try {
        o = parseOptions(args);
        if (o.verbose && root) log::setLevel(log::Level::Info);
        sums = ranks || !o.checkpointDir.empty();
        const std::uint64_t seed = o.control.seed;
        if (ranks) {
            if (o.control.threads == 0) o.control.threads = ranks->threadsPerRank();
            o.control.seed += std::uint64_t(ranks->rank()) * Ranks::SeedStride;
            if (!root) o.control.progress = false;
        }
        auto t0 = std::chrono::steady_clock::now();
        scene = loadSceneFile(o.scenePath, o.parse);
        loadSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (root) checkOutputs(o.outPath, scene->camera().film(), o.dryRun);
        if (sums)
            base = {checkpointIdentity(o.scenePath, o.parse.defines, seed),
                    std::filesystem::absolute(o.scenePath).string(), o.prog.spp, o.prog.timeBudget,
                    o.prog.targetRelMSE};
        if (sums && (!query<IAccumulator>(&scene->camera().film()) || !query<IAccumulator>(&scene->renderer())))
            fail("renderer {} keeps state beyond the film's running sums: it cannot be checkpointed, resumed or "
                 "split over MPI ranks (renderers that can: path, direct, aov, moment, volpath, whitted, photonmap)",
                 scene->renderer().typeName());
        if (!o.resumeDir.empty() && root && !o.dryRun) resumed = readResume(o.resumeDir, *scene, base);
    } catch (const Error& e) {
        if (!ranks) throw;
        early = e.what();
    }
    if (ranks && !ranks->agree(early)) return 1;
    if (o.dryRun) {
        // Load only: every element parsed and every component created (so every error a
        // render would report up front is reported), nothing rendered or written.
        Vector2i size = scene->camera().film().size();
        if (root)
            std::printf("loaded %s: %zu shapes, %zu emitters, %dx%d, renderer %s (load %.2f s)\n",
                        o.scenePath.c_str(), scene->shapes().size(), scene->emitters().size(), size.x, size.y,
                        scene->renderer().typeName().c_str(), loadSeconds);
        return 0;
    }
    // From here on SIGINT only asks the renderer to stop; a render interrupted before it
    // starts writes an empty image.
    std::signal(SIGINT, onSigint);
    RenderControl& control = o.control;
    ProgressiveOptions& prog = o.prog;
    control.stop = &g_stop;

    std::uint64_t spp = scene->camera().sampler().samplesPerPixel();
    std::optional<CheckpointWriter> writer;
    RenderStats stats;
    double estimate = -1.0;
    try {
        if (ranks) ranks->bind(*scene), prog.sharing = ranks.get();
        if (!o.resumeDir.empty()) applyResume(std::move(resumed), base, prog, ranks.get()), spp = prog.resumed.spp;
        const bool previewed = o.previewPort >= 0;  // the same in every rank; the page is rank 0's
        if ((sums || previewed) && prog.spp == 0 && prog.timeBudget <= 0.0 && prog.targetRelMSE <= 0.0)
            prog.spp = base.spp = spp;  // the sampler's count, in passes that can be saved, shared or shown
        o.progressive = o.progressive || sums || previewed;
        std::unique_ptr<Preview> preview;
        if (previewed && root)
            preview = startPreview(o.previewPort, {o.scenePath, scene->renderer().typeName(), prog.spp,
                                                   prog.timeBudget, prog.targetRelMSE});
        if (!o.checkpointDir.empty()) {
            writer.emplace(o.checkpointDir, o.checkpointEvery, base, prog.resumed);
            prog.maxPassSeconds = o.checkpointEvery;
        }
        if (o.progressive) {
            prog.progress = control.progress;
            PassReport last;
            stats = renderProgressive(
                *scene, control, prog,
                [&](const PassReport& r) {
                    spp = r.spp;
                    estimate = r.estimatedRelMSE;
                    if (writer && writer->due(r)) writer->write(*scene, r, ranks.get());
                    if (preview) preview->afterPass(*scene, r, ranks ? nullptr : &prog.maxPassSeconds);
                    return true;
                },
                &last);
            // The job's sums into rank 0; a last checkpoint, also of a render cut short (its
            // partial pass's sample indices are counted as used, so none is drawn twice).
            if (writer) {
                const std::uint64_t bytes = writer->write(*scene, last, ranks.get());
                if (root)
                    log::info("checkpoint {} ({:.1f} MiB)", checkpointFile(o.checkpointDir).string(),
                              double(bytes) / 1048576.0);
            } else if (ranks) {
                ranks->gather(false);
            }
            if (preview) preview->finish(*scene, last);
        } else {
            stats = scene->renderer().render(*scene, control);
        }
    } catch (const Error& e) {
        if (ranks && ranks->processes() > 1) ranks->abort(e.what());
        throw;
    }
    std::signal(SIGINT, SIG_DFL);
    if (!root) return stats.interrupted ? 130 : 0;

    IFilm& film = scene->camera().film();
    FilmMetadata meta{{"effigi/version", version()},
                      {"effigi/scene", std::filesystem::absolute(o.scenePath).string()},
                      {"effigi/renderer", scene->renderer().typeName()},
                      {"effigi/spp", std::to_string(spp)},
                      {"effigi/reference", o.reference ? "true" : "false"},
                      {"effigi/samples", std::to_string(stats.samples)},
                      {"effigi/seconds", fmt::format("{:.3f}", stats.seconds)},
                      {"effigi/interrupted", stats.interrupted ? "true" : "false"}};
    std::filesystem::path out(o.outPath);
    if (out.has_parent_path()) std::filesystem::create_directories(out.parent_path());
    for (const auto& f : film.write(out, meta)) std::printf("wrote %s\n", f.string().c_str());

    if (o.verbose) {
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
    if (ranks) {
        const Ranks::Traffic t = ranks->traffic();
        std::printf("MPI: %llu ranks x %d threads, %d reductions into rank 0 of %.2f MiB per rank, %.3f s in all\n",
                    (unsigned long long)ranks->processes(), control.threads, t.reductions, t.lastBytes / 1048576.0,
                    t.seconds);
    }
    if (o.showStats) printWorkStats(stats);
    if (prog.targetRelMSE > 0.0)
        std::printf("estimated relMSE %.3g (target %.3g) reached after %.2f s at %llu spp\n", estimate,
                    prog.targetRelMSE, stats.seconds, (unsigned long long)spp);
    return stats.interrupted ? 130 : 0;
}

} // namespace effigi::app
