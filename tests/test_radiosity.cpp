// The radiosity mesh, the renderers `radiosity` and `twopass` end to end, saving and
// loading solutions, and the solution as an illumination map.
#include "app_runner.hpp"
#include "cornell_regions.hpp"
#include "radiosity_helpers.hpp"
#include "xml_helpers.hpp"

#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/iilluminationmap.hpp"
#include "effigi/render/radiosity_mesh.hpp"
#include "effigi/xml/loader.hpp"

#include <OpenImageIO/imageio.h>

#include <fstream>
#include <sstream>

using namespace effigi;
using namespace effigi::test;

namespace {

const std::string kCornell = EFFIGI_SOURCE_DIR "/scenes/cornell-box/radiosity.xml";

/// The same means from an EXR file (the Mitsuba 3 reference of tests/test_cornell.cpp).
Image readExr(const std::string& path) {
    auto in = OIIO::ImageInput::open(path);
    REQUIRE(in);
    const auto& spec = in->spec();
    Image img;
    img.width = spec.width;
    img.height = spec.height;
    img.channelNames = {"R", "G", "B"};
    std::vector<float> px(std::size_t(spec.width) * spec.height * spec.nchannels);
    REQUIRE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, px.data()));
    for (std::size_t i = 0; i < std::size_t(spec.width) * spec.height; ++i)
        for (int c = 0; c < 3; ++c) img.pixels.push_back(px[i * spec.nchannels + c]);
    return img;
}

std::unique_ptr<Scene> loadCornell(std::map<std::string, std::string> defines) {
    xml::ParseOptions opt;
    opt.defines = std::move(defines);
    return loadSceneFile(kCornell, opt);
}

} // namespace

TEST_CASE("mesh: elements, areas, shared vertices, spectra", "[radiosity][mesh]") {
    // A 2 × 1 rectangle (quad patch) and, beside it in its plane, a 1 × 1 square: cut at
    // edge 0.25 into 8 × 4 and 4 × 4 parallelograms whose common edge shares its vertices.
    Ref<IShape> a = diffuseShape("rectangle", Transform::scale({1.f, 0.5f, 1.f}), 0.5f, 2.f);
    Ref<IShape> b = diffuseShape("rectangle", Transform::translate({1.5f, 0.f, 0.f}) * Transform::scale({0.5f, 0.5f, 1.f}), 0.25f);
    Rig rig({a, b}, 0.25f, 8);
    const IMesh& m = *rig.mesh;
    REQUIRE(m.elementCount() == 32u + 16u);
    CHECK(rig.areaOf(0) == Approx(2.0).epsilon(1e-6));
    CHECK(rig.areaOf(1) == Approx(1.0).epsilon(1e-6));
    // (9 × 5) + (5 × 5) vertices, minus the 5 on the common edge x = 1.
    CHECK(m.vertices().size() == 45u + 25u - 5u);
    std::size_t interior4 = 0;
    for (std::uint32_t v = 0; v < m.vertices().size(); ++v) interior4 += m.vertexElements(v).size() == 4;
    CHECK(interior4 == (7u * 3u) + (3u * 3u) + 3u);  // inside each grid, and the 3 inner seam vertices
    // Constant spectra average to themselves in every bin: ρ exactly, E = π L.
    const int nb = m.bins().count();
    for (std::uint32_t i = 0; i < m.elementCount(); ++i)
        for (int k = 0; k < nb; ++k) {
            bool first = m.elements()[i].shape == 0;
            CHECK(m.reflectance()[i * nb + k] == Approx(first ? 0.5 : 0.25).epsilon(1e-6));
            CHECK(m.emission()[i * nb + k] == Approx(first ? 2.0 * Pi : 0.0).margin(1e-6));
        }
    // Every element centre, hit by a ray from above, is located in its own element, and
    // the interpolation weights reproduce the point.
    for (std::uint32_t i = 0; i < m.elementCount(); ++i) {
        const MeshElement& e = m.elements()[i];
        Point3f probe = e.centre + 0.2f * (m.vertices()[e.vertices[1]] - e.centre);  // off-centre
        Ray ray{probe + e.n, -e.n, Infinity};
        Hit hit;
        REQUIRE(rig.accel->intersect(ray, hit));
        SurfaceInteraction si = rig.ptrs[hit.shape]->interaction(ray, hit);
        std::optional<MeshPoint> p = m.locate(si);
        REQUIRE(p);
        CHECK(p->element == i);
        Point3f back(0.f);
        for (int k = 0; k < e.corners(); ++k) back += p->weights[k] * m.vertices()[e.vertices[k]];
        CHECK(length(back - si.p) < 1e-5f);
    }
}

