// XML scene parser, bad input: one test section per class of error, each checking that
// the message names the file, the line and the offending name.
#include "xml_helpers.hpp"

#include "effigi/xml/parser.hpp"

#include <catch2/catch.hpp>

#include <initializer_list>
#include <string>

using namespace effigi;
using namespace effigi::xml;
using namespace effigi::test;
using Catch::Contains;

namespace {

/// Parse `xml` as "bad.xml" and check the error message holds every part.
void expectError(const std::string& xml, std::initializer_list<std::string> parts, const ParseOptions& opt = {}) {
    std::string msg = errorOf([&] { parseString(xml, "bad.xml", opt); });
    INFO("message: " << msg);
    for (const std::string& p : parts) CHECK_THAT(msg, Contains(p));
}

} // namespace

TEST_CASE("xml: bad input is reported with file, line and name", "[xml]") {
    SECTION("malformed XML") {
        expectError(R"(<scene version="3.0.0">
    <bsdf type="diffuse">
        <float name="a" value="1">
    </bsdf>
</scene>)",
                    {"bad.xml:4:", "malformed XML"});
    }
    SECTION("unknown element, with a suggestion") {
        expectError(R"(<scene version="3.0.0">
    <shape type="sphere">

        <bsfd type="diffuse"/>
    </shape>
</scene>)",
                    {"bad.xml:4:", "<bsfd>", "did you mean <bsdf>"});
    }
    SECTION("a property directly inside <scene> other than Mitsuba's one scene property") {
        expectError(R"(<scene version="3.0.0">
    <float name="scale" value="2"/>
</scene>)",
                    {"bad.xml:2:", "scale", "directly inside <scene>", "embree_use_robust_intersections"});
        CHECK_NOTHROW(parseString(R"(<scene version="3.0.0">
    <boolean name="embree_use_robust_intersections" value="true"/>
</scene>)",
                                  "good.xml"));
    }
    SECTION("missing name") {
        expectError(R"(<scene version="3.0.0">
    <shape type="sphere">
        <float value="1"/>
    </shape>
</scene>)",
                    {"bad.xml:3:", "<float>", "missing attribute 'name'"});
    }
    SECTION("missing type") {
        expectError(R"(<scene version="3.0.0">
    <shape type="sphere">
        <bsdf id="b"/>
    </shape>
</scene>)",
                    {"bad.xml:3:", "<bsdf>", "missing attribute 'type'"});
    }
    SECTION("unparsable number") {
        expectError(R"(<scene version="3.0.0">
    <sensor type="perspective">
        <float name="fov" value="4o"/>
    </sensor>
</scene>)",
                    {"bad.xml:3:", "fov", "'4o'"});
        expectError(R"(<scene version="3.0.0">
    <sampler type="independent" id="s">
        <integer name="sample_count" value="1.5"/>
    </sampler>
</scene>)",
                    {"bad.xml:3:", "sample_count", "'1.5'"});
    }
    SECTION("NaN or Inf in a property or transform") {
        expectError(R"(<scene version="3.0.0">
    <shape type="sphere">
        <transform name="to_world">
            <scale value="2"/>
            <translate x="1" y="nan"/>
        </transform>
    </shape>
</scene>)",
                    {"bad.xml:5:", "to_world", "<translate>", "'nan'"});
        expectError(R"(<scene version="3.0.0">
    <shape type="sphere">
        <float name="radius" value="inf"/>
    </shape>
</scene>)",
                    {"bad.xml:3:", "radius", "finite"});
    }
    SECTION("degenerate transforms") {
        expectError(R"(<scene version="3.0.0">
    <sensor type="perspective">
        <transform name="to_world">
            <lookat origin="1, 1, 1" target="1, 1, 1" up="0, 1, 0"/>
        </transform>
    </sensor>
</scene>)",
                    {"bad.xml:4:", "to_world", "<lookat>", "coincide"});
        expectError(R"(<scene version="3.0.0">
    <sensor type="perspective">
        <transform name="to_world">
            <lookat origin="0, 0, 0" target="0, 5, 0" up="0, 1, 0"/>
        </transform>
    </sensor>
</scene>)",
                    {"bad.xml:4:", "to_world", "parallel"});
        expectError(R"(<scene version="3.0.0"><shape type="sphere"><transform name="to_world">
            <rotate x="0" angle="30"/></transform></shape></scene>)",
                    {"bad.xml:2:", "to_world", "<rotate>", "axis"});
        expectError(R"(<scene version="3.0.0"><shape type="sphere"><transform name="to_world">
            <matrix value="1 0 0 0 0 1 0 0 0 0 0 0 0 0 0 1"/></transform></shape></scene>)",
                    {"bad.xml:2:", "to_world", "<matrix>", "singular"});
    }
    SECTION("undefined $variable") {
        expectError(R"(<scene version="3.0.0">
    <default name="spp" value="4"/>
    <sampler type="independent" id="s">
        <integer name="sample_count" value="$sp"/>
    </sampler>
</scene>)",
                    {"bad.xml:4:", "<integer name=\"sample_count\">", "'$sp'", "did you mean '$spp'"});
    }
    SECTION("-D for a name the scene does not declare") {
        ParseOptions opt;
        opt.defines["spp"] = "64";
        expectError(R"(<scene version="3.0.0"><sampler type="independent" id="s"/></scene>)",
                    {"bad.xml", "-D spp", "<default name=\"spp\">"}, opt);
    }
    SECTION("missing include file") {
        std::string msg = errorOf([] { parseFile(kData / "missing_include.xml"); });
        CHECK_THAT(msg, Contains("missing_include.xml:3:"));
        CHECK_THAT(msg, Contains("does_not_exist.xml"));
    }
    SECTION("include cycle") {
        std::string msg = errorOf([] { parseFile(kData / "cycle_a.xml"); });
        CHECK_THAT(msg, Contains("cycle_b.xml:3:"));
        CHECK_THAT(msg, Contains("include cycle"));
        CHECK_THAT(msg, Contains("cycle_a.xml"));
    }
    SECTION("duplicate property") {
        expectError(R"(<scene version="3.0.0">
    <sensor type="perspective">
        <float name="fov" value="30"/>
        <float name="fov" value="40"/>
    </sensor>
</scene>)",
                    {"bad.xml:4:", "'fov'", "bad.xml:3"});
    }
    SECTION("duplicate id") {
        expectError(R"(<scene version="3.0.0">
    <bsdf type="diffuse" id="white"/>
    <shape type="sphere">
        <bsdf type="diffuse" id="white"/>
    </shape>
</scene>)",
                    {"bad.xml:4:", "duplicate id 'white'", "bad.xml:2"});
    }
    SECTION("spectrum wavelengths not ascending") {
        expectError(R"(<scene version="3.0.0">
    <bsdf type="conductor" id="c">
        <spectrum name="eta" value="400:1.5, 600:1.4, 500:1.3"/>
    </bsdf>
</scene>)",
                    {"bad.xml:3:", "eta", "ascending"});
    }
    SECTION("missing or corrupt .spd file") {
        const std::string inlineFile = (kData / "parts/inline.xml").string();
        std::string missing = errorOf([&] {
            parseString(R"(<scene version="3.0.0">
    <bsdf type="conductor" id="c">
        <spectrum name="eta" filename="nope.spd"/>
    </bsdf>
</scene>)",
                        inlineFile);
        });
        CHECK_THAT(missing, Contains("inline.xml:3:"));
        CHECK_THAT(missing, Contains("eta"));
        CHECK_THAT(missing, Contains("nope.spd"));
        std::string corrupt = errorOf([&] {
            parseString(R"(<scene version="3.0.0">
    <bsdf type="conductor" id="c">
        <spectrum name="k" filename="corrupt.spd"/>
    </bsdf>
</scene>)",
                        inlineFile);
        });
        CHECK_THAT(corrupt, Contains("inline.xml:3:"));
        CHECK_THAT(corrupt, Contains("corrupt.spd:2"));
    }
    SECTION("other structural errors") {
        expectError(R"(<scene><shape type="sphere"/></scene>)", {"bad.xml:1:", "version"});
        expectError(R"(<scenery version="3.0.0"/>)", {"bad.xml:1:", "<scene>"});
        expectError("<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n<float name=\"r\" vale=\"1\"/></shape></scene>",
                    {"bad.xml:3:", "'vale'", "did you mean 'value'"});
        expectError("<scene version=\"3.0.0\">\n<float name=\"r\" value=\"1\"/></scene>", {"bad.xml:2:", "<scene>"});
        expectError("<scene version=\"3.0.0\">\n<shape type=\"s\">\n<point name=\"c\" value=\"1 2\"/></shape></scene>",
                    {"bad.xml:3:", "<point name=\"c\">", "3 numbers"});
        expectError("<scene version=\"3.0.0\">\n<shape type=\"s\">\n<boolean name=\"b\" value=\"yes\"/></shape></scene>",
                    {"bad.xml:3:", "<boolean name=\"b\">", "'yes'"});
        expectError("<scene version=\"3.0.0\">\n<shape type=\"s\">\n<float name=\"r\" value=\"1e39\"/></shape></scene>",
                    {"bad.xml:3:", "<float name=\"r\">", "range"});
    }
    SECTION("a file that does not exist") {
        CHECK_THAT(errorOf([] { parseFile(kData / "no_such_scene.xml"); }), Contains("no_such_scene.xml"));
    }
}
