// Textures (issue 10), part one: Bitmap loading and its errors, and the bitmap texture
// against independent formulas (bilinear and nearest lookups in every wrap mode, the
// gradient, sRGB upsampling). The checkerboard and mesh_attribute textures, PLY
// attributes, textured roughness and the render against Mitsuba 3 are in
// test_textures_procedural.cpp.
#include "app_runner.hpp"
#include "texture_helpers.hpp"

#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/itexture_resolution.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/render/bitmap.hpp"

#include <catch2/catch.hpp>

#include <OpenImageIO/imageio.h>

#include <fstream>

using namespace effigi;
using namespace effigi::test;
namespace fs = std::filesystem;

namespace {

void writeImage(const fs::path& p, int w, int h, int c, const std::vector<float>& px, OIIO::TypeDesc type) {
    auto out = OIIO::ImageOutput::create(p.string());
    REQUIRE(out);
    OIIO::ImageSpec spec(w, h, c, type);
    REQUIRE(out->open(p.string(), spec));
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, px.data()));
    REQUIRE(out->close());
}

Ref<ITexture> bitmapTexture(const fs::path& file, const std::string& filter, const std::string& wrap) {
    Properties p("texture", "bitmap");
    p.set("filename", file.string());
    p.set("filter_type", filter);
    p.set("wrap_mode", wrap);
    return makeTexture("bitmap", p);
}

/// Texel index under a wrap mode, written independently of the texture's code.
int wrapIndex(int i, int n, const std::string& mode) {
    if (mode == "clamp") return std::min(std::max(i, 0), n - 1);
    if (mode == "repeat") return ((i % n) + n) % n;
    int period = 2 * n, r = ((i % period) + period) % period;  // mirror
    return r < n ? r : period - 1 - r;
}

/// Bilinear reconstruction as a sum of tent functions centred on the texels (x + ½)/W.
double bilinearReference(const std::vector<float>& img, int w, int h, double u, double v, const std::string& mode) {
    double x = u * w - 0.5, y = v * h - 0.5, sum = 0.0;
    for (int j = int(std::floor(y)); j <= int(std::floor(y)) + 1; ++j)
        for (int i = int(std::floor(x)); i <= int(std::floor(x)) + 1; ++i) {
            double wx = std::max(0.0, 1.0 - std::abs(x - i)), wy = std::max(0.0, 1.0 - std::abs(y - j));
            sum += wx * wy * img[std::size_t(wrapIndex(j, h, mode) * w + wrapIndex(i, w, mode))];
        }
    return sum;
}

/// A w × h one-channel float EXR of uniform random values (seeded), written to file.
std::vector<float> randomImage(const fs::path& file, int w, int h, PCG32& rng) {
    std::vector<float> img(std::size_t(w) * std::size_t(h));
    for (float& v : img) v = rng.nextFloat();
    writeImage(file, w, h, 1, img, OIIO::TypeDesc::FLOAT);
    return img;
}

} // namespace

TEST_CASE("textures: Bitmap reads pixels top row first and knows sRGB from linear", "[textures]") {
    fs::path dir = tempDir("tex-bitmap");
    std::vector<float> px = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f};  // 3x2, one channel
    writeImage(dir / "a.exr", 3, 2, 1, px, OIIO::TypeDesc::FLOAT);
    Bitmap exr = Bitmap::load(dir / "a.exr");
    CHECK(exr.width() == 3);
    CHECK(exr.height() == 2);
    CHECK(exr.channels() == 1);
    CHECK_FALSE(exr.srgb());
    CHECK(exr.at(0, 0, 0) == Approx(0.1f));
    CHECK(exr.at(2, 1, 0) == Approx(0.6f));
    Ref<ITexture> tex = bitmapTexture(dir / "a.exr", "nearest", "repeat");
    Ref<ITextureResolution> res = query<ITextureResolution>(tex);
    REQUIRE(res);
    CHECK(res->resolution() == Vector2i(3, 2));

    // 8-bit PNG: sRGB-encoded; decoding follows IEC 61966-2-1.
    std::vector<float> rgb = {128.f / 255.f, 10.f / 255.f, 1.f};
    writeImage(dir / "b.png", 1, 1, 3, rgb, OIIO::TypeDesc::UINT8);
    Bitmap png = Bitmap::load(dir / "b.png");
    CHECK(png.srgb());
    CHECK(png.at(0, 0, 0) == Approx(128.f / 255.f).margin(1e-6));
    png.convertToLinear();
    CHECK_FALSE(png.srgb());
    CHECK(png.at(0, 0, 0) == Approx(std::pow((128.0 / 255.0 + 0.055) / 1.055, 2.4)).epsilon(1e-5));
    CHECK(png.at(0, 0, 1) == Approx(10.0 / 255.0 / 12.92).epsilon(1e-5));  // the linear toe
    CHECK(png.at(0, 0, 2) == Approx(1.f));
    fs::remove_all(dir);
}

