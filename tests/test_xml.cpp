// XML scene parser and loader: the tree it builds (typed values, transforms composed
// in Mitsuba's order, $defaults, -D, <include>, version 0.6 names) and one test per
// class of bad input, each checking file, line and the offending name in the message.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/iintersect.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <functional>

using namespace effigi;
using namespace effigi::xml;
using Catch::Contains;

namespace {

const std::filesystem::path kData = std::filesystem::path(EFFIGI_SOURCE_DIR) / "tests/data/xml";

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    FAIL("no effigi::Error was thrown");
    return {};
}

/// Parse `xml` as "bad.xml" and check the error message holds every part.
void expectError(const std::string& xml, std::initializer_list<std::string> parts, const ParseOptions& opt = {}) {
    std::string msg = errorOf([&] { parseString(xml, "bad.xml", opt); });
    INFO("message: " << msg);
    for (const std::string& p : parts) CHECK_THAT(msg, Contains(p));
}

bool near(const Vector3f& a, const Vector3f& b, float eps = 1e-5f) { return glm::length(a - b) < eps; }

const Properties::Entry& entry(const Node& n, const std::string& name) {
    const Properties::Entry* e = n.props.find(name);
    INFO("property " << name);
    REQUIRE(e != nullptr);
    return *e;
}

template <typename T> const T& value(const Node& n, const std::string& name) {
    const Properties::Entry& e = entry(n, name);
    INFO("property " << name << " holds " << propertyTypeName(e.value));
    REQUIRE(std::holds_alternative<T>(e.value));
    return std::get<T>(e.value);
}

/// The transform `to_world` of the first top-level object of a one-object scene.
Transform transformOf(const std::string& ops) {
    std::string xml = "<scene version=\"3.0.0\"><shape type=\"x\"><transform name=\"to_world\">" + ops +
                      "</transform></shape></scene>";
    auto root = parseString(xml, "t.xml");
    return value<Transform>(*root->children.at(0).node, "to_world");
}

} // namespace

TEST_CASE("xml: property values, aliases and tree structure", "[xml]") {
    auto root = parseString(R"(<scene version="3.0.0">
    <sensor type="perspective" id="cam">
        <float name="fov" value="45"/>
        <integer name="count" value="-12"/>
        <boolean name="flag" value="true"/>
        <string name="label" value="hello world"/>
        <point name="p" value="1, 2 3"/>
        <vector name="v" y="5"/>
        <rgb name="c" value="0.1 0.2 0.3"/>
        <rgb name="g" value="0.5"/>
        <spectrum name="k" value="0.25"/>
        <spectrum name="t" value="400:0.1, 500:0.4,600 : 0.9"/>
        <blackbody name="bb" temperature="3200" scale="2"/>
        <float name="small" value="1e-3"/>
        <film type="hdrfilm"/>
        <sampler type="independent" name="smp"/>
    </sensor>
    <integrator type="path">
        <integrator type="adaptive"/>
    </integrator>
</scene>)",
                            "tree.xml");
    REQUIRE(root->tag == "scene");
    REQUIRE(root->children.size() == 2);
    const Node& cam = *root->children[0].node;
    CHECK(cam.tag == "camera");  // <sensor> is an alias
    CHECK(cam.type == "perspective");
    CHECK(cam.id == "cam");
    CHECK(cam.props.id() == "cam");
    CHECK(cam.where.file == "tree.xml");
    CHECK(cam.where.line == 2);

    CHECK(value<double>(cam, "fov") == 45.0);
    CHECK(entry(cam, "fov").where.line == 3);
    CHECK(value<std::int64_t>(cam, "count") == -12);
    CHECK(value<bool>(cam, "flag"));
    CHECK(value<std::string>(cam, "label") == "hello world");
    CHECK(value<PointValue>(cam, "p").v == Point3f(1, 2, 3));
    CHECK(value<VectorValue>(cam, "v").v == Vector3f(0, 5, 0));
    CHECK(near(value<RGBValue>(cam, "c").v, Vector3f(0.1f, 0.2f, 0.3f)));
    CHECK(value<RGBValue>(cam, "g").v == Vector3f(0.5f));
    const SpectrumValue& k = value<SpectrumValue>(cam, "k");
    CHECK(k.lambdas.empty());
    CHECK(k.values == std::vector<float>{0.25f});
    const SpectrumValue& t = value<SpectrumValue>(cam, "t");
    CHECK(t.lambdas == std::vector<float>{400, 500, 600});
    CHECK(t.values == std::vector<float>{0.1f, 0.4f, 0.9f});
    const SpectrumValue& bb = value<SpectrumValue>(cam, "bb");
    CHECK(bb.temperature == 3200.f);
    CHECK(bb.scale == 2.f);
    CHECK(value<double>(cam, "small") == Approx(1e-3));

    // Nested objects in file order, with their name attribute (empty when absent).
    REQUIRE(cam.children.size() == 2);
    CHECK(cam.children[0].name.empty());
    CHECK(cam.children[0].node->tag == "film");
    CHECK(cam.children[1].name == "smp");
    CHECK(cam.children[1].node->tag == "sampler");
    CHECK(cam.children[1].where.line == 16);

    // A top-level <integrator> is the renderer; one nested in it stays a numerical integrator.
    const Node& rend = *root->children[1].node;
    CHECK(rend.tag == "renderer");
    CHECK(rend.type == "path");
    REQUIRE(rend.children.size() == 1);
    CHECK(rend.children[0].node->tag == "integrator");
}

