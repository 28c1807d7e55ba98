// XML scene loader: instantiate() turns parsed nodes into components (values, nested
// objects, <ref>s), loadScene() assembles the top level and rejects a bad one. Uses a
// private registry with a test component and fake camera, renderer and accelerator.
#include "xml_helpers.hpp"

#include "effigi/core/registry.hpp"
#include "effigi/interfaces/icamera.hpp"
#include "effigi/interfaces/iintersect.hpp"
#include "effigi/interfaces/irenderer.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <catch2/catch.hpp>

#include <memory>
#include <string>

using namespace effigi;
using namespace effigi::xml;
using namespace effigi::test;
using Catch::Contains;

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
