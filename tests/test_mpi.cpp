// `mpirun -np N effigi render` (apps/effigi/render_mpi.cpp) on this machine: 2 and 3
// (uneven shares) ranks give the image of one process, within a stated statistical
// tolerance, with every requested sample drawn once; the time budget is global; a
// checkpoint written by 3 ranks resumes in one process. Skipped (exit 77) only where the
// app is built without MPI (CMake option EFFIGI_MPI).
#include "app_runner.hpp"
#include "cornell_regions.hpp"
#include "image_helpers.hpp"
#include "skip.hpp"

#include "effigi/render/checkpoint.hpp"

#include "test_mpi_config.hpp"  // EFFIGI_TEST_MPIEXEC: mpirun, or "" without MPI (tests/CMakeLists.txt)

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>

namespace fs = std::filesystem;
using namespace effigi;
using namespace effigi::test;

namespace {

const std::string CornellScene = EFFIGI_SOURCE_DIR "/scenes/cornell-box/scene.xml";

/// `mpirun -np n effigi args` on localhost, as root too (containers, CI).
AppResult runRanks(int n, const std::string& args) {
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1);
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);
    setenv("OMPI_MCA_rmaps_base_oversubscribe", "1", 1);
    std::string env;
#if defined(__SANITIZE_ADDRESS__)
    // Open MPI still holds allocations of its components when a rank exits, and unloads
    // those components in MPI_Finalize, so LeakSanitizer's reports on the ranks cannot even
    // be symbolised, let alone suppressed: the ranks run without the exit-time leak check
    // (the later option wins); every other ASan and UBSan check stays on in them, and the
    // single-process renders of this test keep the leak check.
    const char* asan = std::getenv("ASAN_OPTIONS");
    env = "ASAN_OPTIONS='" + std::string(asan ? asan : "") + ":detect_leaks=0' ";
#endif
    const std::string cmd = env + std::string(EFFIGI_TEST_MPIEXEC) + " --oversubscribe --allow-run-as-root -np " +
                            std::to_string(n) + " " + EFFIGI_APP + " " + args + " 2>&1";
    AppResult r;
    FILE* p = popen(cmd.c_str(), "r");
    if (!p) return r;
    char buf[4096];
    for (std::size_t k; (k = fread(buf, 1, sizeof buf, p)) > 0;) r.out.append(buf, k);
    const int status = pclose(p);
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

bool haveMpi() { return std::string(EFFIGI_TEST_MPIEXEC).size() > 0; }

/// Region means of grey and the image means of R, G, B of `a` against `b` (independent
/// renders of the same scene): each difference within 4.5 standard errors, the error of a
/// region mean of the difference image taken from its pixel variance and inflated 4x for
/// the Gaussian filter's correlation of neighbouring pixels (conservative; see
/// test_checkpoint). A false alarm below 7e-6 per comparison (normal), 1e-4 over the 10.
void checkSameImage(const ExrImage& a, const ExrImage& b) {
    REQUIRE(a.pixels() == b.pixels());
    const int w = a.spec.width, h = a.spec.height;
    auto value = [](const ExrImage& img, std::size_t i, int c) {
        return c < 0 ? (img.px[3 * i] + img.px[3 * i + 1] + img.px[3 * i + 2]) / 3.0 : double(img.px[3 * i + c]);
    };
    std::vector<CornellRegion> regions = cornellRegions();
    for (int c = 0; c < 3; ++c) regions.push_back({"image channel " + std::to_string(c), 0.f, 0.f, 1.f, 1.f});
    REQUIRE(regions.size() == 10);
    for (std::size_t k = 0; k < regions.size(); ++k) {
        const CornellRegion& r = regions[k];
        const int channel = k < 7 ? -1 : int(k) - 7;
        double sum = 0, sum2 = 0, ref = 0;
        int n = 0;
        for (int y = int(r.y0 * h); y < int(r.y1 * h); ++y)
            for (int x = int(r.x0 * w); x < int(r.x1 * w); ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
                const double d = value(a, i, channel) - value(b, i, channel);
                sum += d, sum2 += d * d, ref += value(b, i, channel), ++n;
            }
        const double mean = sum / n, se = std::sqrt(4.0 * std::max(0.0, sum2 / n - mean * mean) / n);
        INFO(r.name << ": mean " << ref / n << ", difference " << mean << " ± " << se);
        CHECK(std::abs(mean) < 4.5 * se);
        CHECK(se < 0.06 * ref / n);  // sharp enough to catch a rank's sums added twice
    }
}

} // namespace

