// What the fuzz targets (fuzz/, issue 12) found, checked precisely. Every input that broke
// a target is kept in tests/data/regressions/<target>/ and replayed by ctest fuzz:<target>,
// which only asks "no finding"; the cases here check the specific answer to each one (the
// message names the right thing, escaped), and the loader defects met while writing the
// seeds. Messages are checked with the fuzz targets' own rule, isOnePrintableLine().
#include "../fuzz/fuzz_common.hpp"
#include "temp_files.hpp"
#include "xml_helpers.hpp"

#include "effigi/render/bitmap.hpp"
#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

#include <catch2/catch.hpp>

#include <cstdint>
#include <filesystem>
#include <string>

using namespace effigi;
using namespace effigi::test;
using Catch::Contains;
namespace fs = std::filesystem;

namespace {

const fs::path kRegressions = fs::path(EFFIGI_SOURCE_DIR) / "tests/data/regressions";

/// The message of loading the regression input `name` (a scene) as a scene file.
std::string sceneError(const std::string& name) {
    std::string msg = errorOf([&] { loadSceneFile(kRegressions / name); });
    INFO("message: " << msg);
    CHECK(fuzz::isOnePrintableLine(msg));
    return msg;
}

} // namespace

TEST_CASE("fuzz xml: an unknown <ref> quotes the scene's ids escaped") {
    // ids "gr\xB5up" (not UTF-8) and "bell\x07" (a control byte): the hint and the list of
    // ids quoted them raw, so the message carried the bytes themselves.
    std::string msg = sceneError("xml/ref-unknown-id-list-not-escaped.xml");
    CHECK_THAT(msg, Contains("did you mean 'gr\\xB5up'?"));
    CHECK_THAT(msg, Contains("ids in the scene: bell\\x07, gr\\xB5up)"));
}

TEST_CASE("fuzz xml: a circular <ref> names the ids of the cycle escaped") {
    std::string msg = sceneError("xml/ref-cycle-ids-not-escaped.xml");
    CHECK_THAT(msg, Contains("circular reference a\\x07 -> b -> a\\x07"));
}

TEST_CASE("fuzz xml: a second root element is named escaped") {
    std::string msg = sceneError("xml/second-root-element-name-not-escaped.xml");
    CHECK_THAT(msg, Contains("second-root-element-name-not-escaped.xml:2: malformed XML: a second root element "
                             "<sc\\xA4\\x93\\x90\\x9E>"));
}

TEST_CASE("fuzz xml: a long list of ids in a message is cut short") {
    std::string xml = "<scene version=\"3.0.0\">";
    for (int i = 0; i < 50; ++i) xml += fmt::format("<bsdf type=\"diffuse\" id=\"b{:02}\"/>", i);
    xml += "<shape type=\"sphere\"><ref id=\"nope\"/></shape></scene>";
    std::string msg = errorOf([&] { loadScene(*xml::parseString(xml, "long.xml")); });
    CHECK_THAT(msg, Contains("b19, … (30 more))"));
    CHECK_THAT(msg, !Contains("b20"));
}

TEST_CASE("integrators nest in integrators at any depth, as in Mitsuba (moment > aov > path)") {
    // The loader took a nested <integrator> for a renderer only when its parent was
    // written as a top-level <integrator>, so `path` inside `aov` inside `moment` was
    // looked up among the numerical integrators and refused.
    const std::string xml = R"(<scene version="3.0.0">
        <integrator type="moment">
            <integrator type="aov"><string name="aovs" value="dd.y:depth"/><integrator type="path"/></integrator>
        </integrator>
        <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/>
            <integer name="height" value="4"/></film></sensor>
        <shape type="sphere"/>
    </scene>)";
    std::unique_ptr<Scene> scene = loadScene(*xml::parseString(xml, "nested.xml"));
    REQUIRE(scene);
    CHECK(scene->renderer().typeName() == "renderer/moment");
}

TEST_CASE("fuzz image: an OpenEXR header attribute larger than the file is refused before OpenEXR allocates it") {
    // 35 bytes declaring a 2 GiB attribute of unknown type: OpenEXR allocated the 2 GiB
    // (Imf::OpaqueAttribute) before finding the file too short.
    std::string msg = errorOf([] { Bitmap::load(kRegressions / "image/exr-attribute-claims-2gib.exr"); });
    CHECK(fuzz::isOnePrintableLine(msg));
    CHECK_THAT(msg, Contains("corrupt OpenEXR header (attribute 'comments' claims 2147483632 bytes, the file has 3 left)"));
}

TEST_CASE("fuzz image: the OpenEXR header check walks every header of a multi-part file") {
    // Two headers: the first sound, the second claiming more than the file holds.
    std::string b = "v/1\x01";
    put<std::uint32_t>(b, 2 | 0x1000);  // version 2, multi-part
    b += std::string("name\0string\0", 12);
    put<std::int32_t>(b, 1);
    b += "a";
    b += '\0';  // end of header 1
    b += std::string("comments\0opaque\0", 16);
    put<std::int32_t>(b, 1 << 30);
    b += "xyz";
    const ScratchDir scratch("fuzz_regressions");
    std::string msg = errorOf([&] { Bitmap::load(scratch.write("multipart.exr", b)); });
    CHECK_THAT(msg, Contains("attribute 'comments' claims 1073741824 bytes, the file has 3 left"));
}

TEST_CASE("fuzz image: sound OpenEXR files pass the header check") {
    for (const fs::path& f : {fs::path(EFFIGI_SOURCE_DIR) / "fuzz/corpus/image/tiny.exr",
                              fs::path(EFFIGI_SOURCE_DIR) / "tests/data/emitters/sky.exr"}) {
        INFO(f.string());
        Bitmap bmp = Bitmap::load(f);
        CHECK(bmp.width() > 0);
        CHECK(bmp.channels() >= 3);
    }
}