TEST_CASE("mesh: triangle patches of an OBJ file", "[radiosity][mesh]") {
    // A right triangle and a trapezoid (two triangles that are no parallelogram): three
    // triangle patches, each cut into k² triangles.
    auto dir = tempDir("radiosity-mesh");
    std::ofstream(dir / "t.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nv 4 0 0\nv 3.5 1 0\nv 2.5 1 0\n"
                                    "f 1 2 3\nf 4 5 6\nf 4 6 7\n";
    Properties p("shape", "obj");
    p.set("filename", (dir / "t.obj").string());
    Rig rig({query<IShape>(create("shape", "obj", p))}, 0.26f, 4);
    const IMesh& m = *rig.mesh;
    double area = 0.0;
    for (const MeshElement& e : m.elements()) {
        CHECK(e.corners() == 3);
        area += e.area;
    }
    CHECK(area == Approx(0.5 + 1.5).epsilon(1e-5));  // the triangle and the trapezoid
    for (std::uint32_t i = 0; i < m.elementCount(); ++i) {
        const MeshElement& e = m.elements()[i];
        Ray ray{e.centre + e.n, -e.n, Infinity};
        Hit hit;
        REQUIRE(rig.accel->intersect(ray, hit));
        std::optional<MeshPoint> loc = m.locate(rig.ptrs[0]->interaction(ray, hit));
        REQUIRE(loc);
        CHECK(loc->element == i);
    }
    std::filesystem::remove_all(dir);
}

TEST_CASE("radiosity renderer: the Cornell box agrees with the path tracer's reference", "[radiosity][render]") {
    // The reference is Mitsuba 3's 2048-spp image (tests/data/cornell), which effigi's path
    // tracer matches within 0.2 % per wall. Radiosity differs by its discretisation: with
    // 1000 elements we measured at most 2.8 % (back wall); bench/radiosity_vs_path.py shows
    // it within 3 % at the default 2000. Tolerance 4 % per region, 1 % for the whole image.
    auto scene = loadCornell({{"spp", "1"}, {"elements", "1000"}, {"formfactor", "analytic"}});
    RenderStats stats = scene->renderer().render(*scene, quiet());
    CHECK(stats.rejectedSamples == 0);
    Image ours = scene->camera().film().develop(), ref = readExr(EFFIGI_SOURCE_DIR "/tests/data/cornell/mitsuba-reference.exr");
    const std::vector<CornellRegion> regions = cornellRegions();
    CHECK(regions.size() >= 7);
    for (const CornellRegion& r : regions) {
        double a = regionMean(ours, r), b = regionMean(ref, r);
        INFO(r.name << ": radiosity " << a << ", reference " << b << ", relative " << (a - b) / b);
        CHECK(std::abs(a - b) <= (r.name == "image" ? 0.01 : 0.04) * b);
    }
}

TEST_CASE("radiosity renderer: progressive passes reuse the solution", "[radiosity][render]") {
    // Two passes of one sample each (as renderProgressive and `effigi converge` run them)
    // give the image of one 2-spp render: the same sample indices, one solve.
    std::map<std::string, std::string> d{{"spp", "2"}, {"res", "32"}, {"elements", "200"}, {"formfactor", "analytic"}};
    auto scene = loadCornell(d);
    RenderControl c = quiet();
    c.sampleCount = 1;
    RenderStats first = scene->renderer().render(*scene, c);
    c.sampleOffset = 1;
    c.accumulate = true;
    RenderStats second = scene->renderer().render(*scene, c);
    CHECK(first.samples == 32u * 32u);
    CHECK(second.samples == 32u * 32u);
    CHECK(second.seconds < first.seconds);  // rendering only: no second solve
    Image passes = scene->camera().film().develop();
    auto whole = loadCornell(d);
    whole->renderer().render(*whole, quiet());
    Image once = whole->camera().film().develop();
    REQUIRE(passes.pixels.size() == once.pixels.size());
    // Equal up to the order in which overlapping tile borders are added (float round-off).
    for (std::size_t k = 0; k < once.pixels.size(); ++k) CHECK(passes.pixels[k] == Approx(once.pixels[k]).margin(1e-6));
}

TEST_CASE("radiosity renderer: a saved solution renders the same image, bad files are errors", "[radiosity][io]") {
    auto dir = tempDir("radiosity-io");
    std::string file = (dir / "box.rad").string();
    std::map<std::string, std::string> base{{"spp", "1"}, {"res", "48"}, {"elements", "300"}, {"formfactor", "analytic"}};
    auto saved = base, loaded = base;
    saved["save_solution"] = file;
    loaded["load_solution"] = file;
    auto s1 = loadCornell(saved);
    s1->renderer().render(*s1, quiet());
    REQUIRE(std::filesystem::exists(file));
    auto s2 = loadCornell(loaded);
    s2->renderer().render(*s2, quiet());
    Image a = s1->camera().film().develop(), b = s2->camera().film().develop();
    REQUIRE(a.pixels.size() == b.pixels.size());
    // The same radiosities and seeds: equal up to the order in which tile borders add up.
    for (std::size_t k = 0; k < a.pixels.size(); ++k) CHECK(a.pixels[k] == Approx(b.pixels[k]).margin(1e-6));

    SECTION("a solution of another mesh") {
        auto other = loaded;
        other["elements"] = "500";
        auto s = loadCornell(other);
        std::string msg = errorOf([&] { s->renderer().render(*s, quiet()); });
        CHECK(msg.find("radiosity.xml:") != std::string::npos);  // where load_solution is written
        CHECK(msg.find(file) != std::string::npos);
        CHECK(msg.find("another mesh") != std::string::npos);
    }
    SECTION("a truncated or foreign file") {
        std::filesystem::resize_file(file, 100);
        auto s = loadCornell(loaded);
        CHECK(errorOf([&] { s->renderer().render(*s, quiet()); }).find("truncated") != std::string::npos);
        std::ofstream(file) << "P6 not a solution\n";
        auto s3 = loadCornell(loaded);
        CHECK(errorOf([&] { s3->renderer().render(*s3, quiet()); }).find("bad header") != std::string::npos);
        auto missing = base;
        missing["load_solution"] = (dir / "none.rad").string();
        auto s4 = loadCornell(missing);
        CHECK(errorOf([&] { s4->renderer().render(*s4, quiet()); }).find("no such file") != std::string::npos);
    }
    SECTION("a device is refused, not read forever") {
        auto device = base;
        device["load_solution"] = "/dev/zero";
        auto s = loadCornell(device);
        CHECK(errorOf([&] { s->renderer().render(*s, quiet()); }).find("not a regular file") != std::string::npos);
    }
    std::filesystem::remove_all(dir);
}

TEST_CASE("illumination map: the solved mesh answers radiance B/π and irradiance", "[radiosity]") {
    // Two facing squares 1 apart, the lower one emitting L = 1 with ρ = 0.5, the upper
    // ρ = 0.8; solved exactly (Gauss–Seidel to 1e-12).
    Rig rig({unitSquare(Transform(), 0.5f, 1.f),
             unitSquare(Transform::translate({0.f, 0.f, 1.f}) * Transform::scale({1.f, -1.f, -1.f}), 0.8f)},
            2.f, 4);
    Properties ap("formfactor", "analytic");
    ap.set("points", std::int64_t(8));
    auto ff = makeFormFactor("analytic", ap, rig.ctx);
    REQUIRE(makeSolver("gaussseidel", 1000, 1e-12)->solve(*rig.mesh, *ff, quiet()).converged);
    auto map = query<IIlluminationMap>(Ref<IComponent>(rig.mesh));
    REQUIRE(map);
    const int nb = rig.mesh->bins().count();
    // One element per square: vertex values equal the element's, so any point gives B/π.
    SampledWavelengths lambda = SampledWavelengths::sampleUniform(0.3f);
    for (std::uint32_t s = 0; s < 2; ++s) {
        const MeshElement& e = rig.mesh->elements()[s];
        Ray ray{e.centre + 0.5f * e.n + Vector3f(0.1f, 0.2f, 0.f), -e.n, Infinity};
        Hit hit;
        REQUIRE(rig.accel->intersect(ray, hit));
        SurfaceInteraction si = rig.ptrs[hit.shape]->interaction(ray, hit);
        REQUIRE(map->covers(si));
        SampledSpectrum L = map->radiance(si, lambda), H = map->irradiance(si, lambda);
        float B = rig.mesh->radiosity()[s * nb], E = rig.mesh->emission()[s * nb], rho = s == 0 ? 0.5f : 0.8f;
        for (int k = 0; k < NSpectrumSamples; ++k) {
            CHECK(L[k] == Approx(B * InvPi).epsilon(1e-5));
            CHECK(H[k] == Approx((B - E) / rho).epsilon(1e-4));
        }
        // Irradiance from the other square: H_0 = F B_1, H_1 = F B_0.
        float other = rig.mesh->radiosity()[(1 - s) * nb];
        CHECK(H[0] == Approx(ff->formFactor(s, 1 - s) * other).epsilon(1e-4));
        // Seen from behind (one-sided) the map covers nothing.
        si.wo = -si.wo;
        CHECK_FALSE(map->covers(si));
        CHECK(map->radiance(si, lambda).isBlack());
    }
}

TEST_CASE("twopass: without specular surfaces it shows what radiosity shows", "[radiosity][twopass]") {
    // The same scene and solution through the illumination map (spectral samples) and
    // through the radiosity renderer's XYZ (exact bin integrals): the image means must
    // agree up to twopass's wavelength noise (64 spp × 48² pixels: < 0.2 %), tolerance 1 %.
    std::map<std::string, std::string> d{{"spp", "64"}, {"res", "48"}, {"elements", "300"}, {"formfactor", "analytic"}};
    auto rad = loadCornell(d);
    rad->renderer().render(*rad, quiet());
    std::string text;
    {
        std::ifstream in(kCornell);
        std::stringstream ss;
        ss << in.rdbuf();
        text = ss.str();
    }
    auto at = text.find("<integrator type=\"radiosity\">");
    REQUIRE(at != std::string::npos);
    text.replace(at, 29, "<integrator type=\"twopass\"><integer name=\"specular_rays\" value=\"0\"/>");
    text.replace(text.find("<string name=\"shading\" value=\"$shading\"/>"), 41, "");
    auto dir = tempDir("twopass");
    std::filesystem::copy_file(EFFIGI_SOURCE_DIR "/scenes/cornell-box/geometry.xml", dir / "geometry.xml");
    std::ofstream(dir / "twopass.xml") << text;
    xml::ParseOptions opt;
    opt.defines = d;
    auto two = loadSceneFile(dir / "twopass.xml", opt);
    RenderStats st = two->renderer().render(*two, quiet());
    CHECK(st.rejectedSamples == 0);
    double a = regionMean(rad->camera().film().develop(), 0, 0, 1, 1);
    double b = regionMean(two->camera().film().develop(), 0, 0, 1, 1);
    INFO("radiosity " << a << ", twopass " << b);
    CHECK(b == Approx(a).epsilon(0.01));
    std::filesystem::remove_all(dir);
}

TEST_CASE("twopass: the mirror and glass scene renders finite, with light through specular paths",
          "[radiosity][twopass]") {
    xml::ParseOptions opt;
    opt.defines = {{"spp", "4"}, {"width", "64"}, {"height", "48"}, {"elements", "400"}, {"specular_rays", "16"}};
    auto scene = loadSceneFile(EFFIGI_SOURCE_DIR "/scenes/twopass/scene.xml", opt);
    RenderStats st = scene->renderer().render(*scene, quiet());
    CHECK(st.rejectedSamples == 0);
    Image img = scene->camera().film().develop();
    for (float v : img.pixels) CHECK(std::isfinite(v));
    // The mirror (upper middle of the picture) shows the lit room, not black.
    CHECK(regionMean(img, 0.45f, 0.42f, 0.55f, 0.52f) > 0.05);
}
