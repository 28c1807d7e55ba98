// Mitsuba scene-format compatibility of the XML reader for version < 3 files: names from
// the upgrade table or camelCase -> snake_case, renamed elements and attributes, the
// plugin-specific renames of version < 2, and a Mitsuba 0.6 scene loading with the real
// components. Errors name file:line and the culprit.
#include "xml_compat_helpers.hpp"
#include "xml_helpers.hpp"

#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <catch2/catch.hpp>

#include <string>
#include <utility>
#include <vector>

using namespace effigi;
using namespace effigi::xml;
using namespace effigi::test;
using Catch::Contains;

TEST_CASE("xml compat: version < 3 names come from the table, else camelCase -> snake_case", "[xml]") {
    // Old name -> Mitsuba 3 name, for names written as <float name="...">.
    const std::vector<std::pair<std::string, std::string>> names = {
        {"toWorld", "to_world"},
        {"sampleCount", "sample_count"},
        {"maxDepth", "max_depth"},
        {"rrDepth", "rr_depth"},
        {"intIOR", "int_ior"},
        {"extIOR", "ext_ior"},
        {"fovAxis", "fov_axis"},
        {"nearClip", "near_clip"},
        {"farClip", "far_clip"},
        {"diffuseReflectance", "diffuse_reflectance"},
        {"specularReflectance", "specular_reflectance"},
        {"specularTransmittance", "specular_transmittance"},
        {"alphaU", "alpha_u"},
        {"cropOffsetX", "crop_offset_x"},
        {"pixelFormat", "pixel_format"},
        {"highQualityEdges", "sample_border"},  // renamed, not mechanical
        {"densityMultiplier", "scale"},         // renamed, not mechanical
        {"someNewName", "some_new_name"},       // not in the table: mechanical
        {"radius", "radius"},
    };
    for (const char* version : {"0.5.0", "0.6.0", "2.1.0"}) {
        std::string body;
        for (const auto& [from, to] : names) body += "<float name=\"" + from + "\" value=\"1\"/>";
        auto root = parseString(fmt::format("<scene version=\"{}\"><bsdf type=\"x\" id=\"b\">{}</bsdf></scene>",
                                            version, body),
                                "old.xml");
        const Node& b = *root->children.at(0).node;
        for (const auto& [from, to] : names) {
            INFO(version << ": " << from << " -> " << to);
            CHECK(b.props.has(to));
        }
    }
    // Version 3 keeps names as written: a camelCase name there is the user's typo.
    auto v3 = parseString(R"(<scene version="3.0.0"><bsdf type="x" id="b"><float name="intIOR" value="1"/></bsdf></scene>)",
                          "new.xml");
    CHECK(v3->children.at(0).node->props.has("intIOR"));
}

TEST_CASE("xml compat: version < 3 elements, attributes and plugin-specific renames", "[xml]") {
    auto root = parseString(R"(<scene version="0.6.0">
    <sensor type="perspective" id="cam">
        <transform name="toWorld">
            <lookAt origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/>
        </transform>
    </sensor>
    <emitter type="constant" id="sky">
        <blackbody name="radiance" temperature="5000K" multiplier="2"/>
    </emitter>
    <bsdf type="diffuse" id="white">
        <rgb name="diffuseReflectance" value="0.5"/>
    </bsdf>
    <texture type="checkerboard" id="tex">
        <float name="uoffset" value="0.5"/>
        <float name="uscale" value="4"/>
        <float name="vscale" value="2"/>
    </texture>
</scene>)",
                            "v06.xml");
    // <lookAt> is <lookat>: the camera looks down -z from (0, 0, 4).
    const Transform& cam = value<Transform>(byId(*root, "cam"), "to_world");
    Point3f origin = cam.point(Point3f(0.f));
    CHECK(origin.z == Approx(4.f));
    // <blackbody multiplier> is scale.
    CHECK(value<SpectrumValue>(byId(*root, "sky"), "radiance").scale == Approx(2.f));
    // Version < 2: diffuse's diffuseReflectance is reflectance (as Mitsuba 3 upgrades it).
    CHECK(byId(*root, "white").props.has("reflectance"));
    CHECK_FALSE(byId(*root, "white").props.has("diffuse_reflectance"));
    // uoffset/uscale/vscale fold into to_uv = scale(4, 2) * translate(0.5, 0).
    const Node& tex = byId(*root, "tex");
    CHECK_FALSE(tex.props.has("uoffset"));
    Point3f uv = value<Transform>(tex, "to_uv").point(Point3f(0.f, 0.f, 0.f));
    CHECK(uv.x == Approx(2.f));
    CHECK(uv.y == Approx(0.f));
    Point3f uv1 = value<Transform>(tex, "to_uv").point(Point3f(1.f, 1.f, 0.f));
    CHECK(uv1.x == Approx(6.f));
    CHECK(uv1.y == Approx(2.f));

    // A 2.x file keeps diffuse_reflectance as written (Mitsuba upgrades only < 2.0).
    auto v2 = parseString(R"(<scene version="2.1.0"><bsdf type="diffuse" id="w">
        <rgb name="diffuse_reflectance" value="0.5"/></bsdf></scene>)",
                          "v2.xml");
    CHECK(v2->children.at(0).node->props.has("diffuse_reflectance"));
    // A zero uscale would make to_uv singular: an error at its line.
    std::string msg = errorOf([] {
        parseString(R"(<scene version="0.6.0"><texture type="bitmap" id="t">
        <float name="uscale" value="0"/></texture></scene>)",
                    "zero.xml");
    });
    CHECK_THAT(msg, Contains("zero.xml:2:"));
    CHECK_THAT(msg, Contains("uscale"));
}

TEST_CASE("xml compat: a Mitsuba 0.6 scene loads with the real components", "[xml]") {
    auto scene = loadSceneFile(kCompat / "old/scene06.xml");
    CHECK(scene->shapes().size() == 2);
    CHECK(scene->emitters().size() == 1);
}
