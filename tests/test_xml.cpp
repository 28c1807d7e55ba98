// XML scene parser: the tree it builds (typed values, aliases, <ref>), transforms
// composed in Mitsuba's order, $defaults and -D, <include>, and version 0.6 names.
#include "xml_helpers.hpp"

#include "effigi/xml/parser.hpp"

#include <catch2/catch.hpp>

#include <string>
#include <vector>

using namespace effigi;
using namespace effigi::xml;
using namespace effigi::test;
using Catch::Contains;

namespace {

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
