// Heterogeneous media (issue 15): the volumes (constvolume, gridvolume, vdbvolume) and the
// heterogeneous medium.
// - gridvolume on .vol files written here (grid_data.hpp): exact at voxel centres, linear
//   between them, clamped beyond the outer centres, nearest against trilinear, RGB voxels
//   upsampled (bounded within [0, 1]), raw RGB read as luminance, use_grid_bbox and
//   to_world placing the unit cube; bad files (truncated, wrong header, NaN, negative,
//   2 channels) are one-line errors naming the scene line and the file.
// - vdbvolume (when OpenVDB is there): a .vdb written here reads back through gridvolume.
// - heterogeneous: σt outside sigma_t's box is 0; majorant pieces bound σt; delta and
//   ratio tracking against the closed-form transmittance of a linear ramp (seeded
//   z-tests, significance 1e-6 each); a volpath render with a constant grid equals the
//   homogeneous medium's render (image means within 4 standard errors, false alarm 6e-5
//   per channel, seeded).
// - The committed grids of tests/data/volume (conformance) are the generator's.
#include "grid_data.hpp"
#include "scene_text.hpp"
#include "temp_files.hpp"
#include "xml_helpers.hpp"

#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/imedium.hpp"
#include "effigi/interfaces/ivolume.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/render/transmittance.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace effigi;
using namespace effigi::test;
using Catch::Contains;

namespace {

const std::filesystem::path kGrids = std::filesystem::path(EFFIGI_SOURCE_DIR) / "tests/data/volume";

Ref<IComponent> fromXml(const std::string& element) {
    auto root = xml::parseString("<scene version=\"3.0.0\">\n" + element + "\n</scene>", "grid.xml");
    return instantiate(*root->children.at(0).node, Registry::instance());
}

Ref<IVolume> gridFile(const std::filesystem::path& file, const std::string& extra = "") {
    return query<IVolume>(fromXml(R"(<volume type="gridvolume"><string name="filename" value=")" + file.string() +
                                  "\"/>" + extra + "</volume>"));
}

const SampledWavelengths Green = SampledWavelengths::constant(550.f);

/// The unit-cube point of ramp voxel coordinates (i, j, k) (centres at integers).
Point3f rampPoint(float i, float j, float k) { return Point3f((i + 0.5f) / 6.f, (j + 0.5f) / 5.f, (k + 0.5f) / 4.f); }

} // namespace

TEST_CASE("gridvolume: values at voxel centres, between them and beyond", "[media][volume]") {
    ScratchDir dir("media_grid");
    const auto file = dir.write("ramp.vol", encodeVol(rampGrid()));
    auto lin = gridFile(file), near = gridFile(file, R"(<string name="filter_type" value="nearest"/>)");
    CHECK(lin->resolution() == glm::ivec3(6, 5, 4));
    CHECK(lin->maxValue() == Approx(rampValue(5, 4, 3)));
    for (auto [i, j, k] : {std::array{0, 0, 0}, std::array{5, 4, 3}, std::array{2, 3, 1}}) {
        const Point3f p = rampPoint(float(i), float(j), float(k));
        CHECK(lin->eval(p, Green)[0] == Approx(rampValue(i, j, k)).epsilon(1e-6));
        CHECK(near->evalFloat(p) == Approx(rampValue(i, j, k)).epsilon(1e-6));
    }
    // Linear between centres; nearest takes the voxel the point lies in.
    CHECK(lin->evalFloat(rampPoint(1.25f, 2.5f, 0.75f)) == Approx(0.1f + 0.12f * 1.25f + 0.125f + 0.015f).epsilon(1e-5));
    CHECK(near->evalFloat(rampPoint(1.4f, 2.6f, 0.4f)) == Approx(rampValue(1, 3, 0)).epsilon(1e-6));
    // Beyond the outer centres the edge voxels hold (clamp); repeat wraps to the far side.
    CHECK(lin->evalFloat(Point3f(-3.f, (0.5f) / 5.f, 0.5f / 4.f)) == Approx(rampValue(0, 0, 0)).epsilon(1e-6));
    auto rep = gridFile(file, R"(<string name="wrap_mode" value="repeat"/>)");
    CHECK(rep->evalFloat(rampPoint(5.5f, 0.f, 0.f)) == Approx(0.5f * (rampValue(5, 0, 0) + rampValue(0, 0, 0))).epsilon(1e-5));
    // maxIn: the voxels of a box's trilinear support.
    const Point3f a = rampPoint(1.f, 1.f, 1.f), b = rampPoint(1.2f, 1.2f, 1.2f);
    CHECK(lin->maxIn(BBox3f(a, b)) == Approx(rampValue(2, 2, 2)));
    CHECK(near->maxIn(BBox3f(a, b)) == Approx(rampValue(1, 1, 1)));
    // to_world and use_grid_bbox place the unit cube.
    auto moved = gridFile(file, R"(<transform name="to_world"><scale value="2"/><translate value="1, 0, 0"/></transform>)");
    CHECK(moved->bbox().min == Point3f(1.f, 0.f, 0.f));
    CHECK(moved->evalFloat(2.f * rampPoint(2.f, 3.f, 1.f) + Vector3f(1.f, 0.f, 0.f)) == Approx(rampValue(2, 3, 1)));
    auto boxed = gridFile(file, R"(<boolean name="use_grid_bbox" value="true"/>)");
    CHECK(boxed->bbox().min == Point3f(-1.f, -2.f, 0.5f));
    CHECK(boxed->bbox().max == Point3f(2.f, 1.f, 1.5f));
    CHECK(boxed->evalFloat(Point3f(-1.f, -2.f, 0.5f) + rampPoint(3.f, 1.f, 2.f) * Vector3f(3.f, 3.f, 1.f)) ==
          Approx(rampValue(3, 1, 2)).epsilon(1e-5));
}