TEST_CASE("xml: <ref> children", "[xml]") {
    auto root = parseString(R"(<scene version="3.0.0">
    <bsdf type="diffuse" id="white"/>
    <shape type="sphere">
        <ref id="white"/>
        <ref name="interior" id="white"/>
    </shape>
</scene>)",
                            "refs.xml");
    const Node& shape = *root->children.at(1).node;
    REQUIRE(shape.children.size() == 2);
    CHECK(shape.children[0].refId == "white");
    CHECK(shape.children[0].name.empty());
    CHECK(shape.children[0].node == nullptr);
    CHECK(shape.children[1].name == "interior");
    CHECK(shape.children[1].where.line == 5);
}

TEST_CASE("xml: transform operations compose left to right (M = op * M)", "[xml]") {
    // Translate first, then rotate 90 degrees about +y (right-handed: +x goes to -z).
    Transform m = transformOf(R"(<translate x="1"/><rotate y="1" angle="90"/>)");
    CHECK(near(m.point(Point3f(0, 0, 0)), Point3f(0, 0, -1)));
    // The other order: the rotation leaves the origin alone, the translation moves it.
    Transform r = transformOf(R"(<rotate value="0, 1, 0" angle="90"/><translate value="1 0 0"/>)");
    CHECK(near(r.point(Point3f(0, 0, 0)), Point3f(1, 0, 0)));

    // Scale then translate: (1,0,0) -> (2,0,0) -> (3,0,0); reversed it would be (4,0,0).
    CHECK(near(transformOf(R"(<scale value="2"/><translate x="1"/>)").point(Point3f(1, 0, 0)), Point3f(3, 0, 0)));
    CHECK(near(transformOf(R"(<translate x="1"/><scale value="2"/>)").point(Point3f(1, 0, 0)), Point3f(4, 0, 0)));
    // Scale attributes default to 1.
    CHECK(near(transformOf(R"(<scale y="3"/>)").point(Point3f(1, 1, 1)), Point3f(1, 3, 1)));
    CHECK(near(transformOf(R"(<scale value="1 2 3"/>)").point(Point3f(1, 1, 1)), Point3f(1, 2, 3)));

    // <matrix> is written row-major: the last column is the translation.
    Transform mat = transformOf(R"(<matrix value="1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1"/>)");
    CHECK(near(mat.point(Point3f(0, 0, 0)), Point3f(5, 6, 7)));
    Transform mat3 = transformOf(R"(<matrix value="0 -1 0, 1 0 0, 0 0 1"/>)");
    CHECK(near(mat3.point(Point3f(1, 0, 0)), Point3f(0, 1, 0)));
    CHECK(near(mat3.inverse().point(Point3f(0, 1, 0)), Point3f(1, 0, 0)));

    // An empty transform is the identity.
    CHECK(transformOf("").isIdentity());
}

TEST_CASE("xml: lookat maps local +z to the view direction and +x to the left", "[xml]") {
    Transform m = transformOf(R"(<lookat origin="1, 2, 3" target="1, 2, 0" up="0, 1, 0"/>)");
    CHECK(near(m.point(Point3f(0, 0, 0)), Point3f(1, 2, 3)));
    CHECK(near(m.vector(Vector3f(0, 0, 1)), Vector3f(0, 0, -1)));
    // Looking down -z with +y up, the viewer's left is -x.
    CHECK(near(m.vector(Vector3f(1, 0, 0)), Vector3f(-1, 0, 0)));
    CHECK(near(m.vector(Vector3f(0, 1, 0)), Vector3f(0, 1, 0)));
    // up defaults to +y.
    Transform d = transformOf(R"(<lookat origin="1, 2, 3" target="1, 2, 0"/>)");
    CHECK(near(d.vector(Vector3f(0, 1, 0)), Vector3f(0, 1, 0)));
    // A non-orthogonal up is orthogonalised: local +y stays in the plane of up and the view.
    Transform o = transformOf(R"(<lookat origin="0, 0, 0" target="0, 0, 1" up="0, 1, 1"/>)");
    CHECK(near(o.vector(Vector3f(0, 1, 0)), Vector3f(0, 1, 0)));
    CHECK(near(o.vector(Vector3f(1, 0, 0)), Vector3f(1, 0, 0)));
}

