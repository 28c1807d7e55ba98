// Start-up cost of the effigi app (issue 11): a render written to EXR (with its PNG
// preview), --dry-run, info, list and converge against an EXR reference load no
// OpenImageIO library; a reference in another format loads it on demand, through the
// app's image-oiio module.
//
// What the process loads is read from the dynamic loader's own trace (glibc's
// LD_DEBUG=files, written to a file by LD_DEBUG_OUTPUT), not from the test process:
// the test executables link OpenImageIO themselves. Each check also requires the trace
// to name libraries that must be there (libeffigi, the film module), so a trace that
// is empty or unreadable fails instead of passing, and one case requires OpenImageIO to
// appear, so the check is seen to detect it.
#include "app_runner.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

using namespace effigi::test;
namespace fs = std::filesystem;

namespace {

// A grey plane under a white sky (test_converge's scene); 8x8 pixels, 1 spp.
const std::string Plane = EFFIGI_SOURCE_DIR "/tests/data/converge/plane.xml";
const std::string Tiny = " -D res=8 -D spp=1 --no-progress";

struct Traced {
    AppResult app;
    std::string loader;  // the loader's trace of the effigi process
};

/// Runs effigi with the loader tracing every shared object it opens into dir/ld.<pid>.
Traced runTraced(const fs::path& dir, const std::string& args) {
    for (const auto& f : fs::directory_iterator(dir))
        if (f.path().filename().string().rfind("ld.", 0) == 0) fs::remove(f.path());
    // The variables prefix the effigi command only, so the shell popen starts is not traced.
    const std::string cmd =
        "LD_DEBUG=files LD_DEBUG_OUTPUT=" + (dir / "ld").string() + " " + EFFIGI_APP + " " + args + " 2>&1";
    Traced t;
    if (FILE* p = popen(cmd.c_str(), "r")) {
        char buf[4096];
        std::size_t n;
        while ((n = fread(buf, 1, sizeof buf, p)) > 0) t.app.out.append(buf, n);
        const int status = pclose(p);
        t.app.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }
    for (const auto& f : fs::directory_iterator(dir))
        if (f.path().filename().string().rfind("ld.", 0) == 0) {
            std::ostringstream ss;
            ss << std::ifstream(f.path()).rdbuf();
            t.loader += ss.str();
        }
    return t;
}

bool loaded(const Traced& t, const std::string& library) { return t.loader.find(library) != std::string::npos; }

/// The command succeeded, the trace is real (libeffigi is in it) and has no OpenImageIO.
void requireNoOpenImageIO(const Traced& t) {
    INFO(t.app.out);
    REQUIRE(t.app.exitCode == 0);
    REQUIRE(loaded(t, "libeffigi.so"));
    CHECK_FALSE(loaded(t, "libOpenImageIO"));
}

} // namespace

TEST_CASE("startup: a render to EXR and its PNG preview loads no OpenImageIO", "[startup][cli]") {
    const fs::path dir = tempDir("startup-render");
    const Traced t = runTraced(dir, "render " + Plane + " -o " + (dir / "x.exr").string() + Tiny);
    requireNoOpenImageIO(t);
    CHECK(loaded(t, "film-hdrfilm.so"));  // the film module that wrote both files ran
    CHECK_FALSE(loaded(t, "libcpp-httplib"));  // nor the live preview's server (render --preview only)
    CHECK_FALSE(loaded(t, "libmpi"));          // nor MPI (ranks-mpi.so: under mpirun only)
    CHECK(fs::exists(dir / "x.exr"));
    CHECK(fs::exists(dir / "x.png"));
    fs::remove_all(dir);
}

TEST_CASE("startup: --dry-run, info, list and an EXR reference load no OpenImageIO", "[startup][cli]") {
    const fs::path dir = tempDir("startup-commands");
    requireNoOpenImageIO(runTraced(dir, "render " + Plane + " --dry-run" + Tiny));
    requireNoOpenImageIO(runTraced(dir, "info film/hdrfilm"));
    requireNoOpenImageIO(runTraced(dir, "list"));

    // converge reads an EXR reference (with OpenEXR) and writes PNG reports.
    REQUIRE(runApp("render " + Plane + " -o " + (dir / "ref.exr").string() + Tiny).exitCode == 0);
    const Traced c = runTraced(dir, "converge " + Plane + " --reference " + (dir / "ref.exr").string() + " --spp 1 --out " +
                                        (dir / "conv").string() + Tiny);
    requireNoOpenImageIO(c);
    CHECK(fs::exists(dir / "conv" / "scene.png"));
    CHECK(fs::exists(dir / "conv" / "scene-error.png"));
    fs::remove_all(dir);
}

TEST_CASE("startup: a PNG reference loads OpenImageIO on demand", "[startup][cli]") {
    const fs::path dir = tempDir("startup-png");
    REQUIRE(runApp("render " + Plane + " -o " + (dir / "ref.exr").string() + Tiny).exitCode == 0);
    const Traced t = runTraced(dir, "converge " + Plane + " --reference " + (dir / "ref.png").string() +
                                        " --spp 1 --out " + (dir / "conv").string() + Tiny);
    INFO(t.app.out);
    CHECK(t.app.exitCode == 0);
    CHECK(loaded(t, "image-oiio.so"));
    CHECK(loaded(t, "libOpenImageIO"));
    CHECK(fs::exists(dir / "conv" / "scene-error.png"));
    fs::remove_all(dir);
}

TEST_CASE("startup: an unreadable reference is one line naming the file", "[startup][cli]") {
    const fs::path dir = tempDir("startup-errors");
    std::ofstream(dir / "broken.png") << "not an image";
    std::ofstream(dir / "broken.exr") << "not an image";
    // Missing, a broken EXR (OpenEXR's reader) and a broken PNG (OpenImageIO's, in the module).
    for (const std::string name : {"missing.exr", "broken.exr", "broken.png"}) {
        const fs::path ref = dir / name;
        const AppResult r = runApp("converge " + Plane + " --reference " + ref.string() + " --spp 1 --out " +
                                   (dir / "conv").string() + Tiny);
        INFO(r.out);
        CHECK(r.exitCode == 1);
        CHECK(std::count(r.out.begin(), r.out.end(), '\n') == 1);
        CHECK(r.out.rfind("error: " + ref.string() + ": cannot read image: ", 0) == 0);
    }
    fs::remove_all(dir);
}