TEST_CASE("gridvolume: RGB voxels are upsampled spectra, raw ones luminance", "[media][volume]") {
    ScratchDir dir("media_grid_rgb");
    const auto file = dir.write("rgb.vol", encodeVol(rgbGrid()));
    auto rgb = gridFile(file), raw = gridFile(file, R"(<boolean name="raw" value="true"/>)");
    const SampledWavelengths l = SampledWavelengths::fromNodes({450.f, 550.f, 610.f, 650.f}, {1.f, 1.f, 1.f, 1.f});
    const Point3f centre((1.5f) / 5.f, 2.5f / 4.f, 1.5f / 3.f);  // voxel (1, 2, 1): rgb (0.7, 0.2, 1.1)
    const SampledSpectrum s = rgb->eval(centre, l);
    CHECK(s[0] > s[1]);  // bluish more than green
    CHECK(s[3] > s[1]);  // and red more than green
    const float luma = 0.2126f * 0.7f + 0.7152f * 0.2f + 0.0722f * 1.1f;
    CHECK(raw->eval(centre, l)[2] == Approx(luma).epsilon(1e-3));
    CHECK(rgb->evalFloat(centre) == Approx(luma).epsilon(1e-3));
    // Voxel (0, 0, 0) is black (its neighbours weigh ~1e-8 after the float mapping).
    CHECK(rgb->eval(Point3f(0.5f / 5.f, 0.5f / 4.f, 0.5f / 3.f), l).maxValue() < 1e-6f);
    CHECK(rgb->maxValue() >= 2.2f);
}

TEST_CASE("gridvolume: bad files and data are one-line errors naming the file", "[media][volume]") {
    ScratchDir dir("media_grid_bad");
    const std::string good = encodeVol(rampGrid());
    VolGrid nan = rampGrid(), neg = rampGrid(), two = rampGrid();
    nan.data[7] = std::nanf("");
    neg.data[3] = -0.5f;
    two.channels = 2, two.size[2] = 2;
    const std::pair<std::string, std::string> cases[] = {
        {dir.write("truncated.vol", good.substr(0, good.size() - 9)).string(), "truncated"},
        {dir.write("header.vol", "VOX" + good.substr(3)).string(), "not a .vol"},
        {dir.write("nan.vol", encodeVol(nan)).string(), "not finite"},
        {dir.write("negative.vol", encodeVol(neg)).string(), "must be finite and >= 0"},
        {dir.write("two.vol", encodeVol(two)).string(), "2 channels"},
        {(dir.dir() / "missing.vol").string(), "missing.vol"},
    };
    for (const auto& [file, why] : cases) {
        const std::string msg = errorOf([&] { gridFile(file); });
        INFO(msg);
        CHECK_THAT(msg, Contains("grid.xml:2") && Contains(file) && Contains(why));
        CHECK(msg.find('\n') == std::string::npos);
    }
#ifndef EFFIGI_TEST_OPENVDB
    CHECK_THAT(errorOf([&] { gridFile(dir.dir() / "x.vdb"); }), Contains("OpenVDB"));
#endif
}

