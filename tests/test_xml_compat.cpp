// Mitsuba scene-format compatibility of the XML reader: <path> and the file resolver
// (also inside <include>d files), forward <ref>s and reference cycles, -D without a
// <default>, parameters accepted but ignored, and errors that name the enclosing object.
// Version < 3 files are tested in test_xml_compat_legacy.cpp. Every case checks the
// message names file:line and the culprit.
#include "app_runner.hpp"
#include "xml_compat_helpers.hpp"
#include "xml_helpers.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <string>
#include <utility>
#include <vector>

using namespace effigi;
using namespace effigi::xml;
using namespace effigi::test;
using Catch::Contains;
namespace fs = std::filesystem;

namespace {

bool sameFile(const std::string& a, const fs::path& b) {
    std::error_code ec;
    return fs::equivalent(fs::path(a), b, ec);
}

// A component with an optional nested part and one parameter Mitsuba would take but
// this component ignores; enough to exercise the loader without real modules.
class ITestPart : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("ITestPartCompat");
    static constexpr const char* Tag = "function";
    virtual Ref<ITestPart> inner() const = 0;
};

class TestPart final : public Implements<ITestPart> {
public:
    static Schema schema() {
        Schema s("function", "compatpart", "A test part with an optional nested part.");
        s.real("value", 1.0, "a number");
        s.child("function", "inner", "a nested part");
        s.ignored("legacy_knob", "a test parameter that is accepted and ignored");
        return s;
    }
    explicit TestPart(const Properties& p) : m_inner(p.get<ITestPart>("inner")) {}
    Ref<ITestPart> inner() const override { return m_inner; }

private:
    Ref<ITestPart> m_inner;
};

Registry& testRegistry() {
    static Registry reg;
    static bool once = [] {
        reg.add(ComponentInfo{TestPart::schema(),
                              [](const Properties& p) -> Ref<IComponent> { return std::make_shared<TestPart>(p); },
                              ""});
        return true;
    }();
    (void)once;
    return reg;
}

const char* kCamera = R"(<sensor type="perspective">
        <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="1"/></sampler>
        <film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film>
    </sensor>)";

} // namespace

TEST_CASE("xml compat: <path> and the search path resolve file names, also in includes", "[xml]") {
    auto root = parseFile(kCompat / "scene.xml");
    // Named in the main file, found through <path value="assets"/>.
    CHECK(sameFile(value<std::string>(byId(*root, "direct"), "filename"), kCompat / "assets/mesh.obj"));
    // Named in parts/inc.xml: the search path (assets/, then the main file's folder)
    // applies there too, as in Mitsuba.
    CHECK(sameFile(value<std::string>(byId(*root, "inc_asset"), "filename"), kCompat / "assets/mesh.obj"));
    CHECK(sameFile(value<std::string>(byId(*root, "inc_main"), "filename"), kCompat / "main_only.obj"));
    // In both the main folder and parts/: the main folder wins.
    CHECK(sameFile(value<std::string>(byId(*root, "inc_both"), "filename"), kCompat / "both.obj"));
    // Only next to the included file: kept as written, resolved there by getPath.
    CHECK(value<std::string>(byId(*root, "inc_local"), "filename") == "local_only.obj");
    // <spectrum filename> goes through the same search path.
    const SpectrumValue& eta = value<SpectrumValue>(byId(*root, "metal"), "eta");
    CHECK(eta.lambdas == std::vector<float>{400, 700});
    CHECK(eta.values == std::vector<float>{2.0f, 2.5f});

    // The whole scene loads with the real components (every mesh found).
    auto scene = loadSceneFile(kCompat / "scene.xml");
    CHECK(scene->shapes().size() == 5);
}

