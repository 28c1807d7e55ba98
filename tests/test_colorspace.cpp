// Colour spaces (sRGB, Rec.2020, ACEScg) against their published primaries, whites and
// matrices; tone maps; the film's colorspace / tonemap parameters.
#include "film_helpers.hpp"

#include "app_runner.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/render/tonemap.hpp"
#include "effigi/spectral/colorspace.hpp"

#include <OpenImageIO/imageio.h>
#include <catch2/catch.hpp>

#include <filesystem>

using namespace effigi;
using namespace effigi::test;
namespace fs = std::filesystem;
using colorimetry::Chromaticity;

namespace {

const ColorSpaceId AllSpaces[] = {ColorSpaceId::SRGB, ColorSpaceId::Rec2020, ColorSpaceId::ACEScg};

struct Published {
    ColorSpaceId id;
    Chromaticity r, g, b, white;
};
// ITU-R BT.709-6 / IEC 61966-2-1; ITU-R BT.2020-2 table 3; Academy S-2014-004 (AP1) with
// the ACES white of SMPTE ST 2065-1. The D65 spaces are checked against effigi's D65
// white (xy 0.3127266, 0.3290231; colorspace.hpp); the standards round it to (0.3127, 0.3290).
const Published Spaces[] = {
    {ColorSpaceId::SRGB, {0.64, 0.33}, {0.30, 0.60}, {0.15, 0.06}, {0.312726615, 0.329023130}},
    {ColorSpaceId::Rec2020, {0.708, 0.292}, {0.170, 0.797}, {0.131, 0.046}, {0.312726615, 0.329023130}},
    {ColorSpaceId::ACEScg, {0.713, 0.293}, {0.165, 0.830}, {0.128, 0.044}, {0.32168, 0.33767}},
};

/// Row-major published matrix vs GLM (column-major) M[col][row].
void checkMatrix(const glm::dmat3& M, const double (&ref)[3][3], double tol) {
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
            INFO("row " << r << " col " << c);
            CHECK(M[c][r] == Approx(ref[r][c]).margin(tol));
        }
}

} // namespace

TEST_CASE("each space maps its white to RGB (1,1,1) and its primaries to the unit vectors", "[colorspace]") {
    for (const Published& s : Spaces) {
        const RGBColorSpace& cs = RGBColorSpace::get(s.id);
        INFO(cs.name());
        // White with Y = 1 -> (1, 1, 1), native matrices (no adaptation), double precision.
        glm::dvec3 w = cs.xyzToRGB() * colorimetry::xyToXYZ(s.white);
        for (int c = 0; c < 3; ++c) CHECK(w[c] == Approx(1.0).margin(1e-7));  // white xy given to 9 digits
        // The primaries: XYZ of each unit vector has the published chromaticity, and any
        // XYZ of that chromaticity maps to a multiple of the unit vector.
        const Chromaticity prim[3] = {s.r, s.g, s.b};
        for (int k = 0; k < 3; ++k) {
            glm::dvec3 e(0.0);
            e[k] = 1.0;
            Chromaticity xy = colorimetry::xyzToXY(cs.rgbToXYZ() * e);
            CHECK(xy.x == Approx(prim[k].x).margin(1e-12));
            CHECK(xy.y == Approx(prim[k].y).margin(1e-12));
            glm::dvec3 rgb = cs.xyzToRGB() * (0.37 * colorimetry::xyToXYZ(prim[k]));
            for (int c = 0; c < 3; ++c)
                if (c != k) CHECK(rgb[c] == Approx(0.0).margin(1e-12));
            CHECK(rgb[k] > 0.0);
        }
        // Effigi's D65-referred XYZ: the D65 white is (1, 1, 1) in every space, adapted or not.
        Vector3f d65 = cs.fromXYZ(Vector3f(colorimetry::D65White));
        for (int c = 0; c < 3; ++c) CHECK(d65[c] == Approx(1.f).margin(1e-6));
        // Luminance weights sum to 1 (Y of the white).
        const Vector3f l = cs.luminanceWeights();
        CHECK(l.x + l.y + l.z == Approx(1.f).margin(1e-6));
    }
}