TEST_CASE("xml: <default> variables and -D overrides", "[xml]") {
    const std::string xml = R"xml(<scene version="3.0.0">
    <default name="spp" value="16"/>
    <default name="a" value="0.5"/>
    <default name="b" value="0.25"/>
    <default name="kind" value="independent"/>
    <sampler type="$kind" id="s">
        <integer name="sample_count" value="$spp"/>
        <rgb name="c" value="$a, $b, 1"/>
        <string name="note" value="cost: $5 ($spp spp)"/>
    </sampler>
</scene>)xml";
    auto root = parseString(xml, "vars.xml");
    const Node& s = *root->children.at(0).node;
    CHECK(s.type == "independent");
    CHECK(value<std::int64_t>(s, "sample_count") == 16);
    CHECK(value<RGBValue>(s, "c").v == Vector3f(0.5f, 0.25f, 1.f));
    // '$' not followed by a name is kept as written.
    CHECK(value<std::string>(s, "note") == "cost: $5 (16 spp)");

    ParseOptions opt;
    opt.defines["spp"] = "64";
    opt.defines["kind"] = "stratified";
    auto over = parseString(xml, "vars.xml", opt);
    const Node& o = *over->children.at(0).node;
    CHECK(o.type == "stratified");
    CHECK(value<std::int64_t>(o, "sample_count") == 64);
}

TEST_CASE("xml: <include> splices the included scene's children in place", "[xml]") {
    auto root = parseFile(kData / "main.xml");
    REQUIRE(root->children.size() == 4);
    const std::string mainFile = (kData / "main.xml").string();
    CHECK(root->where.file == mainFile);
    CHECK(root->where.line == 2);

    const Node& white = *root->children[0].node;
    CHECK(white.id == "white");
    const Node& ball = *root->children[1].node;
    const Node& metal = *root->children[2].node;
    const Node& sphere = *root->children[3].node;
    CHECK(ball.id == "ball");
    CHECK(metal.id == "metal");
    CHECK(sphere.type == "sphere");
    CHECK(sphere.where.file == mainFile);
    CHECK(sphere.where.line == 8);

    // Nodes from the included file name that file and their line in it.
    CHECK_THAT(ball.where.file, Contains("part.xml"));
    CHECK(ball.where.line == 4);
    // The including file's defaults apply inside the included file.
    CHECK(value<double>(metal, "scale") == 2.0);
    CHECK(value<double>(sphere, "radius") == 2.0);

    // The .spd file resolves relative to parts/, the directory of the file naming it.
    const SpectrumValue& eta = value<SpectrumValue>(ball, "eta");
    CHECK(eta.lambdas == std::vector<float>{400, 500, 600});
    CHECK(eta.values == std::vector<float>{1.5f, 1.45f, 1.4f});
}

TEST_CASE("xml: version < 3 maps camelCase names to snake_case", "[xml]") {
    CHECK(camelToSnake("maxDepth") == "max_depth");
    CHECK(camelToSnake("toWorld") == "to_world");
    CHECK(camelToSnake("sampleCount") == "sample_count");
    CHECK(camelToSnake("fovAxis") == "fov_axis");
    CHECK(camelToSnake("intIOR") == "int_ior");
    CHECK(camelToSnake("max_depth") == "max_depth");
    CHECK(camelToSnake("fov") == "fov");

    const std::string body = R"(
    <integrator type="path"><integer name="maxDepth" value="5"/></integrator>
    <sensor type="perspective">
        <string name="fovAxis" value="x"/>
        <transform name="toWorld"><lookat origin="0,0,1" target="0,0,0"/></transform>
        <sampler type="independent" name="mySampler"><integer name="sampleCount" value="4"/></sampler>
    </sensor>
</scene>)";
    for (const char* version : {"0.6.0", "2.0.0"}) {
        auto root = parseString(fmt::format("<scene version=\"{}\">", version) + body, "old.xml");
        const Node& integ = *root->children.at(0).node;
        CHECK(integ.tag == "renderer");
        CHECK(value<std::int64_t>(integ, "max_depth") == 5);
        const Node& cam = *root->children.at(1).node;
        CHECK(value<std::string>(cam, "fov_axis") == "x");
        CHECK(cam.props.has("to_world"));
        CHECK(cam.children.at(0).name == "my_sampler");
        CHECK(value<std::int64_t>(*cam.children.at(0).node, "sample_count") == 4);
    }
    // Version 3 keeps names as written.
    auto root = parseString("<scene version=\"3.0.0\">" + body, "new.xml");
    CHECK(root->children.at(0).node->props.has("maxDepth"));
}

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