TEST_CASE("mpi: 2 and 3 ranks give the image of one process", "[mpi]") {
    if (!haveMpi()) return skipTest("effigi is built without MPI (EFFIGI_MPI off or libopenmpi-dev absent)");
    const fs::path dir = tempDir("mpi-ranks");
    const std::string common = CornellScene + " -D res=64 --spp 100 --no-progress";
    AppResult one = runApp("render " + common + " --seed 21 -o " + (dir / "one.exr").string());
    REQUIRE(one.exitCode == 0);
    const ExrImage single = readExr(dir / "one.exr");
    // Rank 0 of 2 draws a single process's 50 spp of seed 0; were rank 1 to repeat them
    // (the same seed and indices), the job's image would be exactly that one.
    AppResult half =
        runApp("render " + CornellScene + " -D res=64 --spp 50 --no-progress -o " + (dir / "half.exr").string());
    REQUIRE(half.exitCode == 0);
    const ExrImage rank0 = readExr(dir / "half.exr");
    for (int ranks : {2, 3}) {
        const fs::path out = dir / ("ranks" + std::to_string(ranks) + ".exr");
        AppResult r = runRanks(ranks, "render " + common + " -o " + out.string());
        INFO(ranks << " ranks: " << r.out);
        REQUIRE(r.exitCode == 0);
        CHECK_THAT(r.out, Catch::Contains("MPI: " + std::to_string(ranks) + " ranks"));
        // Rank 0 alone writes (the EXR and the PNG); 100 spp split 34 + 33 + 33 over 3 ranks.
        std::size_t wrote = 0;
        for (std::size_t at = 0; (at = r.out.find("wrote ", at)) != std::string::npos; ++at) ++wrote;
        CHECK(wrote == 2);
        const ExrImage img = readExr(out);
        CHECK(img.spec.get_string_attribute("effigi/samples") == std::to_string(64 * 64 * 100));
        CHECK(img.spec.get_string_attribute("effigi/spp") == "100");
        CHECK(img.spec.get_string_attribute("effigi/renderer") == single.spec.get_string_attribute("effigi/renderer"));
        checkSameImage(img, single);
        double apart = 0.0;  // mean relative difference from rank 0's samples alone
        for (std::size_t i = 0; i < img.px.size(); ++i)
            apart += std::abs(double(img.px[i]) - rank0.px[i]) / (std::abs(double(rank0.px[i])) + 1e-2);
        CHECK(apart / double(img.px.size()) > 0.01);  // float16 rounding alone: 5e-4
    }
    fs::remove_all(dir);
}

TEST_CASE("mpi: the time budget is the job's and a 3-rank checkpoint resumes in one process", "[mpi]") {
    if (!haveMpi()) return skipTest("effigi is built without MPI (EFFIGI_MPI off or libopenmpi-dev absent)");
    const fs::path dir = tempDir("mpi-budget");
    // --time 1 over 2 ranks: one second of wall time for the whole job, not per rank in turn.
    AppResult t =
        runRanks(2, "render " + CornellScene + " -D res=32 --time 1 --no-progress -o " + (dir / "t.exr").string());
    INFO(t.out);
    REQUIRE(t.exitCode == 0);
    const double seconds = std::stod(readExr(dir / "t.exr").spec.get_string_attribute("effigi/seconds"));
    CHECK(seconds > 0.5);
    CHECK(seconds < 1.9);  // passes shrink to the time left; 2 would be two budgets

    // 3 ranks render 64 spp and checkpoint (rank 0 writes the reduced sums and every
    // rank's sample count); one process continues to 128 spp from where rank 0's seed
    // stopped; against an independent single-process render.
    const fs::path ckpt = dir / "ckpt";
    AppResult a = runRanks(3, "render " + CornellScene + " -D res=64 --spp 64 --no-progress -o " +
                                  (dir / "a.exr").string() + " --checkpoint " + ckpt.string());
    INFO(a.out);
    REQUIRE(a.exitCode == 0);
    const Checkpoint c = readCheckpoint(ckpt);
    CHECK(c.report.spp == 64);
    CHECK(c.processSpp == std::vector<std::uint64_t>{22, 21, 21});
    AppResult b = runApp("render " + CornellScene + " -D res=64 --spp 128 --no-progress -o " +
                         (dir / "b.exr").string() + " --resume " + ckpt.string());
    INFO(b.out);
    REQUIRE(b.exitCode == 0);
    AppResult ref = runApp("render " + CornellScene + " -D res=64 --spp 128 --seed 5 --no-progress -o " +
                           (dir / "ref.exr").string());
    REQUIRE(ref.exitCode == 0);
    const ExrImage img = readExr(dir / "b.exr");
    CHECK(img.spec.get_string_attribute("effigi/samples") == std::to_string(64 * 64 * 128));
    checkSameImage(img, readExr(dir / "ref.exr"));
    fs::remove_all(dir);
}
