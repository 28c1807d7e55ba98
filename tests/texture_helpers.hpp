#pragma once
// Helpers shared by the texture tests (test_textures, test_textures_procedural): the test
// data folder, creating a texture through the registry, and an interaction at given uv.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/itexture.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <string>

namespace effigi::test {

inline const std::filesystem::path DataDir = EFFIGI_SOURCE_DIR "/tests/data/textures";

inline Ref<ITexture> makeTexture(const std::string& type, Properties p) {
    Ref<ITexture> t = query<ITexture>(Registry::instance().create("texture", type, p));
    REQUIRE(t);
    return t;
}

inline SurfaceInteraction at(float u, float v) {
    SurfaceInteraction si;
    si.uv = Point2f(u, v);
    return si;
}

} // namespace effigi::test