TEST_CASE("textures: damaged, missing and non-image files give one-line errors", "[textures]") {
    fs::path dir = tempDir("tex-bad");
    std::vector<float> px(64 * 64 * 3);
    for (std::size_t i = 0; i < px.size(); ++i) px[i] = float(i % 97) / 97.f;
    writeImage(dir / "good.png", 64, 64, 3, px, OIIO::TypeDesc::UINT8);
    writeImage(dir / "good.exr", 64, 64, 3, px, OIIO::TypeDesc::HALF);
    auto truncate = [&](const std::string& from, const std::string& to) {
        std::ifstream in(dir / from, std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        std::ofstream(dir / to, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    };
    truncate("good.png", "half.png");
    truncate("good.exr", "half.exr");
    std::ofstream(dir / "junk.png") << "this is not an image";
    std::ofstream(dir / "junk.exr") << "v/1\x01\x02 not an exr";

    for (const char* name : {"half.png", "half.exr", "junk.png", "junk.exr", "missing.png"}) {
        fs::path file = dir / name;
        INFO(name);
        try {
            Bitmap::load(file);
            FAIL("no error for " << name);
        } catch (const Error& e) {
            std::string msg = e.what();
            INFO(msg);
            CHECK(msg.rfind(file.string() + ": ", 0) == 0);  // file first, then the cause
            CHECK(msg.size() > file.string().size() + 4);
            CHECK(msg.find('\n') == std::string::npos);
        }
        // The CLI: exit status 1 and one line naming the scene line and the image.
        fs::path scene = dir / "scene.xml";
        std::ofstream(scene) << "<scene version=\"3.0.0\">\n<shape type=\"sphere\">\n<bsdf type=\"diffuse\">\n"
                                "<texture type=\"bitmap\" name=\"reflectance\">\n<string name=\"filename\" value=\""
                             << name << "\"/>\n</texture>\n</bsdf>\n</shape>\n</scene>\n";
        AppResult r = runApp("render " + scene.string() + " -o " + (dir / "out.exr").string() + " --no-progress");
        INFO(r.out);
        CHECK(r.exitCode == 1);
        CHECK(std::count(r.out.begin(), r.out.end(), '\n') == 1);
        CHECK(r.out.find(scene.string() + ":5") != std::string::npos);
        CHECK(r.out.find(file.string()) != std::string::npos);
    }
    CHECK(Bitmap::load(dir / "good.exr").width() == 64);  // the originals read fine
    fs::remove_all(dir);
}

TEST_CASE("textures: bitmap lookups match bilinear and nearest reconstruction in every wrap mode", "[textures]") {
    fs::path dir = tempDir("tex-lookup");
    const int w = 5, h = 3;
    PCG32 rng(7, 1);
    const std::vector<float> img = randomImage(dir / "t.exr", w, h, rng);
    for (const std::string mode : {"repeat", "mirror", "clamp"}) {
        Ref<ITexture> bil = bitmapTexture(dir / "t.exr", "bilinear", mode);
        Ref<ITexture> nea = bitmapTexture(dir / "t.exr", "nearest", mode);
        for (int k = 0; k < 200; ++k) {
            float u = -2.5f + 5.f * rng.nextFloat(), v = -2.5f + 5.f * rng.nextFloat();
            INFO(mode << " at (" << u << ", " << v << ")");
            CHECK(bil->evalFloat(at(u, v)) == Approx(bilinearReference(img, w, h, u, v, mode)).margin(1e-5));
            int i = wrapIndex(int(std::floor(u * w)), w, mode), j = wrapIndex(int(std::floor(v * h)), h, mode);
            CHECK(nea->evalFloat(at(u, v)) == img[std::size_t(j * w + i)]);
            // One channel: the spectrum is the value at every wavelength.
            CHECK(nea->eval(at(u, v), SampledWavelengths::constant(500.f))[0] == img[std::size_t(j * w + i)]);
        }
    }
    // NaN and huge coordinates read a texel, never garbage.
    Ref<ITexture> t = bitmapTexture(dir / "t.exr", "bilinear", "repeat");
    float nanValue = t->evalFloat(at(std::nanf(""), 0.5f)), huge = t->evalFloat(at(3e9f, -7e12f));
    CHECK(std::isfinite(nanValue));
    CHECK(huge >= 0.f);
    CHECK(huge <= 1.f);
    fs::remove_all(dir);
}

TEST_CASE("textures: bitmap gradient equals finite differences, through to_uv", "[textures]") {
    fs::path dir = tempDir("tex-grad");
    const int w = 6, h = 4;
    PCG32 rng(11, 1);
    const std::vector<float> img = randomImage(dir / "g.exr", w, h, rng);
    Properties p("texture", "bitmap");
    p.set("filename", (dir / "g.exr").string());
    // to_uv: u' = 2u − 0.5v + 0.1, v' = 0.3u + 1.5v (a 4x4 matrix, extra row/column ignored).
    glm::mat4 m(1.f);
    m[0][0] = 2.f, m[1][0] = -0.5f, m[3][0] = 0.1f, m[0][1] = 0.3f, m[1][1] = 1.5f;
    p.set("to_uv", Transform(m));
    Ref<ITexture> t = makeTexture("bitmap", p);
    int checked = 0;
    for (int k = 0; k < 300; ++k) {
        double u = rng.nextFloat(), v = rng.nextFloat();
        // Away from the interpolant's kinks (texel centres), where it is differentiable.
        double x = (2 * u - 0.5 * v + 0.1) * w - 0.5, y = (0.3 * u + 1.5 * v) * h - 0.5;
        if (std::abs(x - std::round(x)) < 0.05 || std::abs(y - std::round(y)) < 0.05) continue;
        const float e = 1e-3f;
        Vector2f g = t->evalFloatGradient(at(float(u), float(v)));
        double du = (t->evalFloat(at(float(u) + e, float(v))) - t->evalFloat(at(float(u) - e, float(v)))) / (2 * e);
        double dv = (t->evalFloat(at(float(u), float(v) + e)) - t->evalFloat(at(float(u), float(v) - e))) / (2 * e);
        INFO("(" << u << ", " << v << ")");
        CHECK(g.x == Approx(du).margin(0.02));
        CHECK(g.y == Approx(dv).margin(0.02));
        ++checked;
    }
    CHECK(checked > 100);
    // Nearest lookups are piecewise constant.
    p.set("filter_type", std::string("nearest"));
    CHECK(makeTexture("bitmap", p)->evalFloatGradient(at(0.3f, 0.3f)) == Vector2f(0.f));
    fs::remove_all(dir);
}

TEST_CASE("textures: saturated sRGB texels upsample to spectra within [0, 1]", "[textures]") {
    // grid.png holds pure primaries, secondaries, white and black (make_textures.py).
    Properties p("texture", "bitmap");
    p.set("filename", (DataDir / "grid.png").string());
    p.set("filter_type", std::string("nearest"));
    Ref<ITexture> t = makeTexture("bitmap", p);
    CHECK(t->maxValue() <= 1.f);
    float brightest = 0.f;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i)
            for (float lambda = 360.f; lambda <= 830.f; lambda += 2.f) {
                float s = t->eval(at((i + 0.5f) / 4.f, (j + 0.5f) / 4.f), SampledWavelengths::constant(lambda))[0];
                INFO("texel " << i << "," << j << " at " << lambda << " nm");
                CHECK(s >= 0.f);
                CHECK(s <= 1.f);
                brightest = std::max(brightest, s);
            }
    CHECK(brightest > 0.99f);  // the white texel reaches 1: nothing is scaled down
    // The texture as a diffuse albedo conserves energy everywhere.
    Properties b("bsdf", "diffuse");
    b.set("reflectance", ComponentValue{"texture", t});
    Ref<IBSDF> bsdf = query<IBSDF>(Registry::instance().create("bsdf", "diffuse", b));
    PCG32 rng(3, 1);
    for (int k = 0; k < 500; ++k) {
        SampledWavelengths l = SampledWavelengths::sampleUniform(rng.nextFloat());
        SampledSpectrum a = bsdf->albedo(at(rng.nextFloat(), rng.nextFloat()), l);
        for (int c = 0; c < NSpectrumSamples; ++c) CHECK(a[c] <= 1.f);
    }
}
