// Per-pixel adaptive sampling: `adaptive` in mode "pixels" (IPixelAllocator) and the
// two-part passes of renderSampled. The plan and the allocation on synthetic pilots
// (counts ∝ the square root of the pixels' relative variance, the budget kept, the caps),
// the Cornell box region by region against uniform sampling, and the hidden benchmark
// against uniform sampling. (The box's image mean: test_integrators_adaptive.cpp.)
#include "scene_text.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/iintegrator_hooks.hpp"
#include "effigi/render/image_metrics.hpp"

#include <catch2/catch.hpp>

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numeric>

using namespace effigi;

namespace {

Ref<IIntegrator> pixelsIntegrator(double meanShare = 0.5) {
    Properties p("integrator", "adaptive");
    p.set("mode", std::string("pixels"));
    p.set("mean_share", meanShare);
    return query<IIntegrator>(Registry::instance().create("integrator", "adaptive", p));
}

/// Pilots whose one-sample relative variance (Σ_c σ²/(μ² + 0.01)) is `d(x, y)`.
std::vector<PixelPilot> pilots(int w, int h, std::uint32_t samples, double (*d)(int, int)) {
    std::vector<PixelPilot> out(std::size_t(w) * std::size_t(h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            PixelPilot& p = out[std::size_t(y) * std::size_t(w) + std::size_t(x)];
            p.samples = samples;
            for (int c = 0; c < 3; ++c)
                p.mean[c] = 1.f, p.variance[c] = float(d(x, y) * (1.0 + RelMSEEpsilon) / 3.0 / samples);
        }
    return out;
}

} // namespace

TEST_CASE("adaptive, mode pixels: the pilot and its share", "[integrator][adaptive]") {
    auto integ = pixelsIntegrator();
    auto* alloc = query<IPixelAllocator>(integ.get());
    REQUIRE(alloc);
    // f M = 256 → a pilot of 32 weighing 32/256; below 32 samples on average, one uniform part.
    CHECK(alloc->plan(512).pilot == 32);
    CHECK(alloc->plan(512).pilotShare == Approx(0.125));
    CHECK(alloc->plan(64).pilot == 4);
    CHECK(alloc->plan(63).pilot == 0);
    // mode strata (the default) never splits a pass.
    Properties p("integrator", "adaptive");
    auto strata = query<IPixelAllocator>(Registry::instance().create("integrator", "adaptive", p));
    REQUIRE(strata);
    CHECK(strata->plan(4096).pilot == 0);
}

TEST_CASE("adaptive, mode pixels: counts follow the square root of the relative variance", "[integrator][adaptive]") {
    auto integ = pixelsIntegrator();
    auto* alloc = query<IPixelAllocator>(integ.get());
    REQUIRE(alloc);
    const int w = 32, h = 16;
    std::vector<std::uint64_t> counts;

    // Right half 4× the relative variance of the left: √ ratio 2, mean √d 1.5 (left = 1);
    // shares 0.9/1.5 + 0.1 = 0.7 and 0.9·2/1.5 + 0.1 = 1.3 of the 224 left after the
    // pilot of a 512 budget: 157 and 291 samples away from the seam (windows of 3×3).
    alloc->allocate(pilots(w, h, 32, [](int x, int) { return x < 16 ? 1.0 : 4.0; }), w, h, 512, counts);
    REQUIRE(counts.size() == std::size_t(w * h));
    CHECK(counts[5 * w + 4] == Approx(156.8).margin(1.5));
    CHECK(counts[5 * w + 28] == Approx(291.2).margin(1.5));
    const double total = double(std::accumulate(counts.begin(), counts.end(), std::uint64_t(0)));
    CHECK(total / double(w * h) == Approx(224.0).epsilon(0.005));

    // A uniform (or black) image: every pixel the same count; a hot spot: capped at the
    // budget less the pilot, the other pixels never below one sample.
    alloc->allocate(pilots(w, h, 32, [](int, int) { return 0.0; }), w, h, 512, counts);
    for (std::uint64_t n : counts) CHECK(n == 224);
    alloc->allocate(pilots(w, h, 32, [](int x, int y) { return x < 3 && y < 3 ? 1e8 : 1e-6; }), w, h, 512, counts);
    CHECK(counts[0] == 480);
    CHECK(*std::min_element(counts.begin(), counts.end()) >= 1);
    CHECK(*std::max_element(counts.begin(), counts.end()) <= 480);
}

TEST_CASE("path with adaptive mode pixels agrees with uniform sampling region by region", "[integrator][render]") {
    // Cornell box at 32², `mean` at 256 spp against mode pixels at 512 (256 spent on average,
    // most on the ceiling): 4 × 4 regions × R, G, B, each mean within 4.5 standard errors of
    // the difference (two-sided 6.8e-6 each, 3e-4 for all 48). A film that let a pixel with
    // more samples weigh more in its neighbours, or pooled the pilot with the counts it
    // chose, would move the regions where the counts change. Seeded: deterministic.
    struct Render {
        Image image;
        std::vector<float> variance;  // of the unfiltered pixel (the film filter's factor removed)
    };
    auto render = [](const std::string& nested, int spp, std::uint64_t seed) {
        auto scene = test::loadWithIntegrator(
            EFFIGI_SOURCE_DIR "/scenes/cornell-box/scene.xml",
            "<integrator type=\"path\"><boolean name=\"wavefront\" value=\"false\"/>" + nested + "</integrator>",
            {{"spp", std::to_string(spp)}, {"res", "32"}});
        RenderControl control;
        control.progress = false;
        control.seed = seed;
        scene->renderer().render(*scene, control);
        Render r{scene->camera().film().develop(), {}};
        REQUIRE(scene->renderer().varianceEstimate(r.variance));
        for (float& v : r.variance) v /= float(filterVarianceFactor(scene->camera().film().filter()));
        return r;
    };
    const Render u = render("", 256, 1);
    const Render a =
        render("<integrator type=\"adaptive\"><string name=\"mode\" value=\"pixels\"/></integrator>", 512, 2);
    for (int region = 0; region < 16; ++region)
        for (int c = 0; c < 3; ++c) {
            double mu = 0.0, ma = 0.0, var = 0.0;
            for (int y = region / 4 * 8; y < region / 4 * 8 + 8; ++y)
                for (int x = region % 4 * 8; x < region % 4 * 8 + 8; ++x) {
                    const std::size_t i = std::size_t(y) * 32 + std::size_t(x);
                    mu += u.image.at(x, y, c), ma += a.image.at(x, y, c);
                    var += u.variance[3 * i + std::size_t(c)] + a.variance[3 * i + std::size_t(c)];
                }
            INFO("region " << region << " channel " << c << ": uniform " << mu / 64 << ", adaptive " << ma / 64
                           << ", standard error of the difference " << std::sqrt(var) / 64);
            CHECK(std::abs(mu - ma) / 64 <= 4.5 * std::sqrt(var) / 64 + 1e-6);
        }
}

// ---- measurement (hidden: run `test_adaptive_pixels "[.bench]"`) ------------------------
// The Cornell box (scenes/cornell-box/scene.xml, max_depth 8) at EFFIGI_BENCH_RES² (128)
// against a reference of EFFIGI_BENCH_REF_SPP (4096) spp from `path` with `mean`: relMSE
// against process CPU time (user + system, all threads) for uniform sampling (`mean`, in
// the wavefront and in the one-path loop that every other integrator uses) and the
// adaptive integrators. CPU time, not wall time, because the machine may be shared.
// EFFIGI_BENCH_ONLY=a,b runs only the configurations whose names contain a or b;
// EFFIGI_BENCH_SEEDS=n renders each n times (seeds differ). Each row ends with the CPU
// time uniform sampling (the wavefront rows of the run, interpolated log-log, slope −1
// past their ends) needs for that relMSE, over the row's own. Asserts nothing.

namespace {

double cpuSeconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

int envInt(const char* name, int fallback) {
    const char* v = std::getenv(name);
    return v ? std::atoi(v) : fallback;
}

struct Timed {
    Image image;
    double cpu = 0.0;
    std::uint64_t samples = 0;
};

Timed renderTimed(const std::string& pathXml, int res, int spp, std::uint64_t seed) {
    auto scene = test::loadWithIntegrator(EFFIGI_SOURCE_DIR "/scenes/cornell-box/scene.xml", pathXml,
                                          {{"spp", std::to_string(spp)}, {"res", std::to_string(res)}});
    RenderControl control;
    control.progress = false;
    control.seed = seed;
    Timed t;
    const double c0 = cpuSeconds();
    t.samples = scene->renderer().render(*scene, control).samples;
    t.cpu = cpuSeconds() - c0;
    t.image = scene->camera().film().develop();
    return t;
}

/// CPU time of uniform sampling at `relMSE`: its runs' geometric means per spp (ascending),
/// interpolated log-log between the two around `relMSE`, slope −1 past the ends.
double uniformTime(const std::map<int, std::array<double, 3>>& logs, double relMSE) {
    std::vector<std::pair<double, double>> u;  // (relMSE, CPU s), falling relMSE
    for (const auto& [spp, l] : logs) u.emplace_back(std::exp(l[0] / l[2]), std::exp(l[1] / l[2]));
    if (u.empty()) return std::nan("");
    if (u.size() == 1 || relMSE >= u[0].first) return u[0].second * u[0].first / relMSE;
    if (relMSE <= u.back().first) return u.back().second * u.back().first / relMSE;
    std::size_t i = 1;
    while (u[i].first > relMSE) ++i;
    const auto [e0, t0] = u[i - 1];
    const auto [e1, t1] = u[i];
    return t0 * std::pow(t1 / t0, std::log(relMSE / e0) / std::log(e1 / e0));
}

} // namespace

TEST_CASE("bench: Cornell box, relMSE against CPU time, uniform against adaptive sampling", "[.bench]") {
    const int res = envInt("EFFIGI_BENCH_RES", 128), refSpp = envInt("EFFIGI_BENCH_REF_SPP", 4096);
    const int seeds = std::max(1, envInt("EFFIGI_BENCH_SEEDS", 1));
    const std::string open = "<integrator type=\"path\"><integer name=\"max_depth\" value=\"$max_depth\"/>";
    // The reference, cached as raw floats in out/bench/.
    const std::string cache = EFFIGI_SOURCE_DIR "/out/bench/cornell-adaptive-ref-" + std::to_string(res) + "-" +
                              std::to_string(refSpp) + ".f32";
    Image ref;
    if (std::ifstream in(cache, std::ios::binary); in) {
        ref = renderTimed(open + "</integrator>", res, 1, 0).image;  // the layout
        in.read(reinterpret_cast<char*>(ref.pixels.data()), std::streamsize(ref.pixels.size() * sizeof(float)));
    } else {
        Timed t = renderTimed(open + "</integrator>", res, refSpp, 1000);
        std::printf("reference: %d spp in %.0f s CPU\n", refSpp, t.cpu);
        ref = t.image;
        std::filesystem::create_directories(EFFIGI_SOURCE_DIR "/out/bench");
        std::ofstream(cache, std::ios::binary)
            .write(reinterpret_cast<const char*>(ref.pixels.data()),
                   std::streamsize(ref.pixels.size() * sizeof(float)));
    }
    struct Config {
        std::string name, xml;
        std::vector<int> spp;
    };
    const std::vector<int> ladder = {16, 32, 64, 128, 256, 512};
    const std::string pixels = "<integrator type=\"adaptive\"><string name=\"mode\" value=\"pixels\"/>";
    std::vector<Config> configs = {
        {"mean (wavefront)", "", ladder},
        {"mean (one path)", "<boolean name=\"wavefront\" value=\"false\"/>", ladder},
        {"adaptive pixels", pixels + "</integrator>", {64, 128, 256, 512, 1024}},
        {"adaptive pixels share 0.3", pixels + "<float name=\"mean_share\" value=\"0.3\"/></integrator>", {427, 853}},
        {"stratified", "<integrator type=\"stratified\"/>", ladder},
        {"adaptive", "<integrator type=\"adaptive\"/>", ladder},
        {"vegas", "<integrator type=\"vegas\"/>", ladder},
    };
    for (const char* e : {"0.3", "0.2", "0.1", "0.05", "0.03"})
        configs.push_back({std::string("adaptive rel_error ") + e,
                           "<integrator type=\"adaptive\"><float name=\"rel_error\" value=\"" + std::string(e) +
                               "\"/></integrator>",
                           {1024}});
    std::printf("Cornell box %d², reference %d spp (mean); relMSE against it\n", res, refSpp);
    std::printf("%-26s %6s %12s %10s %9s %13s\n", "configuration", "spp", "samples/px", "relMSE", "CPU s",
                "uniform t / t");
    // EFFIGI_BENCH_ONLY: substrings of the names to run, comma-separated (uniform always runs).
    const std::string only = std::getenv("EFFIGI_BENCH_ONLY") ? std::getenv("EFFIGI_BENCH_ONLY") : "";
    auto selected = [&](const std::string& name) {
        if (only.empty() || name == "mean (wavefront)") return true;
        for (std::size_t a = 0, b; a <= only.size(); a = b + 1) {
            b = std::min(only.find(',', a), only.size());
            if (b > a && name.find(only.substr(a, b - a)) != std::string::npos) return true;
        }
        return false;
    };
    std::map<int, std::array<double, 3>> uniform;          // the wavefront's Σ log relMSE, Σ log CPU, runs
    std::uint64_t seed = 1;
    for (const Config& c : configs)
        for (int spp : c.spp)
            for (int k = 0; k < seeds; ++k) {
                ++seed;
                if (!selected(c.name)) continue;
                Timed t = renderTimed(open + c.xml + "</integrator>", res, spp, seed + 1000u * std::uint64_t(k));
                const ErrorMetrics m = compareImages(t.image, ref);
                if (c.name == "mean (wavefront)") {
                    auto& l = uniform[spp];
                    l[0] += std::log(m.relMSE), l[1] += std::log(t.cpu), l[2] += 1.0;
                }
                std::printf("%-26s %6d %12.1f %10.3e %9.2f %13.3f\n", c.name.c_str(), spp,
                            double(t.samples) / double(res * res), m.relMSE, t.cpu,
                            uniformTime(uniform, m.relMSE) / t.cpu);
                std::fflush(stdout);
            }
}
