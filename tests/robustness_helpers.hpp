#pragma once
// Shared by the robustness tests (issue 12): a small scene to vary, load errors checked
// for file:line and words, one-line app errors, image checks.
#include "app_runner.hpp"
#include "film_helpers.hpp"
#include "image_helpers.hpp"
#include "shape_helpers.hpp"
#include "scene_text.hpp"
#include "skip.hpp"
#include "xml_helpers.hpp"

#include "effigi/interfaces/icamera.hpp"
#include "effigi/render/image_block.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <catch2/catch.hpp>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

namespace effigi::test {

namespace fs = std::filesystem;
using Catch::Contains;


inline const std::string kFile = "robust.xml";

inline std::unique_ptr<Scene> load(const std::string& text) { return loadScene(*xml::parseString(text, kFile)); }

/// 1-based line of the first occurrence of marker in text (where an error must point).
inline int lineOf(const std::string& text, const std::string& marker) {
    std::size_t at = text.find(marker);
    REQUIRE(at != std::string::npos);
    return 1 + int(std::count(text.begin(), text.begin() + std::ptrdiff_t(at), '\n'));
}

inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
    std::size_t at = text.find(from);
    REQUIRE(at != std::string::npos);
    return text.replace(at, from.size(), to);
}

/// A small scene; PARTS is replaced by the case's elements, CAMERA by the sensor's
/// transform, RENDERER by the renderer element.
inline const std::string kScene = R"(<scene version="3.0.0">
    RENDERER
    <sensor type="perspective">
        <float name="far_clip" value="1e18"/>
        CAMERA
        <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film>
    </sensor>
    PARTS
</scene>
)";

/// kScene with these parts; `renderer` is a type ("path") or a whole <integrator> element.
inline std::string scene(const std::string& parts, const std::string& camera = "",
                  const std::string& renderer = "path") {
    std::string cam = camera.empty()
                          ? R"(<transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>)"
                          : camera;
    std::string r = renderer.rfind('<', 0) == 0 ? renderer : R"(<integrator type=")" + renderer + R"("/>)";
    return replaced(replaced(replaced(kScene, "PARTS", parts), "CAMERA", cam), "RENDERER", r);
}

/// The load error of `text`: located at kFile:line of `marker`, mentioning each of `words`.
inline void expectLoadError(const std::string& text, const std::string& marker, const std::vector<std::string>& words) {
    std::string msg = errorOf([&] { load(text); });
    INFO(msg);
    CHECK(msg.find('\n') == std::string::npos);
    CHECK(msg.rfind(kFile + ":" + std::to_string(lineOf(text, marker)) + ":", 0) == 0);
    for (const auto& w : words) CHECK_THAT(msg, Contains(w));
}

inline double imageMean(const Image& img) {
    double sum = 0.0;
    for (float v : img.pixels) sum += v;
    return img.pixels.empty() ? 0.0 : sum / double(img.pixels.size());
}

/// The app's output: exactly one line, the error, starting with `start`.
inline void expectOneLineError(const AppResult& r, const std::string& start) {
    INFO(r.out);
    CHECK(r.exitCode == 1);
    CHECK(std::count(r.out.begin(), r.out.end(), '\n') == 1);
    CHECK(r.out.rfind("error: " + start, 0) == 0);
}

inline double physicalMemory() {
    return double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGESIZE));
}


} // namespace effigi::test
