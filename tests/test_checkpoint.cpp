// Checkpoints (effigi/render/checkpoint.hpp, effigi render --checkpoint/--resume): the file
// round-trips and refuses anything incomplete; a writer killed at any moment leaves a
// complete checkpoint; a render killed with SIGKILL and resumed gives the image of an
// uninterrupted render — the same samples (same seed: equal up to float16 rounding and
// summation order) and, against another seed, the same region means within a stated
// statistical tolerance.
#include "app_runner.hpp"
#include "cornell_regions.hpp"
#include "image_helpers.hpp"

#include "effigi/core/error.hpp"
#include "effigi/render/checkpoint.hpp"

#include <catch2/catch.hpp>

#include <csignal>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <random>
#include <thread>

namespace fs = std::filesystem;
using namespace effigi;
using namespace effigi::test;

namespace {

/// A checkpoint whose every value is `stamp` (so a mixture of two writes would show).
Checkpoint stamped(std::uint64_t stamp, std::size_t floats) {
    Checkpoint c;
    c.identity = stamp, c.scene = "scene.xml", c.spp = 64;
    c.report.spp = stamp, c.report.seconds = double(stamp);
    c.processSpp = {stamp, stamp + 1};
    c.film.layout = "film", c.film.floats.assign(floats, float(stamp));
    c.renderer.layout = "variance", c.renderer.doubles.assign(floats / 8, double(stamp));
    return c;
}

bool uniform(const Checkpoint& c) {
    const float f = float(c.identity);
    const double d = double(c.identity);
    return c.report.spp == c.identity &&
           std::all_of(c.film.floats.begin(), c.film.floats.end(), [&](float v) { return v == f; }) &&
           std::all_of(c.renderer.doubles.begin(), c.renderer.doubles.end(), [&](double v) { return v == d; });
}

std::string errorOf(const fs::path& dir) {
    try {
        readCheckpoint(dir);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

/// Start `effigi args...` with its output discarded; its pid.
pid_t spawnApp(const std::vector<std::string>& args) {
    pid_t pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        int devnull = open("/dev/null", O_WRONLY);
        dup2(devnull, 1), dup2(devnull, 2);
        std::vector<char*> argv{const_cast<char*>(EFFIGI_APP)};
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        execv(EFFIGI_APP, argv.data());
        _exit(127);
    }
    return pid;
}

std::string attribute(const ExrImage& img, const char* name) { return img.spec.get_string_attribute(name); }

} // namespace

TEST_CASE("checkpoint: a file round-trips and damage is refused in one line", "[checkpoint]") {
    const fs::path dir = tempDir("checkpoint-file");
    Checkpoint c = stamped(7, 1000);
    c.timeBudget = 2.5, c.targetRelMSE = 0.01, c.report.stats.samples = 123, c.report.stats.rejectedSamples = 4;
    const std::uint64_t bytes = writeCheckpoint(dir, c);
    CHECK(bytes == fs::file_size(checkpointFile(dir)));
    Checkpoint r = readCheckpoint(dir);
    CHECK(r.identity == 7);
    CHECK(r.scene == "scene.xml");
    CHECK(r.spp == 64);
    CHECK(r.timeBudget == 2.5);
    CHECK(r.targetRelMSE == 0.01);
    CHECK(r.report.stats.samples == 123);
    CHECK(r.report.stats.rejectedSamples == 4);
    CHECK(r.processSpp == std::vector<std::uint64_t>{7, 8});
    CHECK(r.film.layout == "film");
    CHECK(r.film.floats == c.film.floats);
    CHECK(r.renderer.doubles == c.renderer.doubles);
    CHECK(std::distance(fs::directory_iterator(dir), fs::directory_iterator()) == 1);  // no temporary left

    // A file cut short, a flipped byte, no file: one line naming the file, never a crash.
    std::string text;
    {
        std::ifstream in(checkpointFile(dir), std::ios::binary);
        text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    std::ofstream(checkpointFile(dir), std::ios::binary) << text.substr(0, text.size() / 2);
    CHECK_THAT(errorOf(dir), Catch::Contains("truncated or damaged") && Catch::Contains("checkpoint.effigi"));
    text[text.size() / 2] ^= 0x10;
    std::ofstream(checkpointFile(dir), std::ios::binary) << text;
    CHECK_THAT(errorOf(dir), Catch::Contains("checksum mismatch"));
    std::ofstream(checkpointFile(dir), std::ios::binary) << "EFFIGI";
    CHECK_THAT(errorOf(dir), Catch::Contains("not a valid effigi checkpoint"));
    fs::remove(checkpointFile(dir));
    CHECK_THAT(errorOf(dir), Catch::Contains("no checkpoint there"));
    fs::remove_all(dir);
}

TEST_CASE("checkpoint: empty arrays round-trip and values no render writes are refused", "[checkpoint]") {
    const fs::path dir = tempDir("checkpoint-values");
    // Empty arrays (a film without double sums, a renderer without sums): their data() may
    // be null, which memcpy must not be given even for 0 bytes (UBSan, 2026-11-29).
    Checkpoint c = stamped(3, 0);
    c.processSpp.clear();
    writeCheckpoint(dir, c);
    Checkpoint r = readCheckpoint(dir);
    CHECK(r.film.floats.empty());
    CHECK(r.renderer.doubles.empty());
    CHECK(r.processSpp.empty());

    // The checksum passes (the file is framed by writeCheckpoint), the values cannot be.
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 6; ++k) {
        Checkpoint bad = stamped(5, 16);
        if (k == 0) bad.timeBudget = nan;
        if (k == 1) bad.targetRelMSE = -1.0;
        if (k == 2) bad.report.seconds = inf;
        if (k == 3) bad.film.floats[3] = float(inf);
        if (k == 4) bad.renderer.doubles[1] = nan;
        if (k == 5) bad.film.floats[15] = -float(nan);
        writeCheckpoint(dir, bad);
        const std::string e = errorOf(dir);
        INFO("case " << k << ": " << e);
        CHECK_THAT(e, Catch::Contains("not a valid effigi checkpoint") && Catch::Contains("checkpoint.effigi"));
        CHECK(e.find('\n') == std::string::npos);
    }
    fs::remove_all(dir);
}

TEST_CASE("checkpoint: a writer killed at any moment leaves a complete checkpoint", "[checkpoint]") {
    // A child rewrites an 8 MB checkpoint with a new stamp over and over; it is killed
    // with SIGKILL after a random delay (seeded), mid-write most of the time. The reader
    // must then find a whole checkpoint of one stamp: the last completed write.
    const fs::path dir = tempDir("checkpoint-torn");
    writeCheckpoint(dir, stamped(1, 2 << 20));
    std::mt19937 rng(17);
    std::uniform_int_distribution<int> delayMs(0, 60);
    std::uint64_t highest = 1;
    for (int round = 0; round < 12; ++round) {
        const std::uint64_t first = 1000 * std::uint64_t(round + 1);
        pid_t pid = fork();
        REQUIRE(pid >= 0);
        if (pid == 0) {
            for (std::uint64_t k = first;; ++k) writeCheckpoint(dir, stamped(k, 2 << 20));
            _exit(0);
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(delayMs(rng)));
        kill(pid, SIGKILL);
        int status = 0;
        waitpid(pid, &status, 0);
        const Checkpoint c = readCheckpoint(dir);
        INFO("round " << round << ": stamp " << c.identity);
        CHECK(uniform(c));
        CHECK(c.film.floats.size() == std::size_t(2 << 20));
        CHECK(c.identity >= highest);  // never an older checkpoint than one seen before
        highest = c.identity;
    }
    // The temporaries of killed writers stay beside it and are never read.
    CHECK(readCheckpoint(dir).identity == highest);
    fs::remove_all(dir);
}

TEST_CASE("checkpoint: a render killed with SIGKILL resumes to the uninterrupted image", "[checkpoint]") {
    // Cornell box, 64x64, 160 spp, seed 3: uninterrupted; killed once a checkpoint exists
    // (checkpoints every 100 ms) and resumed; and an independent render (seed 11).
    const fs::path dir = tempDir("checkpoint-resume");
    const std::string scene = EFFIGI_SOURCE_DIR "/scenes/cornell-box/scene.xml";
    const std::string common = scene + " -D res=64 --spp 160 --no-progress";
    const fs::path whole = dir / "whole.exr", resumed = dir / "resumed.exr", other = dir / "other.exr",
                   ckpt = dir / "ckpt";
    AppResult a = runApp("render " + common + " --seed 3 -o " + whole.string());
    REQUIRE(a.exitCode == 0);

    pid_t pid = spawnApp({"render", scene, "-D", "res=64", "--spp", "160", "--no-progress", "--seed", "3", "-o",
                          resumed.string(), "--checkpoint", ckpt.string(), "--checkpoint-every", "100ms"});
    bool running = true;
    for (int i = 0; i < 3000 && running && !fs::exists(checkpointFile(ckpt)); ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        running = waitpid(pid, nullptr, WNOHANG) == 0;
    }
    REQUIRE(running);  // killed mid-render, not after it
    kill(pid, SIGKILL);
    waitpid(pid, nullptr, 0);
    const Checkpoint at = readCheckpoint(ckpt);
    INFO("killed after a checkpoint at " << at.report.spp << " spp");
    CHECK(at.report.spp > 0);
    CHECK(at.report.spp < 160);
    CHECK(!fs::exists(resumed));

    // Other -D values (another scene, in effect) are refused in one line.
    AppResult wrong = runApp("render " + scene + " -D res=32 --seed 3 --no-progress -o " + (dir / "x.exr").string() +
                             " --resume " + ckpt.string());
    CHECK(wrong.exitCode == 1);
    CHECK_THAT(wrong.out, Catch::Contains("another scene or other options"));

    AppResult r = runApp("render " + scene + " -D res=64 --seed 3 --no-progress -o " + resumed.string() +
                         " --resume " + ckpt.string());  // the budget (--spp 160) is the checkpoint's
    INFO(r.out);
    REQUIRE(r.exitCode == 0);
    AppResult b = runApp("render " + common + " --seed 11 -o " + other.string());
    REQUIRE(b.exitCode == 0);

    const ExrImage w = readExr(whole), s = readExr(resumed), o = readExr(other);
    REQUIRE(s.pixels() == w.pixels());
    // Every sample drawn once: the counts, then the same samples (same seed, the indices
    // continue), so the images agree to float16 rounding.
    CHECK(attribute(s, "effigi/samples") == std::to_string(64 * 64 * 160));
    CHECK(attribute(s, "effigi/spp") == "160");
    double worst = 0.0;
    for (std::size_t i = 0; i < w.px.size(); ++i)
        worst = std::max(worst, std::abs(double(s.px[i]) - w.px[i]) / (std::abs(double(w.px[i])) + 1e-3));
    CHECK(worst < 4e-3);  // float16 keeps 11 bits: 4.9e-4 relative, a few roundings apart

    // Against another seed: region means of grey, and the image mean of R, G, B. The
    // difference image d = resumed − other has independent noise; the standard error of a
    // region mean of d is taken from d's pixel variance over the region, inflated 4x for
    // the Gaussian filter's correlation of neighbouring pixels (each pixel averages about
    // 1 / 0.32 pixels' samples: filterVarianceFactor), which makes it conservative.
    // |z| < 4.5: a false alarm below 7e-6 per comparison (normal), 1e-4 over the 10.
    auto value = [](const ExrImage& img, std::size_t i, int c) {
        return c < 0 ? (img.px[3 * i] + img.px[3 * i + 1] + img.px[3 * i + 2]) / 3.0 : double(img.px[3 * i + c]);
    };
    std::vector<std::pair<std::string, std::array<float, 4>>> checks;
    for (const CornellRegion& reg : cornellRegions()) checks.push_back({reg.name, {reg.x0, reg.y0, reg.x1, reg.y1}});
    for (int c = 0; c < 3; ++c) checks.push_back({"image channel " + std::to_string(c), {0.f, 0.f, 1.f, 1.f}});
    REQUIRE(checks.size() == 10);
    for (std::size_t k = 0; k < checks.size(); ++k) {
        const auto& [name, f] = checks[k];
        const int channel = k < 7 ? -1 : int(k) - 7;
        const int x0 = int(f[0] * 64), y0 = int(f[1] * 64), x1 = int(f[2] * 64), y1 = int(f[3] * 64);
        double sum = 0, sum2 = 0, ref = 0;
        int n = 0;
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                const std::size_t i = std::size_t(y) * 64 + std::size_t(x);
                const double d = value(s, i, channel) - value(o, i, channel);
                sum += d, sum2 += d * d, ref += value(o, i, channel), ++n;
            }
        const double mean = sum / n, var = std::max(0.0, sum2 / n - mean * mean);
        const double se = std::sqrt(4.0 * var / n), z = se > 0 ? mean / se : 0.0;
        INFO(name << ": mean " << ref / n << ", difference " << mean << " ± " << se << " (z = " << z << ")");
        CHECK(std::abs(z) < 4.5);
        CHECK(se < 0.05 * ref / n);  // sharp enough to catch a lost or doubled pass
    }
    fs::remove_all(dir);
}

TEST_CASE("checkpoint: renderers with more state than the film are refused", "[checkpoint]") {
    const fs::path dir = tempDir("checkpoint-refused");
    std::ofstream(dir / "sppm.xml") << R"(<scene version="3.0.0">
  <integrator type="sppm"/>
  <sensor type="perspective">
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
  </sensor>
  <shape type="sphere"/>
  <emitter type="constant"/>
</scene>)";
    AppResult r = runApp("render " + (dir / "sppm.xml").string() + " --no-progress --spp 2 -o " +
                         (dir / "a.exr").string() + " --checkpoint " + (dir / "ck").string());
    CHECK(r.exitCode == 1);
    CHECK_THAT(r.out, Catch::Contains("cannot be checkpointed"));
    AppResult every = runApp("render " + (dir / "sppm.xml").string() + " --checkpoint-every 5parsecs");
    CHECK(every.exitCode == 1);
    CHECK_THAT(every.out, Catch::Contains("expects a duration"));
    fs::remove_all(dir);
}
