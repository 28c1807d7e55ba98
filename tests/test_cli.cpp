// The effigi app end to end: bad input gives one line naming file, line and parameter,
// and exit code 1; list/info work; SIGINT still writes the image.
#include "app_runner.hpp"

#include <catch2/catch.hpp>

#include <csignal>
#include <fstream>
#include <string>
#include <thread>
#include <fcntl.h>
#include <unistd.h>

using namespace effigi::test;
namespace fs = std::filesystem;

namespace {

// A small valid scene; each bad-input case replaces one part of it.
const char* ValidScene = R"(<scene version="3.0.0">
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="1"/></sampler>
        <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
    </sensor>
    SHAPE
</scene>
)";

fs::path writeScene(const fs::path& dir, const std::string& shape) {
    std::string text = ValidScene;
    text.replace(text.find("SHAPE"), 5, shape);
    fs::path p = dir / "scene.xml";
    std::ofstream(p) << text;
    return p;
}

// One bad-input class: the message is one line, starts with file:line, mentions `what`.
void expectError(const std::string& shape, int line, const std::string& what, const std::string& extraArgs = "") {
    fs::path dir = tempDir("cli");
    fs::path scene = writeScene(dir, shape);
    AppResult r = runApp("render " + scene.string() + " -o " + (dir / "out.exr").string() + " " + extraArgs);
    INFO(r.out);
    CHECK(r.exitCode == 1);
    CHECK(std::count(r.out.begin(), r.out.end(), '\n') == 1);
    CHECK(r.out.find("error: " + scene.string() + ":" + std::to_string(line)) == 0);
    CHECK(r.out.find(what) != std::string::npos);
    CHECK_FALSE(fs::exists(dir / "out.exr"));
    fs::remove_all(dir);
}

} // namespace

TEST_CASE("cli: a valid scene renders and reports throughput", "[cli]") {
    fs::path dir = tempDir("cli-ok");
    fs::path scene = writeScene(dir, R"(<shape type="sphere"><emitter type="area"/></shape>)");
    AppResult r = runApp("render " + scene.string() + " -o " + (dir / "ok.exr").string() + " -v --no-progress");
    INFO(r.out);
    CHECK(r.exitCode == 0);
    CHECK(fs::exists(dir / "ok.exr"));
    CHECK(fs::exists(dir / "ok.png"));
    CHECK(r.out.find("M samples/s") != std::string::npos);
    CHECK(r.out.find("0 NaN/Inf samples rejected") != std::string::npos);
    CHECK(r.out.find("shape-sphere.so") != std::string::npos);  // -v lists modules
    CHECK(r.out.find("shape-rectangle.so") == std::string::npos);
    fs::remove_all(dir);
}

TEST_CASE("cli: malformed XML", "[cli]") { expectError("<shape type=\"sphere\">\n</shap>", 9, "malformed XML"); }

TEST_CASE("cli: unknown component", "[cli]") {
    expectError(R"(<shape type="sphere"><bsdf type="difuse"/></shape>)", 8, "did you mean 'diffuse'");
}

TEST_CASE("cli: unknown parameter", "[cli]") {
    expectError(R"(<shape type="sphere"><float name="radus" value="1"/></shape>)", 8, "did you mean 'radius'");
}

TEST_CASE("cli: wrong parameter type", "[cli]") {
    expectError(R"(<shape type="sphere"><string name="radius" value="big"/></shape>)", 8,
                "'radius' must be a float, got string");
}

TEST_CASE("cli: parameter out of range", "[cli]") {
    expectError(R"(<shape type="sphere"><bsdf type="diffuse"><float name="reflectance" value="1.5"/></bsdf></shape>)",
                8, "reflectance");
}

TEST_CASE("cli: NaN in a transform", "[cli]") {
    expectError(R"(<shape type="sphere"><transform name="to_world"><translate value="0, nan, 0"/></transform></shape>)",
                8, "translate");
}

TEST_CASE("cli: missing mesh file", "[cli]") {
    expectError(R"(<shape type="ply"><string name="filename" value="nowhere.ply"/></shape>)", 8, "nowhere.ply");
    expectError(R"(<shape type="obj"><string name="filename" value="nowhere.obj"/></shape>)", 8, "nowhere.obj");
}

