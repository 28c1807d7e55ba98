// Film: hdrfilm development (XYZ -> sRGB), pixel formats and AOVs, block merging,
// EXR/PNG output, crop windows, errors.
#include "film_helpers.hpp"

#include "effigi/interfaces/ifilm.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/render/image_block.hpp"
#include "effigi/spectral/colorspace.hpp"

#include <OpenImageIO/imageio.h>
#include <catch2/catch.hpp>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <thread>

using namespace effigi;
using namespace effigi::test;
namespace fs = std::filesystem;

namespace {

using Params = std::vector<std::pair<std::string, PropertyValue>>;

PropertyValue I(std::int64_t v) { return PropertyValue(v); }
PropertyValue S(const char* v) { return PropertyValue(std::string(v)); }

/// A fresh temporary directory, removed at scope exit.
struct TempDir {
    fs::path path;
    TempDir() {
        path = fs::temp_directory_path() / fmt::format("effigi_test_film_{}", ::getpid());
        fs::remove_all(path);
        fs::create_directories(path);
    }
    ~TempDir() {
        std::error_code ec;
        fs::remove_all(path, ec);
    }
};

/// Reads an image with OpenImageIO as floats; returns the spec.
OIIO::ImageSpec readImage(const fs::path& file, std::vector<float>& pixels) {
    auto in = OIIO::ImageInput::open(file.string());
    REQUIRE(in);
    OIIO::ImageSpec spec = in->spec();
    pixels.resize(std::size_t(spec.width) * spec.height * spec.nchannels);
    REQUIRE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data()));
    in->close();
    return spec;
}

} // namespace

TEST_CASE("a film of constant D65 white develops to linear sRGB (1,1,1)", "[film]") {
    // Default filter (gaussian, created by the film itself); samples everywhere.
    Ref<IFilm> film = makeFilm({{"width", I(12)}, {"height", I(9)}});
    CHECK(film->size() == Vector2i(12, 9));
    CHECK(film->filter().radius() == Approx(2.f));
    film->prepare({"X", "Y", "Z"});
    ImageBlock block = film->createBlock({0, 0}, film->size());
    const float white[3] = {0.95047f, 1.f, 1.08883f};
    PCG32 rng(42, 3);
    for (int k = 0; k < 2000; ++k) block.put(Point2f(12.f * rng.nextFloat(), 9.f * rng.nextFloat()), white);
    film->put(block);
    Image img = film->develop();
    REQUIRE(img.width == 12);
    REQUIRE(img.height == 9);
    REQUIRE(img.channelNames == std::vector<std::string>{"R", "G", "B"});
    for (int y = 0; y < 9; ++y)
        for (int x = 0; x < 12; ++x)
            for (int c = 0; c < 3; ++c) CHECK(img.at(x, y, c) == Approx(1.f).margin(1e-3));
}

TEST_CASE("pixel formats and AOV channels", "[film]") {
    const float v[5] = {0.95047f, 1.f, 1.08883f, 0.25f, 0.75f};
    auto develop = [&](const char* format) {
        Ref<IFilm> film = makeFilm({{"width", I(2)}, {"height", I(2)}, {"pixel_format", S(format)}}, "box");
        film->prepare({"X", "Y", "Z", "albedo.R", "albedo.G"});
        ImageBlock b = film->createBlock({0, 0}, {2, 2});
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x) b.put(Point2f(float(x) + 0.5f, float(y) + 0.5f), v);
        film->put(b);
        return film->develop();
    };
    Image rgba = develop("rgba");
    CHECK(rgba.channelNames == std::vector<std::string>{"R", "G", "B", "A", "albedo.R", "albedo.G"});
    CHECK(rgba.at(1, 1, 3) == 1.f);
    CHECK(rgba.at(1, 1, 4) == 0.25f);
    CHECK(rgba.at(0, 1, 5) == 0.75f);
    Image xyz = develop("xyz");
    CHECK(xyz.channelNames == std::vector<std::string>{"X", "Y", "Z", "albedo.R", "albedo.G"});
    CHECK(xyz.at(0, 0, 2) == Approx(1.08883f));
    Image lum = develop("luminance");
    CHECK(lum.channelNames == std::vector<std::string>{"Y", "albedo.R", "albedo.G"});
    CHECK(lum.at(1, 0, 0) == Approx(1.f));
    // Pixels without samples develop to 0, not NaN.
    Ref<IFilm> empty = makeFilm({{"width", I(3)}, {"height", I(2)}}, "box");
    empty->prepare({"X", "Y", "Z"});
    Image e = empty->develop();
    for (float p : e.pixels) CHECK(p == 0.f);
    // A clash between an AOV name and a colour channel is an error, not a silent overwrite.
    CHECK_THROWS_AS(empty->prepare({"X", "Y", "Z", "R"}), Error);
    CHECK_THROWS_AS(empty->prepare({"a", "a"}), Error);
}

