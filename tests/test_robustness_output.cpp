// Issue 12, defect 6: an output path that cannot be written (a file as folder, /proc, no
// permission) fails before the render, with one line naming the path; existing files and
// folders are left as they are.
#include "robustness_helpers.hpp"

using namespace effigi;
using namespace effigi::test;

namespace {

/// A valid scene file in `dir`; returns its path.
fs::path validScene(const fs::path& dir) {
    fs::path p = dir / "scene.xml";
    std::ofstream(p) << scene(R"(<shape type="sphere"><emitter type="area"/></shape>)");
    return p;
}

} // namespace

TEST_CASE("robustness: an output path that cannot be written fails before the render", "[robustness][output]") {
    fs::path dir = tempDir("robust-out");
    const fs::path s = validScene(dir);
    std::ofstream(dir / "file") << "a regular file";
    for (const char* extra : {"--no-progress", "--dry-run"}) {  // a dry run reports it too: nothing rendered first
        INFO(extra);
        SECTION(std::string("a regular file used as a folder, ") + extra) {
            AppResult r = runApp("render " + s.string() + " -o " + (dir / "file/out.exr").string() + " " + extra);
            expectOneLineError(r, "cannot write " + (dir / "file/out.exr").string() + ": '" + (dir / "file").string() +
                                      "' is not a folder");
        }
        SECTION(std::string("a path under /proc, ") + extra) {
            AppResult r = runApp("render " + s.string() + " -o /proc/effigi-robust.exr " + extra);
            expectOneLineError(r, "cannot write /proc/effigi-robust.exr: ");
        }
        SECTION(std::string("a folder where the PNG goes, ") + extra) {
            fs::create_directories(dir / "taken.png");
            AppResult r = runApp("render " + s.string() + " -o " + (dir / "taken.exr").string() + " " + extra);
            expectOneLineError(r, "cannot write " + (dir / "taken.png").string() + ": it is a folder");
            CHECK_FALSE(fs::exists(dir / "taken.exr"));
        }
    }
    fs::remove_all(dir);
}

TEST_CASE("robustness: an output folder without write permission fails before the render", "[robustness][output]") {
    if (::geteuid() == 0) return skipTest("root writes into any folder");
    fs::path dir = tempDir("robust-locked");
    const fs::path s = validScene(dir);
    fs::create_directories(dir / "locked");
    fs::permissions(dir / "locked", fs::perms::owner_read | fs::perms::owner_exec);
    AppResult r = runApp("render " + s.string() + " -o " + (dir / "locked/out.exr").string() + " --dry-run");
    fs::permissions(dir / "locked", fs::perms::owner_all);
    expectOneLineError(r, "cannot write " + (dir / "locked/out.exr").string() + ": Permission denied");
    fs::remove_all(dir);
}

TEST_CASE("robustness: the output check leaves existing files and folders as they are", "[robustness][output]") {
    fs::path dir = tempDir("robust-probe");
    const fs::path s = validScene(dir);
    std::ofstream(dir / "old.exr") << "keep";
    AppResult r = runApp("render " + s.string() + " -o " + (dir / "old.exr").string() + " --dry-run");
    INFO(r.out);
    CHECK(r.exitCode == 0);
    CHECK(readText(dir / "old.exr") == "keep");
    CHECK_FALSE(fs::exists(dir / "old.png"));  // the probe file is gone again
    // A dry run creates no folder either.
    r = runApp("render " + s.string() + " -o " + (dir / "new/sub/out.exr").string() + " --dry-run");
    CHECK(r.exitCode == 0);
    CHECK_FALSE(fs::exists(dir / "new"));
    fs::remove_all(dir);
}

TEST_CASE("robustness: converge checks its output folder before rendering", "[robustness][output]") {
    fs::path dir = tempDir("robust-converge");
    const fs::path s = validScene(dir);
    std::ofstream(dir / "file") << "a regular file";
    AppResult r = runApp("converge " + s.string() + " --spp 1 --no-progress --out " + (dir / "file").string());
    expectOneLineError(r, "cannot write " + (dir / "file/convergence.csv").string() + ": '" +
                              (dir / "file").string() + "' is not a folder");
    CHECK(r.out.find("configuration") == std::string::npos);  // nothing was rendered
    fs::remove_all(dir);
}
