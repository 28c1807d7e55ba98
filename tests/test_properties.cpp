// Properties: typed access, conversions, locations, file names relative to the scene.
#include "effigi/core/properties.hpp"
#include "effigi/interfaces/itexture.hpp"

#include <catch2/catch.hpp>

using namespace effigi;

namespace {
// A texture that is nothing but a texture, to nest in properties.
class ConstantTextureProbe final : public Implements<ITexture> {
public:
    SampledSpectrum eval(const SurfaceInteraction&, const SampledWavelengths&) const override {
        return SampledSpectrum(0.5f);
    }
    float evalFloat(const SurfaceInteraction&) const override { return 0.5f; }
    float maxValue() const override { return 0.5f; }
};
} // namespace

TEST_CASE("properties: typed getters and their conversions", "[properties]") {
    Properties p("shape", "sphere", {"scene.xml", 4});
    p.set("radius", 2.5, {"scene.xml", 5});
    p.set("count", std::int64_t(3), {"scene.xml", 6});
    p.set("flip", true, {"scene.xml", 7});
    p.set("centre", PointValue{{1.f, 2.f, 3.f}}, {"scene.xml", 8});
    p.set("colour", RGBValue{{0.2f, 0.4f, 0.6f}}, {"scene.xml", 9});
    CHECK(p.getFloat("radius") == 2.5f);
    CHECK(p.getFloat("count") == 3.f);  // integers read as floats
    CHECK(p.getInt("count") == 3);
    CHECK(p.getBool("flip"));
    CHECK(p.getPoint("centre") == Point3f(1.f, 2.f, 3.f));
    CHECK(p.getVector("centre") == Vector3f(1.f, 2.f, 3.f));
    CHECK(p.whereOf("colour").line == 9);
    CHECK(p.whereOf("absent").line == 4);  // falls back to the element

    // A float read as a spectrum is a constant; an rgb becomes a smooth reflectance.
    SampledWavelengths lambda = SampledWavelengths::sampleVisible(0.3f);
    CHECK(p.getSpectrum("radius", SpectrumKind::Unbounded).sample(lambda)[2] == 2.5f);
    Ref<ITexture> tex = p.getTexture("colour", SpectrumKind::Reflectance);
    REQUIRE(tex);
    CHECK(tex->isConstant());
    CHECK(tex->maxValue() <= 1.f);

    auto message = [&](auto f) {
        try {
            f();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    CHECK(message([&] { p.getInt("radius"); }) == "scene.xml:5: shape 'sphere': parameter 'radius' must be an integer, got float");
    CHECK(message([&] { p.getString("absent"); }) == "scene.xml:4: shape 'sphere': missing parameter 'absent'");
    CHECK(message([&] { p.set("radius", 1.0, {"scene.xml", 11}); }) ==
          "scene.xml:11: shape 'sphere': parameter 'radius' given twice (first at line 5)");
}

TEST_CASE("properties: file names resolve against the file they were written in", "[properties]") {
    Properties p("shape", "ply", {"/data/scenes/room/scene.xml", 3});
    p.set("filename", std::string("meshes/chair.ply"), {"/data/scenes/room/parts/furniture.xml", 12});
    p.set("absolute", std::string("/tmp/x.ply"), {"/data/scenes/room/scene.xml", 13});
    CHECK(p.getPath("filename") == std::filesystem::path("/data/scenes/room/parts/meshes/chair.ply"));
    CHECK(p.getPath("absolute") == std::filesystem::path("/tmp/x.ply"));
}

TEST_CASE("properties: nested objects by name and by tag", "[properties]") {
    Properties p("bsdf", "diffuse");
    auto tex = std::make_shared<ConstantTextureProbe>();
    p.set("reflectance", ComponentValue{"texture", tex});
    p.set("", ComponentValue{"texture", tex});
    p.set("", ComponentValue{"texture", tex});
    CHECK(p.getComponent("reflectance") == tex);
    CHECK(p.get<ITexture>("reflectance").get() == static_cast<ITexture*>(tex.get()));
    CHECK(p.components("texture").size() == 3);
    CHECK(p.getComponent("absent") == nullptr);
}
