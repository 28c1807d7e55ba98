#pragma once
// Scenes edited as text before loading, for the renderer tests that render a committed
// scene with another integrator or an extra element (test_photonmap, test_sppm,
// test_ptracer, test_renderers_extra, test_camera_importance).
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/render/scene.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>

#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace effigi::test {

inline std::string readText(const std::filesystem::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

using TextEdits = std::vector<std::pair<std::string, std::string>>;

/// Scene `file` with each (from, to) of `edits` applied to its first occurrence (which
/// must exist), parsed with `defines` (file names resolve against `file`) and loaded.
inline std::unique_ptr<Scene> loadEdited(const std::string& file, const TextEdits& edits,
                                         std::map<std::string, std::string> defines = {}) {
    std::string text = readText(file);
    for (const auto& [from, to] : edits) {
        auto at = text.find(from);
        INFO("edit of " << file << ": " << from);
        REQUIRE(at != std::string::npos);
        text.replace(at, from.size(), to);
    }
    xml::ParseOptions opt;
    opt.defines = std::move(defines);
    return loadScene(*xml::parseString(text, file, opt));
}

/// Scene `file` with its <integrator …> element (self-closing or not) replaced by the XML
/// `integrator`, then `edits` applied.
inline std::unique_ptr<Scene> loadWithIntegrator(const std::string& file, const std::string& integrator,
                                                 std::map<std::string, std::string> defines = {},
                                                 const TextEdits& edits = {}) {
    const std::string text = readText(file);
    const auto a = text.find("<integrator");
    REQUIRE(a != std::string::npos);
    const auto close = text.find('>', a);
    const auto end = text[close - 1] == '/' ? close + 1 : text.find("</integrator>", a) + 13;
    TextEdits all{{text.substr(a, end - a), integrator}};
    all.insert(all.end(), edits.begin(), edits.end());
    return loadEdited(file, all, std::move(defines));
}

/// `scene` rendered with `seed` and no progress bar (other settings from `control`): the
/// developed image, and the render's statistics in *stats when asked.
inline Image renderSeeded(Scene& scene, std::uint64_t seed, RenderStats* stats = nullptr, RenderControl control = {}) {
    control.progress = false;
    control.seed = seed;
    RenderStats s = scene.renderer().render(scene, control);
    if (stats) *stats = s;
    return scene.camera().film().develop();
}

/// True when no pixel value is NaN or infinite (saturated colours may be negative in RGB).
inline bool allFinite(const Image& img) {
    for (float v : img.pixels)
        if (!std::isfinite(v)) return false;
    return true;
}

} // namespace effigi::test