TEST_CASE("xml compat: bad <path> elements", "[xml]") {
    std::string msg = errorOf([] { parseFile(kCompat / "bad_path.xml"); });
    CHECK_THAT(msg, Contains("bad_path.xml:2:"));
    CHECK_THAT(msg, Contains("no_such_folder"));
    msg = errorOf([] {
        parseString(R"(<scene version="3.0.0">
    <shape type="sphere"><path value="."/></shape>
</scene>)",
                    "nested.xml");
    });
    CHECK_THAT(msg, Contains("nested.xml:2:"));
    CHECK_THAT(msg, Contains("<path>"));
    msg = errorOf([] { parseString(R"(<scene version="3.0.0"><path valu="."/></scene>)", "attr.xml"); });
    CHECK_THAT(msg, Contains("attr.xml:1:"));
    CHECK_THAT(msg, Contains("valu"));
}

TEST_CASE("xml compat: a <ref> may name an object declared later, and cycles are errors", "[xml]") {
    SECTION("forward reference in a real scene") {
        auto root = parseString(std::string(R"(<scene version="3.0.0">
    )") + kCamera + R"(
    <shape type="sphere"><ref id="later"/></shape>
    <bsdf type="diffuse" id="later"><rgb name="reflectance" value="0.25"/></bsdf>
</scene>)",
                                "fwd.xml");
        auto scene = loadScene(*root);
        CHECK(scene->shapes().size() == 1);
    }
    SECTION("a top-level emitter referenced by a shape is that shape's light, listed once") {
        // Mitsuba's cbox scenes declare the area emitter at top level, after the shape that
        // references it: counting it twice would halve its MIS weights.
        auto root = parseString(std::string(R"(<scene version="3.0.0">
    )") + kCamera + R"(
    <shape type="sphere"><ref id="lamp"/></shape>
    <emitter type="area" id="lamp"><rgb name="radiance" value="1"/></emitter>
    <emitter type="constant"/>
</scene>)",
                                "lamp.xml");
        auto scene = loadScene(*root);
        REQUIRE(scene->emitters().size() == 2);
        CHECK(scene->emitters()[0] == scene->shapes()[0]->emitter());
        CHECK(scene->emitters()[1]->isInfinite());
        CHECK(scene->emitterProbability(scene->emitters()[0]) == Approx(0.5f));
    }
    SECTION("forward reference to a nested object, built once") {
        auto root = parseString(R"(<scene version="3.0.0">
    <function type="compatpart" id="a"><ref name="inner" id="deep"/></function>
    <function type="compatpart" id="b">
        <function type="compatpart" name="inner" id="deep"/>
    </function>
</scene>)",
                                "nested.xml");
        Registry& reg = testRegistry();
        // No camera: the scene fails at the end, after every reference was resolved.
        std::string msg = errorOf([&] { loadScene(*root, reg); });
        CHECK_THAT(msg, Contains("no <sensor>"));
    }
    SECTION("cycle") {
        auto root = parseString(R"(<scene version="3.0.0">
    <function type="compatpart" id="a"><ref name="inner" id="b"/></function>
    <function type="compatpart" id="b">
        <ref name="inner" id="a"/>
    </function>
</scene>)",
                                "cycle.xml");
        std::string msg = errorOf([&] { loadScene(*root, testRegistry()); });
        CHECK_THAT(msg, Contains("cycle.xml:4:"));
        CHECK_THAT(msg, Contains("circular reference a -> b -> a"));
    }
    SECTION("self reference") {
        auto root = parseString(R"(<scene version="3.0.0">
    <function type="compatpart" id="me"><ref name="inner" id="me"/></function>
</scene>)",
                                "self.xml");
        std::string msg = errorOf([&] { loadScene(*root, testRegistry()); });
        CHECK_THAT(msg, Contains("self.xml:2:"));
        CHECK_THAT(msg, Contains("me -> me"));
    }
    SECTION("unknown id, declared nowhere") {
        auto root = parseString(R"(<scene version="3.0.0">
    <function type="compatpart" id="alpha"/>
    <function type="compatpart" id="b"><ref name="inner" id="alhpa"/></function>
</scene>)",
                                "unknown.xml");
        std::string msg = errorOf([&] { loadScene(*root, testRegistry()); });
        CHECK_THAT(msg, Contains("unknown.xml:3:"));
        CHECK_THAT(msg, Contains("did you mean 'alpha'"));
    }
}