#ifdef EFFIGI_TEST_OPENVDB
TEST_CASE("vdbvolume: a .vdb written by OpenVDB reads back through gridvolume", "[media][volume]") {
    ScratchDir dir("media_grid_vdb");
    const auto file = dir.dir() / "ramp.vdb";
    writeRampVdb(file);
    auto v = gridFile(file);
    REQUIRE(v);
    CHECK(v->typeName() == "volume/gridvolume");
    CHECK(v->resolution() == glm::ivec3(6, 4, 3));  // the active voxels' box
    // Dense voxel (i, j, k) is VDB index (i − 2, j + 1, k).
    auto centre = [](int i, int j, int k) { return Point3f((i + 0.5f) / 6.f, (j + 0.5f) / 4.f, (k + 0.5f) / 3.f); };
    CHECK(v->evalFloat(centre(4, 2, 2)) == Approx(vdbValue(2, 3, 2)).epsilon(1e-6));
    CHECK(v->evalFloat(centre(2, 1, 1)) < 1e-6f);  // the switched-off voxel: background 0
    // use_grid_bbox: index box (−2.5, 0.5, −0.5) – (3.5, 4.5, 2.5) times the voxel size 0.25.
    auto boxed = gridFile(file, R"(<boolean name="use_grid_bbox" value="true"/>)");
    CHECK(boxed->bbox().min.x == Approx(-0.625f));
    CHECK(boxed->bbox().max.y == Approx(1.125f));
    CHECK(boxed->evalFloat(Point3f(0.25f * 3.f, 0.25f * 2.f, 0.25f * 1.f)) == Approx(vdbValue(3, 2, 1)).epsilon(1e-5));
    CHECK_THAT(errorOf([&] { gridFile(file, R"(<string name="grid" value="smoke"/>)"); }),
               Contains("grid.xml:2") && Contains("no grid named 'smoke'") && Contains("density, velocity"));
    CHECK_THAT(errorOf([&] { gridFile(file, R"(<string name="grid" value="velocity"/>)"); }), Contains("floats"));
    CHECK_THAT(errorOf([&] { gridFile(dir.write("bad.vdb", "not a vdb file at all")); }),
               Contains("bad.vdb") && Contains("OpenVDB"));
}
#endif

