// `effigi convert`: a rendered spectral EXR (the Cornell box, 32 bins) collapsed to RGB
// matches the film's own RGB output; bad input gives one line and exit code 1.
#include "app_runner.hpp"
#include "film_helpers.hpp"
#include "image_helpers.hpp"

#include "effigi/spectral/colorspace.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace effigi;
using namespace effigi::test;
namespace fs = std::filesystem;

namespace {
PropertyValue I(std::int64_t v) { return PropertyValue(v); }
} // namespace

TEST_CASE("effigi convert of a rendered spectral EXR matches the film's RGB", "[spectral_exr][app]") {
    // The Cornell box with 32 bins over 360-830 nm, written float32 so that the
    // comparison is not limited by half floats.
    // The scene directory is copied (scene.xml may <include> its neighbours) and the copy
    // of scene.xml gets the film parameters.
    auto dir = tempDir("convert");
    const fs::path sceneDir = EFFIGI_SOURCE_DIR "/scenes/cornell-box";
    for (const auto& e : fs::directory_iterator(sceneDir))
        if (e.is_regular_file()) fs::copy_file(e.path(), dir / e.path().filename());
    std::ifstream in(sceneDir / "scene.xml");
    std::stringstream ss;
    ss << in.rdbuf();
    std::string xml = ss.str();
    const std::string filter = "<rfilter type=\"gaussian\"/>";
    const auto pos = xml.find(filter);
    REQUIRE(pos != std::string::npos);
    xml.insert(pos + filter.size(), "<integer name=\"spectral_bins\" value=\"32\"/>"
                                    "<string name=\"component_format\" value=\"float32\"/>");
    std::ofstream(dir / "scene.xml") << xml;

    AppResult r = runApp(fmt::format("render {} -o {} -D spp=256 -D res=32 --no-progress", (dir / "scene.xml").string(),
                                     (dir / "box.exr").string()));
    INFO(r.out);
    REQUIRE(r.exitCode == 0);
    REQUIRE(fs::exists(dir / "box.spectral.exr"));
    r = runApp(fmt::format("convert {} {}", (dir / "box.spectral.exr").string(), (dir / "conv.exr").string()));
    INFO(r.out);
    REQUIRE(r.exitCode == 0);
    r = runApp(fmt::format("convert {} {}", (dir / "box.spectral.exr").string(), (dir / "conv.png").string()));
    REQUIRE(r.exitCode == 0);

    ExrImage film = readExr(dir / "box.exr"), conv = readExr(dir / "conv.exr"), sp = readExr(dir / "box.spectral.exr");
    REQUIRE(conv.spec.width == film.spec.width);
    REQUIRE(conv.spec.height == film.spec.height);
    // Header metadata: scene, spp, time and version in both EXRs the render wrote, and
    // carried over by convert.
    for (const char* key : {"effigi/scene", "effigi/spp", "effigi/seconds", "effigi/version"}) {
        INFO(key);
        CHECK_FALSE(film.spec.get_string_attribute(key).empty());
        CHECK(sp.spec.get_string_attribute(key) == film.spec.get_string_attribute(key));
        CHECK(conv.spec.get_string_attribute(key) == film.spec.get_string_attribute(key));
    }
    CHECK(film.spec.get_string_attribute("effigi/spp") == "256");

    // Two kinds of difference. (1) Bin quantisation, a bias: the film's XYZ integrates
    // the spectrum against x̄ exactly, the bins only know 14.7 nm means; with convert's
    // linear reconstruction it is ≤ 0.1 % of Y per XYZ channel for smooth spectra (test
    // above), at most ~3× that in R, G, B (|entries| of XYZ -> sRGB ≤ 3.24). (2) Noise: a
    // sample at λ weighs x̄(λ) in the film's XYZ but the bin's reconstruction in the bins;
    // zero-mean, it falls as 1/√spp (per pixel ~1.4 % of Y in R at 256 spp, 0.7 % at 1024).
    // Checks at 256 spp, per channel:
    //   mean relative difference Σ|conv − film| / Σ|film| < 1 %   (noise and bias; the bound)
    //   mean over pixels of (conv − film) / Y, |·| < 0.3 %       (the bias: noise averages out)
    const Vector3f luma = RGBColorSpace::get(ColorSpaceId::SRGB).luminanceWeights();
    for (int c = 0; c < 3; ++c) {
        double absDiff = 0.0, absFilm = 0.0, signedRel = 0.0;
        const int n = film.spec.width * film.spec.height;
        for (int y = 0; y < film.spec.height; ++y)
            for (int x = 0; x < film.spec.width; ++x) {
                double a = conv.at(x, y, c), b = film.at(x, y, c);
                double Y = dot(luma, Vector3f(film.at(x, y, 0), film.at(x, y, 1), film.at(x, y, 2)));
                REQUIRE(Y > 0.0);  // every pixel of the box sees light
                absDiff += std::abs(a - b), absFilm += std::abs(b), signedRel += (a - b) / Y;
            }
        signedRel /= n;
        WARN("channel " << "RGB"[c] << ": mean relative difference " << absDiff / absFilm
                        << ", mean difference / Y " << signedRel);
        CHECK(absDiff / absFilm < 0.01);
        CHECK(std::abs(signedRel) < 0.003);
    }
    // Another colour space: convert's ACEScg equals the film's sRGB taken to ACEScg.
    r = runApp(fmt::format("convert {} {} --colorspace acescg", (dir / "box.spectral.exr").string(),
                           (dir / "aces.exr").string()));
    REQUIRE(r.exitCode == 0);
    ExrImage aces = readExr(dir / "aces.exr");
    CHECK(aces.spec.get_string_attribute("effigi/colorspace") == "acescg");
    const RGBColorSpace& ap1 = RGBColorSpace::get(ColorSpaceId::ACEScg);
    double absDiff = 0.0, absFilm = 0.0;
    for (int y = 0; y < film.spec.height; ++y)
        for (int x = 0; x < film.spec.width; ++x) {
            Vector3f want = ap1.fromXYZ(linearSRGBToXYZ(Vector3f(film.at(x, y, 0), film.at(x, y, 1), film.at(x, y, 2))));
            for (int c = 0; c < 3; ++c) absDiff += std::abs(aces.at(x, y, c) - want[c]), absFilm += std::abs(want[c]);
        }
    WARN("ACEScg: mean relative difference " << absDiff / absFilm);
    CHECK(absDiff / absFilm < 0.01);
    // The PNGs: 8-bit sRGB of the same image; bytes differ by at most a few levels.
    auto png = [](const fs::path& f) {
        ExrImage img = readExr(f);
        return img;
    };
    ExrImage pa = png(dir / "conv.png"), pb = png(dir / "box.png");
    REQUIRE(pa.px.size() == pb.px.size());
    double meanLevels = 0.0;
    for (std::size_t i = 0; i < pa.px.size(); ++i) meanLevels += std::abs(pa.px[i] - pb.px[i]) * 255.0;
    meanLevels /= double(pa.px.size());
    WARN("PNG mean |difference| " << meanLevels << " levels");
    CHECK(meanLevels < 1.0);
    fs::remove_all(dir);
}