TEST_CASE("xml compat: -D may set a $variable the scene does not declare", "[xml]") {
    const std::string xml = R"(<scene version="3.0.0">
    <sampler type="independent" id="s">
        <integer name="sample_count" value="$spp"/>
    </sampler>
</scene>)";
    ParseOptions opt;
    opt.defines["spp"] = "16";
    auto root = parseString(xml, "d.xml", opt);
    CHECK(value<std::int64_t>(*root->children.at(0).node, "sample_count") == 16);

    // Neither a <default> nor a -D: the error names file, line and variable.
    std::string msg = errorOf([&] { parseString(xml, "d.xml"); });
    CHECK_THAT(msg, Contains("d.xml:3:"));
    CHECK_THAT(msg, Contains("$spp"));
    CHECK_THAT(msg, Contains("-D spp="));

    // A -D the scene neither declares nor uses is still an error (as in Mitsuba).
    ParseOptions extra = opt;
    extra.defines["sp"] = "4";
    msg = errorOf([&] { parseString(xml, "d.xml", extra); });
    CHECK_THAT(msg, Contains("d.xml"));
    CHECK_THAT(msg, Contains("-D sp:"));

    // "\$" is a literal dollar sign (Mitsuba's escape), not a variable.
    auto esc = parseString(R"(<scene version="3.0.0"><bsdf type="x" id="b">
        <string name="label" value="cost \$spp, $spp"/></bsdf></scene>)",
                           "esc.xml", opt);
    CHECK(value<std::string>(*esc->children.at(0).node, "label") == "cost $spp, 16");
}

TEST_CASE("xml compat: ignored parameters are accepted, unknown ones are not", "[xml]") {
    Registry& reg = testRegistry();
    auto root = parseString(R"(<scene version="3.0.0">
    <function type="compatpart" id="a"><boolean name="legacy_knob" value="true"/></function>
    <function type="compatpart" id="b"><rgb name="legacy_knob" value="0.5"/></function>
    <function type="compatpart" id="c"><float name="legacy_knop" value="1"/></function>
</scene>)",
                            "ign.xml");
    // Any value type is accepted for an ignored parameter.
    CHECK(instantiate(*root->children.at(0).node, reg) != nullptr);
    CHECK(instantiate(*root->children.at(1).node, reg) != nullptr);
    // A name neither effigi nor Mitsuba knows stays an error, with a did-you-mean.
    std::string msg = errorOf([&] { instantiate(*root->children.at(2).node, reg); });
    CHECK_THAT(msg, Contains("ign.xml:4:"));
    CHECK_THAT(msg, Contains("legacy_knop"));
    CHECK_THAT(msg, Contains("did you mean 'legacy_knob'"));
    CHECK(TestPart::schema().find("legacy_knob")->ignored);

    // Real components: Mitsuba's hdrfilm/perspective/path/area options load.
    auto real = parseString(std::string(R"(<scene version="3.0.0">
    <integrator type="path"><integer name="samples_per_pass" value="4"/><float name="timeout" value="10"/></integrator>
    <sensor type="perspective">
        <float name="focus_distance" value="3"/>
        <float name="shutter_open" value="0"/><float name="shutter_close" value="1"/>
        <film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/>
            <boolean name="banner" value="false"/><boolean name="sample_border" value="true"/>
            <boolean name="compensate" value="true"/></film>
    </sensor>
    <shape type="sphere"><emitter type="area"><float name="sampling_weight" value="2"/></emitter></shape>
    <emitter type="point"><float name="sampling_weight" value="2"/></emitter>
</scene>)"),
                            "real.xml");
    auto scene = loadScene(*real);
    CHECK(scene->emitters().size() == 2);
    // ... and `effigi info` says they are ignored.
    AppResult info = runApp("info film/hdrfilm");
    CHECK(info.exitCode == 0);
    CHECK_THAT(info.out, Contains("banner"));
    CHECK_THAT(info.out, Contains("ignored"));
}