TEST_CASE("blocks from two threads merge to the image of one block", "[film]") {
    const Params params{{"width", I(16)}, {"height", I(12)}, {"pixel_format", S("xyz")}};
    Ref<IFilm> one = makeFilm(params, "gaussian"), two = makeFilm(params, "gaussian");
    one->prepare({"X", "Y", "Z", "aov"});
    two->prepare({"X", "Y", "Z", "aov"});
    struct Sample { Point2f p; float v[4]; };
    std::vector<Sample> samples;
    PCG32 rng(1234, 5);
    for (int k = 0; k < 3000; ++k) {
        Sample s{Point2f(16.f * rng.nextFloat(), 12.f * rng.nextFloat()), {}};
        for (float& v : s.v) v = rng.nextFloat();
        samples.push_back(s);
    }
    ImageBlock whole = one->createBlock({0, 0}, {16, 12});
    for (const Sample& s : samples) whole.put(s.p, s.v);
    one->put(whole);

    // Left and right halves, each splatting only the samples inside it, in parallel.
    auto half = [&](int x0) {
        ImageBlock b = two->createBlock({x0, 0}, {8, 12});
        for (const Sample& s : samples)
            if (s.p.x >= float(x0) && s.p.x < float(x0 + 8)) b.put(s.p, s.v);
        two->put(b);
    };
    std::thread left(half, 0), right(half, 8);
    left.join();
    right.join();

    Image a = one->develop(), b = two->develop();
    REQUIRE(a.pixels.size() == b.pixels.size());
    REQUIRE(a.pixels.size() == std::size_t(16 * 12 * 4));
    for (std::size_t i = 0; i < a.pixels.size(); ++i) CHECK(a.pixels[i] == Approx(b.pixels[i]).epsilon(1e-5));
}

TEST_CASE("EXR round trip keeps pixels and metadata, PNG written beside", "[film]") {
    TempDir tmp;
    for (const char* format : {"float32", "float16"}) {
        INFO(format);
        Ref<IFilm> film = makeFilm({{"width", I(5)}, {"height", I(3)}, {"component_format", S(format)}}, "box");
        film->prepare({"X", "Y", "Z", "albedo.R", "albedo.G", "albedo.B"});
        ImageBlock b = film->createBlock({0, 0}, {5, 3});
        for (int y = 0; y < 3; ++y)
            for (int x = 0; x < 5; ++x) {
                Vector3f xyz = linearSRGBToXYZ(Vector3f(0.1f * float(x), 0.2f * float(y), 0.5f));
                float v[6] = {xyz.x, xyz.y, xyz.z, 0.1f * float(x + y), 0.5f, 2.f};
                b.put(Point2f(float(x) + 0.5f, float(y) + 0.5f), v);
            }
        film->put(b);
        const Image img = film->develop();

        fs::path exr = tmp.path / fmt::format("img_{}.exr", format);
        auto files = film->write(exr, {{"spp", "16"}, {"scene", "test scene.xml"}});
        REQUIRE(files.size() == 2);
        CHECK(files[0] == exr);
        CHECK(files[1] == tmp.path / fmt::format("img_{}.png", format));
        CHECK(fs::exists(files[0]));
        CHECK(fs::exists(files[1]));

        std::vector<float> px;
        OIIO::ImageSpec spec = readImage(exr, px);
        REQUIRE(spec.width == 5);
        REQUIRE(spec.height == 3);
        REQUIRE(spec.nchannels == 6);
        CHECK(spec.get_string_attribute("spp") == "16");
        CHECK(spec.get_string_attribute("scene") == "test scene.xml");
        CHECK(spec.get_string_attribute("compression") == "zip");
        const double tol = std::string(format) == "float16" ? 1e-3 : 1e-7;
        for (int c = 0; c < img.channels(); ++c) {
            auto it = std::find(spec.channelnames.begin(), spec.channelnames.end(), img.channelNames[std::size_t(c)]);
            REQUIRE(it != spec.channelnames.end());
            int fc = int(it - spec.channelnames.begin());
            for (int y = 0; y < 3; ++y)
                for (int x = 0; x < 5; ++x) {
                    float want = img.at(x, y, c);
                    float got = px[(std::size_t(y) * 5 + std::size_t(x)) * 6 + std::size_t(fc)];
                    CHECK(got == Approx(want).epsilon(tol).margin(1e-4));
                }
        }
        CHECK(img.at(4, 2, 0) == Approx(0.4f).margin(1e-5));  // R came back from XYZ

        // The PNG: 8-bit sRGB of the first three channels.
        std::vector<float> png;
        OIIO::ImageSpec pspec = readImage(files[1], png);
        CHECK(pspec.width == 5);
        CHECK(pspec.nchannels == 3);
        CHECK(pspec.format == OIIO::TypeDesc::UINT8);
        for (int y = 0; y < 3; ++y)
            for (int x = 0; x < 5; ++x)
                for (int c = 0; c < 3; ++c) {
                    float want = std::round(srgbEncode(std::clamp(img.at(x, y, c), 0.f, 1.f)) * 255.f) / 255.f;
                    CHECK(png[(std::size_t(y) * 5 + std::size_t(x)) * 3 + std::size_t(c)] == Approx(want).margin(1e-6));
                }
    }

    // png=false writes only the EXR; a .png path writes only the PNG.
    Ref<IFilm> film = makeFilm({{"width", I(4)}, {"height", I(4)}, {"png", PropertyValue(false)}});
    film->prepare({"X", "Y", "Z"});
    auto files = film->write(tmp.path / "only.exr", {});
    CHECK(files == std::vector<fs::path>{tmp.path / "only.exr"});
    CHECK_FALSE(fs::exists(tmp.path / "only.png"));
    files = film->write(tmp.path / "preview.png", {});
    CHECK(files == std::vector<fs::path>{tmp.path / "preview.png"});
    CHECK(fs::exists(tmp.path / "preview.png"));
    CHECK_FALSE(fs::exists(tmp.path / "preview.exr"));
}