// ---- loader ---------------------------------------------------------------------------

namespace {

class ITestPart : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("ITestPart");
    static constexpr const char* Tag = "function";
    virtual double value() const = 0;
    virtual Ref<ITestPart> inner() const = 0;
};

class TestPart final : public Implements<ITestPart> {
public:
    static Schema schema() {
        Schema s("function", "testpart", "A test component holding a number and an optional nested part.");
        s.real("value", 1.0, "a number");
        s.child("function", "inner", "a nested part");
        return s;
    }
    explicit TestPart(const Properties& p) : m_value(p.getFloat("value")), m_inner(p.get<ITestPart>("inner")) {}
    double value() const override { return m_value; }
    Ref<ITestPart> inner() const override { return m_inner; }

private:
    double m_value;
    Ref<ITestPart> m_inner;
};

Registry& testRegistry() {
    static Registry reg;
    static bool once = [] {
        reg.add(ComponentInfo{TestPart::schema(), [](const Properties& p) -> Ref<IComponent> {
                                  return std::make_shared<TestPart>(p);
                              },
                              ""});
        return true;
    }();
    (void)once;
    return reg;
}

} // namespace

TEST_CASE("xml: instantiate passes values, nested objects and refs", "[xml]") {
    Registry& reg = testRegistry();
    auto root = parseString(R"(<scene version="3.0.0">
    <function type="testpart" id="a">
        <float name="value" value="2.5"/>
    </function>
    <function type="testpart" id="b">
        <function type="testpart"><float name="value" value="7"/></function>
    </function>
    <function type="testpart" id="c">
        <ref name="inner" id="a"/>
    </function>
    <function type="testpart" id="d">
        <ref name="inner" id="x"/>
    </function>
</scene>)",
                            "load.xml");
    Ref<IComponent> a = instantiate(*root->children.at(0).node, reg);
    auto pa = query<ITestPart>(a);
    REQUIRE(pa);
    CHECK(pa->value() == Approx(2.5));
    CHECK(pa->inner() == nullptr);
    CHECK(a->id() == "a");
    CHECK(a->typeName() == "function/testpart");

    // An unnamed nested object is placed in the schema's slot for its tag.
    auto pb = query<ITestPart>(instantiate(*root->children.at(1).node, reg));
    REQUIRE(pb->inner());
    CHECK(pb->inner()->value() == Approx(7.0));
    CHECK(pb->value() == Approx(1.0));  // schema default

    // A <ref> resolves to the very object known under that id.
    auto pc = query<ITestPart>(instantiate(*root->children.at(2).node, reg, {{"a", a}}));
    CHECK(pc->inner() == pa);

    // Unknown ids are errors at the <ref>'s line, listing the known ones.
    std::string msg = errorOf([&] { instantiate(*root->children.at(3).node, reg, {{"a", a}}); });
    CHECK_THAT(msg, Contains("load.xml:12:"));
    CHECK_THAT(msg, Contains("'x'") || Contains("\"x\""));
    CHECK_THAT(msg, Contains("unknown id"));
    CHECK_THAT(msg, Contains("a"));
    // A forward reference is unknown too: ids resolve in file order.
    CHECK_THAT(errorOf([&] { instantiate(*root->children.at(2).node, reg); }), Contains("load.xml:9:"));
}