TEST_CASE("matrices agree with their published values", "[colorspace]") {
    // sRGB: exactly the matrices effigi used before (IEC 61966-2-1 primaries, the
    // tabulated D65 white), which the RGB->spectrum fit shares.
    const RGBColorSpace& srgb = RGBColorSpace::get(ColorSpaceId::SRGB);
    PCG32 rng(7, 1);
    for (int i = 0; i < 100; ++i) {
        Vector3f v(rng.nextFloat(), rng.nextFloat(), rng.nextFloat());
        Vector3f a = srgb.fromXYZ(v), b = xyzToLinearSRGB(v);
        Vector3f c = srgb.toXYZ(v), d = linearSRGBToXYZ(v);
        for (int k = 0; k < 3; ++k) {
            CHECK(a[k] == Approx(b[k]).margin(2e-6));
            CHECK(c[k] == Approx(d[k]).margin(2e-6));
        }
    }
    // ACEScg AP1 -> XYZ, Academy S-2014-004, to its printed 10 digits.
    const double ap1[3][3] = {{0.6624541811, 0.1340042065, 0.1561876870},
                              {0.2722287168, 0.6740817658, 0.0536895174},
                              {-0.0055746495, 0.0040607335, 1.0103391003}};
    checkMatrix(RGBColorSpace::get(ColorSpaceId::ACEScg).rgbToXYZ(), ap1, 1e-8);
    // Rec.2020 -> XYZ as commonly published (computed with D65 = (0.3127, 0.3290)); ours
    // uses the unrounded D65 white (Z 1.08883 instead of 1.08906), which moves entries by
    // up to 2.3e-4 (the blue column's Z).
    const double r2020[3][3] = {{0.636958, 0.144617, 0.168881}, {0.262700, 0.677998, 0.059302}, {0.0, 0.028073, 1.060985}};
    checkMatrix(RGBColorSpace::get(ColorSpaceId::Rec2020).rgbToXYZ(), r2020, 3e-4);
    // BT.2020 table 4: luminance Y = 0.2627 R + 0.6780 G + 0.0593 B.
    Vector3f l = RGBColorSpace::get(ColorSpaceId::Rec2020).luminanceWeights();
    CHECK(l.x == Approx(0.2627f).margin(1e-4));
    CHECK(l.y == Approx(0.6780f).margin(1e-4));
    CHECK(l.z == Approx(0.0593f).margin(1e-4));
    // Linear sRGB -> ACEScg with Bradford adaptation, as the ACES OCIO configuration gives
    // it ("Utility - Linear - sRGB", D65 = (0.3127, 0.3290)); 2e-4 covers the D65 rounding.
    const double srgbToAP1[3][3] = {{0.6130974024, 0.3395231462, 0.0473794514},
                                    {0.0701937225, 0.9163538791, 0.0134523985},
                                    {0.0206155929, 0.1095697729, 0.8698146342}};
    const RGBColorSpace& aces = RGBColorSpace::get(ColorSpaceId::ACEScg);
    for (int c = 0; c < 3; ++c) {
        Vector3f e(0.f);
        e[c] = 1.f;
        Vector3f col = aces.fromXYZ(linearSRGBToXYZ(e));
        for (int r = 0; r < 3; ++r) CHECK(col[r] == Approx(srgbToAP1[r][c]).margin(2e-4));
    }
}