TEST_CASE("crop window renders and writes only the crop", "[film]") {
    TempDir tmp;
    Ref<IFilm> film = makeFilm({{"width", I(8)},
                                {"height", I(6)},
                                {"crop_offset_x", I(2)},
                                {"crop_offset_y", I(1)},
                                {"crop_width", I(4)},
                                {"crop_height", I(3)},
                                {"pixel_format", S("xyz")}},
                               "box");
    CHECK(film->size() == Vector2i(4, 3));
    CHECK(film->fullSize() == Vector2i(8, 6));
    CHECK(film->cropOffset() == Point2i(2, 1));
    film->prepare({"X", "Y", "Z"});
    // A renderer splats in the crop frame and hands pFilm = p + cropOffset to the
    // camera; here the "radiance" is the full-film position the camera would see.
    // The block is larger than the crop: what falls outside is dropped.
    ImageBlock block = film->createBlock({-2, -1}, {8, 6});
    for (int y = -1; y < 5; ++y)
        for (int x = -2; x < 6; ++x) {
            Point2f p(float(x) + 0.5f, float(y) + 0.5f);
            Point2f pFilm = p + Point2f(film->cropOffset());
            float v[3] = {pFilm.x, pFilm.y, 1.f};
            block.put(p, v);
        }
    film->put(block);
    Image img = film->develop();
    REQUIRE(img.width == 4);
    REQUIRE(img.height == 3);
    for (int y = 0; y < 3; ++y)
        for (int x = 0; x < 4; ++x) {
            CHECK(img.at(x, y, 0) == Approx(float(x + 2) + 0.5f));
            CHECK(img.at(x, y, 1) == Approx(float(y + 1) + 0.5f));
        }
    auto files = film->write(tmp.path / "crop.exr", {});
    std::vector<float> px;
    OIIO::ImageSpec spec = readImage(files.at(0), px);
    CHECK(spec.width == 4);
    CHECK(spec.height == 3);

    // Default crop: the whole film; the crop offset alone shrinks it to the rest.
    Ref<IFilm> rest = makeFilm({{"width", I(8)}, {"height", I(6)}, {"crop_offset_x", I(5)}});
    CHECK(rest->size() == Vector2i(3, 6));
    CHECK(rest->cropOffset() == Point2i(5, 0));
    // A crop window outside the film is an error naming the parameter.
    CHECK_THROWS_WITH(makeFilm({{"width", I(8)}, {"height", I(6)}, {"crop_offset_x", I(4)}, {"crop_width", I(5)}}),
                      Catch::Contains("crop_width"));
    CHECK_THROWS_AS(makeFilm({{"width", I(8)}, {"crop_offset_y", I(576)}}), Error);
}

TEST_CASE("bad parameters and unwritable paths are effigi::Error", "[film]") {
    CHECK_THROWS_WITH(makeFilm({{"file_format", S("rgbe")}}), Catch::Contains("openexr"));
    CHECK_THROWS_AS(makeFilm({{"pixel_format", S("rgbx")}}), Error);
    CHECK_THROWS_AS(makeFilm({{"component_format", S("uint8")}}), Error);
    CHECK_THROWS_AS(makeFilm({{"width", I(0)}}), Error);

    Ref<IFilm> film = makeFilm({{"width", I(4)}, {"height", I(4)}});
    film->prepare({"X", "Y", "Z"});
    CHECK_THROWS_WITH(film->write("/nonexistent-effigi-dir/img.exr", {}),
                      Catch::StartsWith("cannot write /nonexistent-effigi-dir/img.exr: "));
    CHECK_THROWS_WITH(film->write("/nonexistent-effigi-dir/img.png", {}),
                      Catch::StartsWith("cannot write /nonexistent-effigi-dir/img.png: "));
    CHECK_THROWS_AS(film->write("/tmp/img.jpg", {}), Error);
    // A directory where the file should be: the library's own reason is passed on.
    TempDir tmp;
    fs::create_directories(tmp.path / "taken.exr");
    CHECK_THROWS_WITH(film->write(tmp.path / "taken.exr", {}), Catch::StartsWith("cannot write "));
    // Merging a block with the wrong channel count is refused.
    Ref<IFilm> other = makeFilm({{"width", I(4)}, {"height", I(4)}});
    other->prepare({"X", "Y", "Z", "extra"});
    CHECK_THROWS_AS(film->put(other->createBlock({0, 0}, {4, 4})), Error);
}