TEST_CASE("effigi convert rejects bad input with one line", "[spectral_exr][app]") {
    auto dir = tempDir("convert-errors");
    AppResult r = runApp(fmt::format("convert {} {}", (dir / "missing.exr").string(), (dir / "o.png").string()));
    CHECK(r.exitCode == 1);
    CHECK_THAT(r.out, Catch::Contains("cannot read") && Catch::Contains("missing.exr"));
    // An RGB EXR without spectral channels.
    Ref<IFilm> film = makeFilm({{"width", I(2)}, {"height", I(2)}, {"png", PropertyValue(false)}}, "box");
    film->prepare({"X", "Y", "Z"});
    film->write(dir / "rgb.exr", {});
    r = runApp(fmt::format("convert {} {}", (dir / "rgb.exr").string(), (dir / "o.png").string()));
    CHECK(r.exitCode == 1);
    CHECK_THAT(r.out, Catch::Contains("not a spectral EXR"));
    r = runApp(fmt::format("convert {} {} --colorspace p3", (dir / "rgb.exr").string(), (dir / "o.exr").string()));
    CHECK(r.exitCode == 1);
    CHECK_THAT(r.out, Catch::Contains("--colorspace"));
    r = runApp(fmt::format("convert {} {} --tonemap x", (dir / "rgb.exr").string(), (dir / "o.png").string()));
    CHECK(r.exitCode == 1);
    r = runApp(fmt::format("convert {} {}", (dir / "rgb.exr").string(), (dir / "o.tif").string()));
    CHECK(r.exitCode == 1);
    r = runApp("convert");
    CHECK(r.exitCode == 1);
    fs::remove_all(dir);
}
