// The component model: registry, schemas, validation, QueryInterface, lazy modules.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/interfaces/itexture.hpp"
#include "effigi/xml/loader.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <fstream>
#include <functional>
#include <unistd.h>

using namespace effigi;

namespace {

// Two made-up interfaces and a component implementing both (a photon map is an
// IEventStore and an IIlluminationMap; this is the same situation in miniature).
class IFoo : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IFoo");
    static constexpr const char* Tag = "function";
    virtual int foo() const = 0;
};
class IBar : public virtual IComponent {
public:
    static constexpr InterfaceId IID = interfaceId("IBar");
    static constexpr const char* Tag = "function";
    virtual int bar() const = 0;
};

class FooBar final : public Implements<IFoo, IBar> {
public:
    static Schema schema() {
        Schema s("function", "foobar", "Test component with two interfaces.");
        s.integer("count", 3, "A count").range(1, 10);
        s.real("scale", 0.5, "A scale").withUnit("m");
        s.string("mode", "fast", "A mode").oneOf({"fast", "exact"});
        s.child("function", "inner", "An optional nested function");
        return s;
    }
    explicit FooBar(const Properties& p)
        : m_count(int(p.getInt("count"))), m_scale(p.getFloat("scale")), m_mode(p.getString("mode")),
          m_inner(p.getComponent("inner")) {}
    int foo() const override { return m_count; }
    int bar() const override { return int(m_scale * 10.f); }

    int m_count;
    float m_scale;
    std::string m_mode;
    Ref<IComponent> m_inner;
};

void addFooBar(Registry& reg) {
    reg.add(ComponentInfo{FooBar::schema(),
                          [](const Properties& p) -> Ref<IComponent> { return std::make_shared<FooBar>(p); }, ""});
}

std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

bool loaded(const std::string& module) {
    auto mods = Registry::instance().loadedModules();
    return std::any_of(mods.begin(), mods.end(), [&](const std::string& m) { return m.find(module) != std::string::npos; });
}

} // namespace

TEST_CASE("registry: query returns each implemented interface of one object", "[registry]") {
    Registry reg;
    addFooBar(reg);
    Properties p("function", "foobar");
    Ref<IComponent> obj = reg.create("function", "foobar", p);
    REQUIRE(obj);
    CHECK(obj->typeName() == "function/foobar");
    Ref<IFoo> foo = query<IFoo>(obj);
    Ref<IBar> bar = query<IBar>(obj);
    REQUIRE(foo);
    REQUIRE(bar);
    CHECK(foo->foo() == 3);  // defaults filled from the schema
    CHECK(bar->bar() == 5);
    CHECK(query<IBSDF>(obj) == nullptr);
    // The interface pointers share ownership with the object.
    CHECK(foo.use_count() == obj.use_count());
}

TEST_CASE("registry: schema validation names the parameter and suggests", "[registry]") {
    Registry reg;
    addFooBar(reg);
    SourceLocation at{"scene.xml", 12};
    auto make = [&](const std::string& name, PropertyValue v) {
        Properties p("function", "foobar", at);
        p.set(name, std::move(v), at);
        return reg.create("function", "foobar", p);
    };
    CHECK(std::dynamic_pointer_cast<FooBar>(make("count", std::int64_t(7)))->m_count == 7);
    CHECK(std::dynamic_pointer_cast<FooBar>(make("scale", std::int64_t(2)))->m_scale == 2.f);  // int -> float

    std::string e = errorOf([&] { make("cuont", std::int64_t(2)); });
    CHECK(e.find("scene.xml:12") == 0);
    CHECK(e.find("'cuont'") != std::string::npos);
    CHECK(e.find("did you mean 'count'") != std::string::npos);

    e = errorOf([&] { make("count", std::string("many")); });
    CHECK(e.find("scene.xml:12") == 0);
    CHECK(e.find("'count' must be an integer, got string") != std::string::npos);

    e = errorOf([&] { make("count", std::int64_t(11)); });
    CHECK(e.find("out of range [1, 10]") != std::string::npos);

    e = errorOf([&] { make("mode", std::string("fats")); });
    CHECK(e.find("did you mean 'fast'") != std::string::npos);

    e = errorOf([&] { make("scale", RGBValue{Vector3f(1.f)}); });
    CHECK(e.find("'scale' must be a float, got rgb") != std::string::npos);
}

TEST_CASE("registry: unnamed children fill the schema's slots", "[registry]") {
    Registry reg;
    addFooBar(reg);
    Properties inner("function", "foobar");
    Ref<IComponent> child = reg.create("function", "foobar", inner);

    Properties p("function", "foobar", {"a.xml", 3});
    p.set("", ComponentValue{"function", child}, {"a.xml", 4});
    auto obj = std::dynamic_pointer_cast<FooBar>(reg.create("function", "foobar", p));
    CHECK(obj->m_inner == child);

    Properties two("function", "foobar", {"a.xml", 3});
    two.set("", ComponentValue{"function", child}, {"a.xml", 4});
    two.set("", ComponentValue{"function", child}, {"a.xml", 5});
    std::string e = errorOf([&] { reg.create("function", "foobar", two); });
    CHECK(e.find("a.xml:5") == 0);
    CHECK(e.find("does not accept another nested function") != std::string::npos);

    Properties wrong("function", "foobar", {"a.xml", 3});
    wrong.set("", ComponentValue{"bsdf", child}, {"a.xml", 6});
    e = errorOf([&] { reg.create("function", "foobar", wrong); });
    CHECK(e.find("a.xml:6") == 0);
    CHECK(e.find("nested bsdf") != std::string::npos);
}

