// effigi render --frames A:B (apps/effigi/render_frames.cpp): one image per frame with
// $frame set, named by the -o pattern; a frame equals a single render with the same
// -D frame (same seed, one thread: the same samples summed in the same order).
#include "app_runner.hpp"
#include "image_helpers.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>

using namespace effigi::test;

namespace {

/// A sphere that moves with $frame, lit by a constant environment.
std::filesystem::path writeScene(const std::filesystem::path& dir) {
    const auto path = dir / "frames.xml";
    std::ofstream(path) << R"(<scene version="3.0.0"><default name="frame" value="0"/>
        <sensor type="perspective"><float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="0, 0, 6" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="12"/></film></sensor>
        <emitter type="constant"><rgb name="radiance" value="1"/></emitter>
        <shape type="sphere"><float name="radius" value="0.5"/>
          <transform name="to_world"><translate x="$frame" y="-1"/><scale value="0.2"/></transform></shape></scene>)";
    return path;
}

} // namespace

TEST_CASE("frames: a 24-frame sequence is written, one file per frame", "[frames][app]") {
    const auto dir = tempDir("frames-seq");
    const auto scene = writeScene(dir);
    const AppResult r = runApp("render " + scene.string() + " --frames 0:23 -t 1 --no-progress -o " +
                               (dir / "shot_{frame:02}.exr").string());
    INFO(r.out);
    REQUIRE(r.exitCode == 0);
    for (int f = 0; f < 24; ++f) CHECK(std::filesystem::exists(dir / fmt::format("shot_{:02}.exr", f)));
    CHECK(!std::filesystem::exists(dir / "shot_24.exr"));
    // Without a pattern the number goes before the extension.
    REQUIRE(runApp("render " + scene.string() + " --frames 3:4 --no-progress -o " + (dir / "plain.exr").string())
                .exitCode == 0);
    CHECK(std::filesystem::exists(dir / "plain_0003.exr"));
    CHECK(std::filesystem::exists(dir / "plain_0004.exr"));
    std::filesystem::remove_all(dir);
}

TEST_CASE("frames: one frame equals a single render with the same $frame", "[frames][app]") {
    const auto dir = tempDir("frames-one");
    const auto scene = writeScene(dir);
    REQUIRE(runApp("render " + scene.string() + " --frames 5:7 -t 1 --no-progress -o " + (dir / "f.exr").string())
                .exitCode == 0);
    REQUIRE(runApp("render " + scene.string() + " -D frame=6 -t 1 --no-progress -o " + (dir / "single.exr").string())
                .exitCode == 0);
    const ExrImage a = readExr(dir / "f_0006.exr"), b = readExr(dir / "single.exr"), c = readExr(dir / "f_0005.exr");
    REQUIRE(a.px.size() == b.px.size());
    double worst = 0.0, moved = 0.0;
    for (std::size_t i = 0; i < a.px.size(); ++i) {
        worst = std::max(worst, double(std::abs(a.px[i] - b.px[i])));
        moved = std::max(moved, double(std::abs(a.px[i] - c.px[i])));
    }
    CHECK(worst <= 1e-6);
    CHECK(moved > 0.1);  // frame 5's sphere is elsewhere: the frames differ
    std::filesystem::remove_all(dir);
}

TEST_CASE("frames: bad ranges and combinations are one-line errors", "[frames][app]") {
    const auto dir = tempDir("frames-bad");
    const auto scene = writeScene(dir).string();
    for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
             {"--frames 5:2", "--frames expects A:B"},
             {"--frames x", "--frames expects A:B"},
             {"--frames 0:1 -D frame=3", "--frames sets $frame itself"},
             {"--frames 0:1 --checkpoint " + dir.string(), "cannot be combined with --frames"},
             {"--frames 0:1 -o " + (dir / "f_{frame:q}.exr").string(), "not a valid {frame} pattern"}}) {
        const AppResult r = runApp("render " + scene + " --no-progress " + args);
        INFO(args << ": " << r.out);
        CHECK(r.exitCode == 1);
        CHECK(r.out.find(message) != std::string::npos);
    }
    std::filesystem::remove_all(dir);
}