TEST_CASE("heterogeneous: sigma_t's box bounds the medium and majorants bound sigma_t", "[media][heterogeneous]") {
    // Mitsuba's semantics: a plain number is a constvolume over the unit cube.
    auto unit = query<IMedium>(fromXml(R"(<medium type="heterogeneous"><float name="sigma_t" value="3"/></medium>)"));
    CHECK_FALSE(unit->isHomogeneous());
    CHECK(unit->at(Point3f(0.5f), Green).sigmaT()[0] == Approx(3.f));
    CHECK(unit->at(Point3f(0.5f, 1.5f, 0.5f), Green).sigmaT().isBlack());
    const MajorantSegment before = unit->majorant(Ray{Point3f(-2.f, 0.5f, 0.5f), Vector3f(1.f, 0.f, 0.f)}, 0.f, 10.f, Green);
    CHECK(before.sigmaMaj.isBlack());
    CHECK(before.tMax == Approx(2.f).epsilon(1e-3));

    ScratchDir dir("media_grid_het");
    const auto file = dir.write("rgb.vol", encodeVol(rgbGrid()));
    auto m = query<IMedium>(fromXml(R"(<medium type="heterogeneous"><float name="scale" value="3"/>
        <volume type="gridvolume" name="sigma_t"><string name="filename" value=")" + file.string() + R"("/>
        <transform name="to_world"><scale value="2"/></transform></volume>
        <volume type="gridvolume" name="albedo"><string name="filename" value=")" + dir.write("a.vol", encodeVol(rampGrid())).string() + R"("/></volume></medium>)"));
    PCG32 rng(11, 3);
    int pieces = 0;
    for (int r = 0; r < 200; ++r) {
        const Ray ray{Point3f(4.f * rng.nextFloat() - 1.f, 4.f * rng.nextFloat() - 1.f, -1.f),
                      normalize(Vector3f(rng.nextFloat() - 0.5f, rng.nextFloat() - 0.5f, 1.f)), Infinity};
        const SampledWavelengths l = SampledWavelengths::sampleUniform(rng.nextFloat());
        for (float t = 0.f; t < 10.f; ++pieces) {
            const MajorantSegment seg = m->majorant(ray, t, 10.f, l);
            REQUIRE(seg.tMin == t);
            REQUIRE(seg.tMax > t);
            for (int j = 0; j < 8; ++j) {
                const SampledSpectrum st = m->at(ray(t + (seg.tMax - t) * rng.nextFloat()), l).sigmaT();
                for (int k = 0; k < 4; ++k) REQUIRE(st[k] <= seg.sigmaMaj[k] * (1.f + 1e-6f));
            }
            t = seg.tMax;
        }
    }
    CHECK(pieces > 200 * 3);  // the DDA visits several cells per ray
    // An albedo volume above 1 is refused.
    CHECK_THAT(errorOf([&] {
                   fromXml(R"(<medium type="heterogeneous"><volume type="constvolume" name="albedo">
                   <float name="value" value="1.5"/></volume></medium>)");
               }),
               Contains("grid.xml:2") && Contains("albedo"));
}

TEST_CASE("heterogeneous: transmittance through a linear ramp against the closed form", "[media][heterogeneous]") {
    // The ramp is linear in the voxel index, so between the outer voxel centres σt is
    // linear along any ray and ∫σt ds = L σt(midpoint). Seeded; |z| < 4.89 is a two-sided
    // test at significance 1e-6 per estimator.
    ScratchDir dir("media_grid_ramp");
    const auto file = dir.write("ramp.vol", encodeVol(rampGrid()));
    auto m = query<IMedium>(fromXml(R"(<medium type="heterogeneous"><float name="scale" value="0.5"/>
        <volume type="gridvolume" name="sigma_t"><string name="filename" value=")" + file.string() + R"("/>
        <transform name="to_world"><scale x="6" y="5" z="4"/></transform></volume></medium>)"));
    // In world units voxel (i, j, k) is centred at (i + ½, j + ½, k + ½).
    const Point3f a(0.7f, 0.6f, 0.55f), b(5.2f, 4.1f, 3.3f);
    const Ray ray{a, 0.5f * (b - a), Infinity};  // t ∈ [0, 2] covers a → b
    const double L = double(length(b - a));
    const Point3f mid = 0.5f * (a + b) - Vector3f(0.5f);
    const double tau = 0.5 * L * (0.1 + 0.12 * mid.x + 0.05 * mid.y + 0.02 * mid.z), T = std::exp(-tau);
    PCG32 rng(5, 9);
    auto u = [&] { return rng.nextFloat(); };
    const int n = 200000;
    double d = 0, r = 0, r2 = 0;
    for (int i = 0; i < n; ++i) {
        d += deltaTrackingTransmittance(*m, ray, 2.f, Green, u)[0];
        const double x = ratioTrackingTransmittance(*m, ray, 2.f, Green, u)[0];
        r += x, r2 += x * x;
    }
    d /= n, r /= n;
    INFO("exact " << T << ", delta " << d << ", ratio " << r);
    CHECK(std::abs(d - T) < 4.89 * std::sqrt(T * (1 - T) / n));
    CHECK(std::abs(r - T) < 4.89 * std::sqrt((r2 / n - r * r) / n) + 1e-9);
}

TEST_CASE("heterogeneous: a constant grid renders as the homogeneous medium", "[media][heterogeneous][render]") {
    // A cube of medium (σt 2, albedo 0.8, HG 0.5) in a uniform environment with a small
    // light above, 24², 64 spp: the image mean of the heterogeneous medium (a 2×2×2 grid
    // of 2 over a box enclosing the cube) against the homogeneous one, per channel,
    // within 4 standard errors of the difference of two independent renders (two-sided
    // false alarm 6e-5 per channel; seeded, so deterministic).
    ScratchDir dir("media_grid_render");
    VolGrid g;
    g.size[0] = g.size[1] = g.size[2] = 2, g.channels = 1, g.data.assign(8, 2.f);
    const auto file = dir.write("const.vol", encodeVol(g));
    auto render = [&](const std::string& medium, std::vector<float>& var) {
        const std::string xml = R"(<scene version="3.0.0"><integrator type="volpath"/>
    <sensor type="perspective"><float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0.5, 1, 3" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="64"/></sampler>
        <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="24"/>
            <rfilter type="box"/></film></sensor>
    <emitter type="constant"><rgb name="radiance" value="0.3, 0.4, 0.5"/></emitter>
    <shape type="sphere"><point name="center" value="0, 2, 0"/><float name="radius" value="0.3"/>
        <emitter type="area"><rgb name="radiance" value="10"/></emitter></shape>
    <shape type="cube"><transform name="to_world"><scale value="0.5"/></transform><bsdf type="null"/>)" +
                                medium + "</shape></scene>";
        auto scene = loadScene(*xml::parseString(xml, "render.xml", {}));
        RenderControl control;
        control.progress = false;
        control.seed = 17;
        scene->renderer().render(*scene, control);
        REQUIRE(scene->renderer().varianceEstimate(var));
        return scene->camera().film().develop();
    };
    const std::string common = R"(<float name="albedo" value="0.8"/><phase type="hg"><float name="g" value="0.5"/></phase>)";
    std::vector<float> vh, vg;
    const Image hom = render(R"(<medium type="homogeneous" name="interior"><float name="sigma_t" value="2"/>)" + common +
                                 "</medium>", vh);
    const Image het = render(R"(<medium type="heterogeneous" name="interior"><volume type="gridvolume" name="sigma_t">
        <string name="filename" value=")" + file.string() + R"("/><transform name="to_world">
        <translate value="-0.5, -0.5, -0.5"/><scale value="1.2"/></transform></volume>)" + common + "</medium>", vg);
    const std::size_t n = std::size_t(hom.width) * hom.height;
    for (int c = 0; c < 3; ++c) {
        double a = 0, b = 0, v = 0;
        for (std::size_t i = 0; i < n; ++i) a += hom.pixels[3 * i + c], b += het.pixels[3 * i + c], v += vh[3 * i + c] + vg[3 * i + c];
        const double se = std::sqrt(v) / double(n);
        INFO("channel " << c << ": homogeneous " << a / n << ", heterogeneous " << b / n << " ± " << se);
        CHECK(std::abs(a - b) / double(n) < 4.0 * se);
    }
}

TEST_CASE("volume data: the committed conformance grids are the generator's", "[media][volume]") {
    CHECK(readText(kGrids / "ramp.vol") == encodeVol(rampGrid()));
    CHECK(readText(kGrids / "rgb.vol") == encodeVol(rgbGrid()));
#ifdef EFFIGI_TEST_OPENVDB
    auto v = gridFile(kGrids / "ramp.vdb");  // VDB files hold a random UUID: compare values
    CHECK(v->evalFloat(Point3f(4.5f / 6.f, 2.5f / 4.f, 2.5f / 3.f)) == Approx(vdbValue(2, 3, 2)).epsilon(1e-6));
#endif
}

TEST_CASE("volume data: write the conformance grids", "[.generate]") {
    // Run by hand (test_media_grid "[.generate]") after changing grid_data.hpp.
    std::ofstream(kGrids / "ramp.vol", std::ios::binary) << encodeVol(rampGrid());
    std::ofstream(kGrids / "rgb.vol", std::ios::binary) << encodeVol(rgbGrid());
#ifdef EFFIGI_TEST_OPENVDB
    writeRampVdb(kGrids / "ramp.vdb");
#endif
}