TEST_CASE("Bradford adaptation maps white to white and is the identity between equal whites", "[colorspace]") {
    const glm::dvec3 from = colorimetry::D65White, to = colorimetry::xyToXYZ(colorimetry::AcesWhite);
    glm::dvec3 w = colorimetry::bradfordAdaptation(from, to) * from;
    for (int c = 0; c < 3; ++c) CHECK(w[c] == Approx(to[c]).epsilon(1e-12));
    glm::dmat3 I = colorimetry::bradfordAdaptation(from, from);
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) CHECK(I[c][r] == Approx(r == c ? 1.0 : 0.0).margin(1e-12));
}

TEST_CASE("sRGB -> XYZ -> Rec.2020 / ACEScg -> XYZ -> sRGB round trips", "[colorspace]") {
    PCG32 rng(2024, 11);
    double worst = 0.0;
    for (int i = 0; i < 10000; ++i) {
        Vector3f rgb(rng.nextFloat(), rng.nextFloat(), rng.nextFloat());
        rgb *= 4.f;  // HDR values too
        for (ColorSpaceId id : AllSpaces) {
            const RGBColorSpace& cs = RGBColorSpace::get(id);
            Vector3f back = xyzToLinearSRGB(cs.toXYZ(cs.fromXYZ(linearSRGBToXYZ(rgb))));
            for (int c = 0; c < 3; ++c) worst = std::max(worst, double(std::abs(back[c] - rgb[c])));
        }
    }
    // float32 matrices of entries ≤ 3.3, three products: a few ulps of 4 ≈ 1e-6.
    CHECK(worst < 1e-5);
    // Rec.2020 contains the sRGB gamut: sRGB colours have non-negative Rec.2020 RGB, and
    // Rec.2020's green primary is outside sRGB (negative red).
    const RGBColorSpace& r2020 = RGBColorSpace::get(ColorSpaceId::Rec2020);
    for (int c = 0; c < 3; ++c) {
        Vector3f e(0.f);
        e[c] = 1.f;
        Vector3f v = r2020.fromXYZ(linearSRGBToXYZ(e));
        CHECK(std::min({v.x, v.y, v.z}) > -1e-6f);
    }
    CHECK(xyzToLinearSRGB(r2020.toXYZ(Vector3f(0.f, 1.f, 0.f))).x < -0.5f);
}