TEST_CASE("registry: unknown components list what exists", "[registry]") {
    Registry reg;
    addFooBar(reg);
    Properties p("function", "fobar", {"s.xml", 9});
    std::string e = errorOf([&] { reg.create("function", "fobar", p); });
    CHECK(e.find("s.xml:9") == 0);
    CHECK(e.find("unknown function 'fobar'") != std::string::npos);
    CHECK(e.find("did you mean 'foobar'") != std::string::npos);
    CHECK(e.find("available: foobar") != std::string::npos);

    Properties q("bsdf", "x");
    e = errorOf([&] { reg.create("bsdf", "x", q); });
    CHECK(e.find("no components of kind 'bsdf'") != std::string::npos);
}

TEST_CASE("registry: the manifest lists every built-in component without loading it", "[registry]") {
    Registry& reg = Registry::instance();
    auto all = reg.list();
    auto has = [&](const char* t, const char* n) {
        return std::find(all.begin(), all.end(), std::pair<std::string, std::string>(t, n)) != all.end();
    };
    for (auto [t, n] : {std::pair{"accelerator", "embree"}, {"accelerator", "bruteforce"}, {"shape", "sphere"},
                        {"shape", "ply"}, {"bsdf", "diffuse"}, {"emitter", "area"}, {"renderer", "path"},
                        {"renderer", "aov"}, {"integrator", "mean"}, {"film", "hdrfilm"}})
        CHECK(has(t, n));
    CHECK(reg.loadedModules().empty());
    CHECK(reg.knows("sensor", "perspective"));  // XML alias of camera
    // Asking for a schema loads exactly that module.
    CHECK(reg.info("bsdf", "diffuse").schema.find("reflectance"));
    CHECK(loaded("bsdf-diffuse"));
    CHECK(reg.loadedModules().size() == 1);
}

TEST_CASE("registry: a scene loads only the modules it uses", "[registry]") {
    auto scene = loadSceneFile(EFFIGI_SOURCE_DIR "/scenes/cornell-box/scene.xml");
    CHECK(loaded("shape-rectangle"));
    CHECK(loaded("shape-cube"));
    CHECK(loaded("accelerator-embree"));
    CHECK_FALSE(loaded("shape-sphere"));     // the Cornell box has no sphere
    CHECK_FALSE(loaded("shape-ply"));
    CHECK_FALSE(loaded("renderer-aov"));
    CHECK_FALSE(loaded("accelerator-bruteforce"));
    CHECK_FALSE(loaded("emitter-point"));
}

TEST_CASE("registry: a missing or broken module is a clear error", "[registry]") {
    namespace fs = std::filesystem;
    fs::path dir = fs::temp_directory_path() / ("effigi-test-broken-module-" + std::to_string(getpid()));
    fs::create_directories(dir);
    {
        std::ofstream(dir / "manifest.txt") << "shape broken not-a-module.so\nshape gone missing.so\n";
        std::ofstream(dir / "not-a-module.so") << "this is not an ELF file";
    }
    Registry reg;
    reg.addModuleDirectory(dir);
    Properties p("shape", "broken");
    std::string e = errorOf([&] { reg.create("shape", "broken", p); });
    CHECK(e.find("cannot load module") != std::string::npos);
    CHECK(e.find("not-a-module.so") != std::string::npos);
    Properties q("shape", "gone");
    e = errorOf([&] { reg.create("shape", "gone", q); });
    CHECK(e.find("missing.so") != std::string::npos);
    fs::remove_all(dir);
}

TEST_CASE("registry: plugin directories without a manifest, and plugins replacing components", "[registry]") {
    namespace fs = std::filesystem;
    fs::path base = fs::temp_directory_path() / ("effigi-test-plugin-dirs-" + std::to_string(getpid()));
    fs::path bare = base / "bare", first = base / "first", second = base / "second";
    for (const auto& d : {bare, first, second}) fs::create_directories(d);
    {
        // Not loadable: only the names matter until something is created.
        std::ofstream(bare / "bsdf-fake.so") << "not an ELF file";
        std::ofstream(bare / "libhelper.so") << "not an ELF file";
        std::ofstream(first / "manifest.txt") << "shape twin one.so\n";
        std::ofstream(second / "manifest.txt") << "shape twin two.so\n";
    }
    Registry reg;
    reg.addModuleDirectory(bare);  // warns about libhelper.so
    auto all = reg.list();
    CHECK(all == std::vector<std::pair<std::string, std::string>>{{"bsdf", "fake"}});
    Properties p("bsdf", "fake");
    CHECK(errorOf([&] { reg.create("bsdf", "fake", p); }).find("bsdf-fake.so") != std::string::npos);

    // The later directory wins (with a warning): its module is the one loaded.
    reg.addModuleDirectory(first);
    reg.addModuleDirectory(second);
    reg.addModuleDirectory(base / "missing");  // warns, adds nothing
    CHECK(reg.list().size() == 2);
    Properties q("shape", "twin");
    std::string e = errorOf([&] { reg.create("shape", "twin", q); });
    CHECK(e.find("two.so") != std::string::npos);
    CHECK(e.find("one.so") == std::string::npos);
    fs::remove_all(base);
}

TEST_CASE("tests: no test name contains a semicolon (ctest would split and skip it)", "[registry]") {
    namespace fs = std::filesystem;
    for (const auto& entry : fs::directory_iterator(EFFIGI_SOURCE_DIR "/tests")) {
        if (entry.path().extension() != ".cpp") continue;
        std::ifstream in(entry.path());
        std::string line;
        int n = 0;
        while (std::getline(in, line)) {
            ++n;
            auto at = line.find("TEST_CASE(\"");
            if (at == std::string::npos) continue;
            auto end = line.find('"', at + 11);
            INFO(entry.path().filename().string() << ":" << n);
            CHECK(line.substr(at, end - at).find(';') == std::string::npos);
        }
    }
}