TEST_CASE("xml compat: an unknown nested type names the object it is in", "[xml]") {
    auto root = parseString(R"(<scene version="3.0.0">
    <function type="compatpart" id="outer">
        <function type="nope" name="inner"/>
    </function>
</scene>)",
                            "nest.xml");
    std::string msg = errorOf([&] { instantiate(*root->children.at(0).node, testRegistry()); });
    CHECK_THAT(msg, Contains("nest.xml:3:"));
    CHECK_THAT(msg, Contains("'nope'"));
    CHECK_THAT(msg, Contains("inside function 'compatpart' at nest.xml:2"));

    // A nested <integrator> inside a top-level <integrator> (a renderer in effigi).
    auto r = parseString(R"(<scene version="3.0.0">
    <integrator type="path">
        <integrator type="nope"/>
    </integrator>
</scene>)",
                         "integ.xml");
    msg = errorOf([&] { instantiate(*r->children.at(0).node, Registry::instance()); });
    CHECK_THAT(msg, Contains("integ.xml:3:"));
    CHECK_THAT(msg, Contains("'nope'"));
    CHECK_THAT(msg, Contains("inside integrator 'path' at integ.xml:2"));

    // A nested <integrator> naming a renderer is one (Mitsuba's aov/moment nest them);
    // one naming a numerical integrator (mean) stays that.
    auto nested = parseString(R"(<scene version="3.0.0">
    <integrator type="aov">
        <integrator type="direct"><integrator type="mean"/></integrator>
    </integrator>
</scene>)",
                              "aov.xml");
    CHECK(instantiate(*nested->children.at(0).node, Registry::instance()) != nullptr);
}

TEST_CASE("xml compat: effigi render --dry-run loads without rendering", "[xml][cli]") {
    fs::path dir = tempDir("dry-run");
    fs::path out = dir / "out.exr";
    AppResult ok = runApp("render " + (kCompat / "old/scene06.xml").string() + " --dry-run -o " + out.string());
    CHECK(ok.exitCode == 0);
    CHECK_THAT(ok.out, Contains("2 shapes"));
    CHECK_FALSE(fs::exists(out));
    // Load errors still fail, with file:line.
    AppResult bad = runApp("render " + (kCompat / "bad_path.xml").string() + " --dry-run");
    CHECK(bad.exitCode == 1);
    CHECK_THAT(bad.out, Contains("bad_path.xml:2:"));
    // -D for a $variable without a <default> works from the command line.
    fs::path scene = dir / "d.xml";
    std::ofstream(scene) << R"(<scene version="3.0.0">
    <sensor type="perspective">
        <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
        <film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film>
    </sensor>
</scene>)";
    CHECK(runApp("render " + scene.string() + " --dry-run -D spp=2").exitCode == 0);
    AppResult undef = runApp("render " + scene.string() + " --dry-run");
    CHECK(undef.exitCode == 1);
    CHECK_THAT(undef.out, Contains("d.xml:3:"));
    CHECK_THAT(undef.out, Contains("$spp"));
    fs::remove_all(dir);
}

TEST_CASE("xml compat: Mitsuba's volpathmis is read as volpath, top-level and nested", "[xml]") {
    for (const char* type : {"volpath", "volpathmis"}) {
        auto root = parseString(std::string(R"(<scene version="3.0.0">
    <integrator type="moment"><integrator type=")") + type + R"("><integer name="max_depth" value="3"/></integrator></integrator>
    )" + kCamera + R"(
    <shape type="sphere"/>
</scene>)",
                                "volpath.xml");
        INFO(type);
        auto scene = loadScene(*root);
        CHECK(scene->renderer().typeName() == "renderer/moment");
        auto top = parseString(std::string(R"(<scene version="3.0.0"><integrator type=")") + type + R"("/>
    )" + kCamera + R"(<shape type="sphere"/></scene>)",
                               "volpath_top.xml");
        CHECK(loadScene(*top)->renderer().typeName() == "renderer/volpath");
    }
}