TEST_CASE("tone maps: 0 to 0, monotone, within [0,1], published curve values", "[tonemap]") {
    const Vector3f luma = RGBColorSpace::get(ColorSpaceId::SRGB).luminanceWeights();
    for (ToneMap op : {ToneMap::None, ToneMap::Reinhard, ToneMap::Filmic}) {
        INFO(int(op));
        CHECK(tonemap::applyGrey(op, 0.f, 0.f) == 0.f);
        Vector3f z = tonemap::apply(op, Vector3f(0.f), 3.f, luma);
        CHECK((z.x == 0.f && z.y == 0.f && z.z == 0.f));
        float prev = 0.f;
        int decreasing = 0, outside = 0, greyMismatch = 0;
        for (int i = 1; i <= 20000; ++i) {  // 1e-4 .. 1e4, log-spaced
            float x = std::pow(10.f, -4.f + 8.f * float(i) / 20000.f);
            float y = tonemap::applyGrey(op, x, 0.f);
            decreasing += y < prev;
            outside += !(y >= 0.f && y <= 1.f);
            // Grey RGB takes the same curve (luminance of grey = grey).
            Vector3f g = tonemap::apply(op, Vector3f(x), 0.f, luma);
            greyMismatch += std::abs(g.x - y) > 1e-5f;
            prev = y;
        }
        CHECK(decreasing == 0);
        CHECK(outside == 0);
        CHECK(greyMismatch == 0);
        CHECK(prev == Approx(1.f).margin(op == ToneMap::Reinhard ? 2e-4 : 0.0));  // saturates (1e4/(1+1e4))
        // Coloured and absurd inputs stay in [0, 1], NaN and negatives become 0.
        PCG32 rng(99, 3);
        int bad = 0;
        for (int i = 0; i < 1000; ++i) {
            Vector3f v(100.f * rng.nextFloat() - 10.f, 1000.f * rng.nextFloat(), rng.nextFloat());
            Vector3f t = tonemap::apply(op, v, 2.f * rng.nextFloat() - 1.f, luma);
            for (int c = 0; c < 3; ++c) bad += !(t[c] >= 0.f && t[c] <= 1.f);
        }
        CHECK(bad == 0);
        Vector3f n = tonemap::apply(op, Vector3f(std::nanf(""), -1.f, Infinity), 0.f, luma);
        for (int c = 0; c < 3; ++c) CHECK((n[c] >= 0.f && n[c] <= 1.f));
    }
    // none: clamp; exposure doubles per stop.
    CHECK(tonemap::applyGrey(ToneMap::None, 0.25f, 1.f) == Approx(0.5f));
    CHECK(tonemap::applyGrey(ToneMap::None, 3.f, 0.f) == 1.f);
    // Reinhard et al. 2002, eq. 3: L/(1+L): 1 -> 1/2, 3 -> 3/4, 0.18 -> 0.152542.
    CHECK(tonemap::reinhard(1.f) == Approx(0.5f));
    CHECK(tonemap::reinhard(3.f) == Approx(0.75f));
    CHECK(tonemap::reinhard(0.18f) == Approx(0.18f / 1.18f));
    // Luminance-based: a colour keeps its channel ratios when nothing clips.
    Vector3f c = tonemap::apply(ToneMap::Reinhard, Vector3f(0.2f, 0.4f, 0.1f), 0.f, luma);
    float L = dot(luma, Vector3f(0.2f, 0.4f, 0.1f));
    CHECK(c.y / c.x == Approx(2.f));
    CHECK(dot(luma, c) == Approx(L / (1.f + L)));
    // Narkowicz 2015: f(x) = x(2.51x+0.03)/(x(2.43x+0.59)+0.14); f(1) = 2.54/3.16,
    // f(0.18) = 0.266897 (mid grey), saturates at 1 (the fit's asymptote 2.51/2.43 > 1).
    CHECK(tonemap::filmic(1.f) == Approx(2.54f / 3.16f));
    CHECK(tonemap::filmic(0.18f) == Approx(0.266897f).margin(1e-6));
    CHECK(tonemap::filmic(0.5f) == Approx(0.5f * 1.285f / (0.5f * 1.805f + 0.14f)));
    CHECK(tonemap::filmic(100.f) == 1.f);
}

