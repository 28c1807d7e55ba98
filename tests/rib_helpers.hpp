#pragma once
// Helpers of the RIB tests (test_rib, test_rib_errors): RIB text loaded as a scene, or
// interpreted only (the translator's SceneSpec, src/rib/state.hpp: the elements it makes,
// before any component exists), and the message of the error a text raises.
#include "../src/rib/state.hpp"
#include "xml_helpers.hpp"

#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/iemitter.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/rib/loader.hpp"

#include <catch2/catch.hpp>

#include <map>
#include <memory>
#include <string>

namespace effigi::test {

/// A 32 x 24 perspective frame around `body`, which starts on line 4 of the text.
inline std::string ribWorld(const std::string& body) {
    return "Format 32 24 1\nProjection \"perspective\" \"fov\" 40\nWorldBegin\n" + body + "\nWorldEnd\n";
}

inline std::unique_ptr<Scene> loadRib(const std::string& text, std::map<std::string, std::string> defines = {}) {
    xml::ParseOptions opt;
    opt.defines = std::move(defines);
    return rib::loadString(text, "t.rib", opt);
}

inline rib::SceneSpec ribSpec(const std::string& text) { return rib::interpret(text, "t.rib"); }

inline std::string ribError(const std::string& text, std::map<std::string, std::string> defines = {}) {
    return errorOf([&] { loadRib(text, std::move(defines)); });
}

/// The only shape of a scene.
inline const IShape& onlyShape(const Scene& scene) {
    REQUIRE(scene.shapes().size() == 1);
    return *scene.shapes()[0];
}

/// The BSDF element under the twosided wrapper the translator puts around every surface.
inline const xml::Node& innerBsdf(const xml::Node& bsdf) {
    REQUIRE(bsdf.type == "twosided");
    REQUIRE(bsdf.children.size() == 1);
    return *bsdf.children[0].node;
}

/// The vector of an element's rgb parameter.
inline Vector3f rgbOf(const xml::Node& n, const std::string& name) {
    const Properties::Entry* e = n.props.find(name);
    REQUIRE(e);
    REQUIRE(std::holds_alternative<RGBValue>(e->value));
    return std::get<RGBValue>(e->value).v;
}

inline void checkVec(const Vector3f& a, const Vector3f& b, float eps = 1e-4f) {
    INFO("(" << a.x << ", " << a.y << ", " << a.z << ") vs (" << b.x << ", " << b.y << ", " << b.z << ")");
    CHECK(a.x == Approx(b.x).margin(eps));
    CHECK(a.y == Approx(b.y).margin(eps));
    CHECK(a.z == Approx(b.z).margin(eps));
}

} // namespace effigi::test
