// effigi-conform — runs the conformance suites (conformance/) on every component the
// registry knows, built in or found on EFFIGI_PLUGIN_PATH, in each configuration its
// schema declares, and prints one row per component × configuration × check. Exit code
// 0 when every check passes, 1 when one fails, 2 on bad usage.
#include "conformance/conformance.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/worker_threads.hpp"

#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include <unistd.h>

namespace {

void usage(std::FILE* out) {
    std::fprintf(out,
                 "usage: effigi-conform [options]\n"
                 "  --tag TAG            only components of this tag (bsdf, warp, sampler, ...)\n"
                 "  --component NAME     only components of this name\n"
                 "  --seed N             seed of every check (default %llu); runs are deterministic\n"
                 "  --quick              fewer samples and angles (what `make test` runs)\n"
                 "  --report FILE.html   also write an HTML report (with the images of failing tests)\n"
                 "  --json [FILE]        write the rows as JSON to FILE, or to stdout instead of the table\n"
                 "  --out DIR            directory for histogram images (default conform-out)\n"
                 "  --threads N          worker threads (default: all cores)\n"
                 "  --list               list the suites and the jobs that would run, run nothing\n",
                 static_cast<unsigned long long>(effigi::conform::Options{}.seed));
}

std::string value(const std::vector<std::string>& args, std::size_t& i) {
    if (i + 1 >= args.size()) effigi::fail("option {} needs a value", args[i]);
    return args[++i];
}

std::uint64_t number(const std::string& option, const std::string& text) {
    try {
        std::size_t used = 0;
        unsigned long long v = std::stoull(text, &used, 0);
        if (used != text.size()) throw std::invalid_argument(text);
        return v;
    } catch (const std::exception&) {
        effigi::fail("option {} expects a non-negative integer, got '{}'", option, text);
    }
}

int run(const std::vector<std::string>& args) {
    using namespace effigi::conform;
    Options opts;
    std::string report, json;
    bool list = false, jsonOut = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        if (a == "-h" || a == "--help") {
            usage(stdout);
            return 0;
        } else if (a == "--tag") opts.tag = value(args, i);
        else if (a == "--component") opts.component = value(args, i);
        else if (a == "--seed") opts.seed = number(a, value(args, i));
        else if (a == "--quick") opts.quick = true;
        else if (a == "--report") report = value(args, i);
        else if (a == "--out") opts.outDir = value(args, i);
        else if (a == "--threads") opts.threads = int(number(a, value(args, i)));
        else if (a == "--list") list = true;
        else if (a == "--json") {
            jsonOut = true;
            if (i + 1 < args.size() && args[i + 1].rfind("--", 0) != 0) json = args[++i];
        } else {
            std::fprintf(stderr, "effigi-conform: unknown option '%s'\n", a.c_str());
            usage(stderr);
            return 2;
        }
    }
    if (!opts.tag.empty() && !findSuite(opts.tag)) {
        std::string tags;
        for (const Suite& s : suites()) tags += (tags.empty() ? "" : ", ") + s.tag;
        effigi::fail("no conformance suite for tag '{}' (suites: {})", opts.tag, tags);
    }

    Session session(opts);
    std::vector<Job> jobs = session.plan();
    if (list) {
        for (const Suite& s : suites()) std::printf("suite %-12s %s\n", s.tag.c_str(), s.summary.c_str());
        std::printf("\n");
        for (const Job& j : jobs) std::printf("%s/%s  %s\n", j.tag.c_str(), j.component.c_str(), j.config.name.c_str());
        return 0;
    }
    if (jobs.empty())
        effigi::fail("no component matches{}{}", opts.tag.empty() ? "" : " --tag " + opts.tag,
                     opts.component.empty() ? "" : " --component " + opts.component);

    // Progress on a terminal only: ctest and pipes get the table alone.
    const bool progress = isatty(fileno(stderr));
    std::size_t started = 0;
    session.run([&](const Job& j) {
        if (progress)
            std::fprintf(stderr, "\r[%zu/%zu] %s/%s (%s)\033[K", ++started, jobs.size(), j.tag.c_str(),
                         j.component.c_str(), j.config.name.c_str());
    });
    if (progress) std::fprintf(stderr, "\r\033[K");

    const bool jsonToStdout = jsonOut && (json.empty() || json == "-");
    if (!jsonToStdout) session.printTable(stdout);
    if (jsonOut) {
        std::FILE* f = jsonToStdout ? stdout : std::fopen(json.c_str(), "w");
        if (!f) effigi::fail("cannot write {}", json);
        session.writeJson(f);
        if (f != stdout) std::fclose(f);
    }
    if (!report.empty()) {
        session.writeHtml(report);
        std::fprintf(stderr, "report: %s\n", report.c_str());
    }
    return session.count(Verdict::Fail) == 0 ? 0 : 1;
}

} // namespace

int main(int argc, char** argv) {
    effigi::WorkerThreadsJoin join;  // workers joined before exit (LeakSanitizer)
    try {
        return run(std::vector<std::string>(argv + 1, argv + argc));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "effigi-conform: error: %s\n", e.what());
        return 2;
    }
}