namespace {

class FakeCamera final : public Implements<ICamera> {
public:
    Ray generateRay(const CameraSample&, const SampledWavelengths&, SampledSpectrum&) const override { return {}; }
    const Transform& toWorld() const override { return m_toWorld; }
    IFilm& film() const override { fail("fake camera: no film"); }
    ISampler& sampler() const override { fail("fake camera: no sampler"); }

private:
    Transform m_toWorld;
};

class FakeRenderer final : public Implements<IRenderer> {
public:
    explicit FakeRenderer(const Properties& p) : label(p.getString("label")) {}
    RenderStats render(const Scene&, const RenderControl&) override { return {}; }
    std::string label;
};

class FakeAccel final : public Implements<IIntersect> {
public:
    void build(std::span<const IShape* const> shapes) override { built = int(shapes.size()); }
    bool intersect(const Ray&, Hit&) const override { return false; }
    bool occluded(const Ray&) const override { return false; }
    BBox3f bbox() const override { return {}; }
    int built = -1;
};

/// A registry with the test part and fake scene parts; the fakes also stand in for the
/// default renderer ('path') and accelerator ('embree').
Registry& sceneRegistry() {
    static Registry reg;
    static bool once = [] {
        reg.add(testRegistry().info("function", "testpart"));
        Schema cam("camera", "fake", "A camera that renders nothing.");
        reg.add(ComponentInfo{cam, [](const Properties&) -> Ref<IComponent> { return std::make_shared<FakeCamera>(); }, ""});
        for (const char* name : {"fake", "path"}) {
            Schema r("renderer", name, "A renderer that renders nothing.");
            r.string("label", name, "tells instances apart");
            reg.add(ComponentInfo{r, [](const Properties& p) -> Ref<IComponent> {
                                      return std::make_shared<FakeRenderer>(p);
                                  },
                                  ""});
            Schema a("accelerator", std::string(name) == "fake" ? "fake" : "embree", "No acceleration at all.");
            reg.add(ComponentInfo{a, [](const Properties&) -> Ref<IComponent> { return std::make_shared<FakeAccel>(); }, ""});
        }
        return true;
    }();
    (void)once;
    return reg;
}

} // namespace

TEST_CASE("xml: loadScene assembles the top level", "[xml]") {
    Registry& reg = sceneRegistry();
    auto root = parseString(R"(<scene version="3.0.0">
    <function type="testpart" id="shared"/>
    <sensor type="fake" id="cam"/>
    <integrator type="fake"><string name="label" value="mine"/></integrator>
    <accelerator type="fake"/>
</scene>)",
                            "scene.xml");
    std::unique_ptr<Scene> scene = loadScene(*root, reg);
    CHECK(scene->sourceFile == "scene.xml");
    CHECK(scene->camera().id() == "cam");
    CHECK(scene->camera().typeName() == "camera/fake");
    auto* rend = dynamic_cast<FakeRenderer*>(&scene->renderer());
    REQUIRE(rend);
    CHECK(rend->label == "mine");
    auto* accel = dynamic_cast<const FakeAccel*>(&scene->accelerator());
    REQUIRE(accel);
    CHECK(accel->built == 0);  // built once, over no shapes
    CHECK(accel->typeName() == "accelerator/fake");

    // Without <integrator> and <accelerator>: the defaults 'path' and 'embree'.
    auto minimal = parseString("<scene version=\"3.0.0\"><sensor type=\"fake\"/></scene>", "min.xml");
    scene = loadScene(*minimal, reg);
    CHECK(scene->renderer().typeName() == "renderer/path");
    CHECK(scene->accelerator().typeName() == "accelerator/embree");
}

TEST_CASE("xml: loadScene rejects a bad top level", "[xml]") {
    Registry& reg = sceneRegistry();
    // Objects that are neither scene parts nor referable are rejected.
    auto noId = parseString("<scene version=\"3.0.0\">\n<function type=\"testpart\"/>\n</scene>", "top.xml");
    std::string msg = errorOf([&] { loadScene(*noId, reg); });
    CHECK_THAT(msg, Contains("top.xml:2:"));
    CHECK_THAT(msg, Contains("<function> needs an id"));
    // A scene without a camera says so.
    auto noCam = parseString("<scene version=\"3.0.0\">\n<function type=\"testpart\" id=\"f\"/>\n</scene>", "top.xml");
    CHECK_THAT(errorOf([&] { loadScene(*noCam, reg); }), Contains("top.xml: scene has no <sensor>/<camera>"));
    // Two cameras: the error points at the second and at the first.
    auto two = parseString("<scene version=\"3.0.0\">\n<sensor type=\"fake\"/>\n<sensor type=\"fake\"/>\n</scene>",
                           "top.xml");
    msg = errorOf([&] { loadScene(*two, reg); });
    CHECK_THAT(msg, Contains("top.xml:3:"));
    CHECK_THAT(msg, Contains("second camera"));
    CHECK_THAT(msg, Contains("top.xml:2"));
    // An unknown component type is located too (the message is the registry's).
    auto unknown = parseString("<scene version=\"3.0.0\">\n\n<sensor type=\"nosuch\"/>\n</scene>", "top.xml");
    CHECK_THAT(errorOf([&] { loadScene(*unknown, reg); }), Contains("top.xml:3:"));
}