TEST_CASE("cli: corrupt mesh file", "[cli]") {
    fs::path dir = tempDir("cli-mesh");
    std::ofstream(dir / "bad.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                      "property float y\nproperty float z\nelement face 1\n"
                                      "property list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n";
    fs::path scene = writeScene(dir, R"(<shape type="ply"><string name="filename" value="bad.ply"/></shape>)");
    AppResult r = runApp("render " + scene.string() + " -o " + (dir / "o.exr").string());
    INFO(r.out);
    CHECK(r.exitCode == 1);
    CHECK(std::count(r.out.begin(), r.out.end(), '\n') == 1);
    CHECK(r.out.find("bad.ply") != std::string::npos);
    fs::remove_all(dir);
}

TEST_CASE("cli: undefined variable and unknown -D", "[cli]") {
    expectError(R"(<shape type="sphere"><float name="radius" value="$r"/></shape>)", 8, "$r");
    fs::path dir = tempDir("cli-define");
    fs::path scene = writeScene(dir, R"(<shape type="sphere"/>)");
    AppResult r = runApp("render " + scene.string() + " -D spp=4 -o " + (dir / "o.exr").string());
    CHECK(r.exitCode == 1);
    CHECK(r.out.find("spp") != std::string::npos);
    fs::remove_all(dir);
}

TEST_CASE("cli: bad command line", "[cli]") {
    CHECK(runApp("render").exitCode == 1);
    CHECK(runApp("render a.xml b.xml").exitCode == 1);
    CHECK(runApp("render -t many x.xml").exitCode == 1);
    AppResult r = runApp("render /nonexistent/scene.xml");
    CHECK(r.exitCode == 1);
    CHECK(r.out.find("/nonexistent/scene.xml") != std::string::npos);
}

TEST_CASE("cli: list and info come from the manifest and schemas", "[cli]") {
    AppResult list = runApp("list");
    CHECK(list.exitCode == 0);
    // One line per tag, names sorted: the accelerator line holds at least these two.
    const std::size_t acc = list.out.find("accelerator  ");
    REQUIRE(acc != std::string::npos);
    const std::string line = list.out.substr(acc, list.out.find('\n', acc) - acc);
    CHECK(line.find(" bruteforce ") != std::string::npos);
    CHECK(line.find(" embree") != std::string::npos);
    AppResult info = runApp("info bsdf/diffuse");
    CHECK(info.exitCode == 0);
    CHECK(info.out.find("reflectance") != std::string::npos);
    AppResult md = runApp("info --markdown");
    CHECK(md.exitCode == 0);
    CHECK(md.out.find("### `shape/sphere`") != std::string::npos);
    CHECK(md.out.find("| `radius` |") != std::string::npos);
    CHECK(runApp("info bsdf/nothing").exitCode == 1);
}

TEST_CASE("cli: docs/components.md is what the schemas generate", "[cli]") {
    AppResult md = runApp("info --markdown");
    std::ifstream in(EFFIGI_SOURCE_DIR "/docs/components.md");
    std::string committed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    INFO("regenerate with: make docs");
    CHECK(md.out == committed);
}

TEST_CASE("cli: SIGINT writes the partial image", "[cli]") {
    fs::path dir = tempDir("cli-sigint");
    fs::path out = dir / "partial.exr";
    pid_t pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        int devnull = open("/dev/null", O_WRONLY);
        dup2(devnull, 1);
        dup2(devnull, 2);
        std::string scene = EFFIGI_SOURCE_DIR "/scenes/cornell-box/scene.xml";
        execl(EFFIGI_APP, EFFIGI_APP, "render", scene.c_str(), "-D", "spp=100000", "-o", out.c_str(), (char*)nullptr);
        _exit(127);
    }
    // Wait until the app has installed its SIGINT handler (the caught-signal mask in
    // /proc), not a fixed time: a loaded machine or a sanitizer build starts slowly, and a
    // signal before the handler would kill the app instead of testing it.
    // Until exec the child is a copy of this test, whose Catch2 handler catches SIGINT
    // too, so the mask only counts once /proc/<pid>/exe is the app.
    const fs::path app = fs::canonical(EFFIGI_APP);
    const fs::path proc = "/proc/" + std::to_string(pid);
    bool caught = false;
    for (int i = 0; i < 6000 && !caught; ++i) {
        std::error_code ec;
        if (fs::read_symlink(proc / "exe", ec) != app) {
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
            continue;
        }
        std::ifstream status(proc / "status");
        for (std::string line; std::getline(status, line);)
            if (line.rfind("SigCgt:", 0) == 0) caught = (std::stoull(line.substr(7), nullptr, 16) >> (SIGINT - 1)) & 1;
        if (!caught) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    CHECK(caught);
    std::this_thread::sleep_for(std::chrono::milliseconds(500));  // let it render a little
    kill(pid, SIGINT);
    int status = 0;
    waitpid(pid, &status, 0);
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 130);
    CHECK(fs::exists(out));
    fs::remove_all(dir);
}