TEST_CASE("film colorspace: a D65 white is (1,1,1) in every space, EXR records the chromaticities",
          "[colorspace][film]") {
    auto dir = tempDir("colorspace");
    const char* names[] = {"srgb", "rec2020", "acescg"};
    for (int k = 0; k < 3; ++k) {
        INFO(names[k]);
        Ref<IFilm> film = makeFilm({{"width", PropertyValue(std::int64_t(2))},
                                    {"height", PropertyValue(std::int64_t(2))},
                                    {"colorspace", PropertyValue(std::string(names[k]))},
                                    {"component_format", PropertyValue(std::string("float32"))}}, "box");
        film->prepare({"X", "Y", "Z"});
        ImageBlock b = film->createBlock({0, 0}, {2, 2});
        // A D65 white and a saturated sRGB red.
        const Vector3f white(colorimetry::D65White), red = linearSRGBToXYZ(Vector3f(0.8f, 0.05f, 0.02f));
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x) b.put(Point2f(float(x) + 0.5f, float(y) + 0.5f), x == 0 ? &white.x : &red.x);
        film->put(b);
        Image img = film->develop();
        const RGBColorSpace& cs = RGBColorSpace::get(AllSpaces[k]);
        for (int c = 0; c < 3; ++c) {
            CHECK(img.at(0, 1, c) == Approx(1.f).margin(1e-5));
            CHECK(img.at(1, 0, c) == Approx(cs.fromXYZ(red)[c]).margin(1e-6));
        }
        auto files = film->write(dir / fmt::format("{}.exr", names[k]), {});
        REQUIRE(files.size() == 2);
        auto in = OIIO::ImageInput::open(files[0].string());
        REQUIRE(in);
        const OIIO::ParamValue* chroma = in->spec().find_attribute("chromaticities");
        REQUIRE(chroma);
        REQUIRE(chroma->type() == OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
        const float* v = static_cast<const float*>(chroma->data());
        const auto& p = cs.primaries();
        for (int i = 0; i < 3; ++i) {
            CHECK(v[2 * i] == Approx(p[std::size_t(i)].x).margin(1e-6));
            CHECK(v[2 * i + 1] == Approx(p[std::size_t(i)].y).margin(1e-6));
        }
        CHECK(v[6] == Approx(cs.whiteXY().x).margin(1e-6));
        CHECK(v[7] == Approx(cs.whiteXY().y).margin(1e-6));
        CHECK(in->spec().get_string_attribute("effigi/colorspace") == names[k]);
        // The PNG is sRGB whatever the space: the red pixel has the same bytes in all three.
        std::vector<float> png(2 * 2 * 3);
        auto pin = OIIO::ImageInput::open(files[1].string());
        REQUIRE(pin);
        REQUIRE(pin->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, png.data()));
        CHECK(png[3 * 1 + 0] == Approx(std::round(srgbEncode(0.8f) * 255.f) / 255.f).margin(1e-6));
        CHECK(png[3 * 1 + 1] == Approx(std::round(srgbEncode(0.05f) * 255.f) / 255.f).margin(1e-6));
    }
    fs::remove_all(dir);
}

TEST_CASE("film tonemap and exposure shape the PNG only", "[tonemap][film]") {
    auto dir = tempDir("tonemap");
    for (const char* op : {"none", "reinhard", "filmic"}) {
        INFO(op);
        Ref<IFilm> film = makeFilm({{"width", PropertyValue(std::int64_t(1))},
                                    {"height", PropertyValue(std::int64_t(1))},
                                    {"tonemap", PropertyValue(std::string(op))},
                                    {"exposure", PropertyValue(1.0)},
                                    {"component_format", PropertyValue(std::string("float32"))}}, "box");
        film->prepare({"X", "Y", "Z"});
        ImageBlock b = film->createBlock({0, 0}, {1, 1});
        const Vector3f grey = 1.5f * Vector3f(colorimetry::D65White);  // linear sRGB (1.5, 1.5, 1.5)
        b.put(Point2f(0.5f), &grey.x);
        film->put(b);
        auto files = film->write(dir / fmt::format("{}.exr", op), {});
        std::vector<float> exr(3), png(3);
        auto e = OIIO::ImageInput::open(files[0].string());
        REQUIRE(e);
        REQUIRE(e->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, exr.data()));
        CHECK(exr[0] == Approx(1.5f).margin(1e-5));  // the EXR is never scaled nor mapped
        auto p = OIIO::ImageInput::open(files[1].string());
        REQUIRE(p);
        REQUIRE(p->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, png.data()));
        const float mapped = tonemap::applyGrey(*tonemap::parse(op), 1.5f, 1.f);  // 3 after exposure
        CHECK(png[1] == Approx(std::round(srgbEncode(mapped) * 255.f) / 255.f).margin(1e-6));
    }
    fs::remove_all(dir);
}

TEST_CASE("film rejects unknown colour spaces and tone maps", "[colorspace][film]") {
    Properties p("film", "hdrfilm");
    p.set("colorspace", PropertyValue(std::string("adobergb")));
    CHECK_THROWS_AS(Registry::instance().create("film", "hdrfilm", p), Error);
    Properties q("film", "hdrfilm");
    q.set("tonemap", PropertyValue(std::string("aces")));
    CHECK_THROWS_AS(Registry::instance().create("film", "hdrfilm", q), Error);
}
