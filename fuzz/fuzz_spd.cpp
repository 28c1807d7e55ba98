// Fuzz target: spectrum files (<spectrum filename="x.spd"/>: two columns "wavelength
// value" per line, '#' comments; read by src/xml/values.cpp), and the spectra made of them
// (src/spectral/spectrum.cpp).
//
// Why: the file is text of any length and encoding; its numbers must be finite, in float
// range and in ascending wavelength order, and its errors quote the offending line, which
// must come out as one printable line whatever bytes the line holds. The reader has no
// entry point of its own (the XML parser calls it for a <spectrum> element), so the input
// is written to x.spd in the scratch folder and a scene naming it is parsed; the objects
// that use it are then built, a diffuse BSDF (a reflectance: checked against [0, 1]
// where the renderer needs it) and a constant environment (an emission: peak checks).
#include "fuzz_common.hpp"

#include "effigi/xml/loader.hpp"
#include "effigi/xml/parser.hpp"

using namespace effigi;

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    fuzz::quiet();
    fuzz::preload({{"bsdf", "diffuse"}, {"emitter", "constant"}});
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::filesystem::path& dir = fuzz::scratchDir("spd");
    fuzz::writeInput(dir / "x.spd", data, size);
    static const std::string scene = R"(<scene version="3.0.0">
    <bsdf type="diffuse" id="b"><spectrum name="reflectance" filename="x.spd"/></bsdf>
    <emitter type="constant" id="e"><spectrum name="radiance" filename="x.spd"/></emitter>
</scene>)";
    std::unique_ptr<xml::Node> root;
    fuzz::expectCleanRejection([&] { root = xml::parseString(scene, (dir / "scene.xml").string()); });
    if (root)  // each object on its own: a reflectance above 1 must not hide the emitter's checks
        for (const xml::Child& c : root->children)
            fuzz::expectCleanRejection([&] { instantiate(*c.node, Registry::instance()); });
    return 0;
}
