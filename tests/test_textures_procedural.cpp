// Textures (issue 10), part two: the checkerboard and mesh_attribute textures against
// independent formulas, PLY attributes, textured roughness, and an end-to-end render
// compared with Mitsuba 3. Bitmap loading and lookups are in test_textures.cpp.
#include "app_runner.hpp"
#include "texture_helpers.hpp"

#include "effigi/interfaces/ibsdf.hpp"
#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/ishape.hpp"
#include "effigi/math/rng.hpp"
#include "effigi/render/ply_reader.hpp"
#include "effigi/xml/loader.hpp"

#include <catch2/catch.hpp>

#include <OpenImageIO/imageio.h>

#include <fstream>

using namespace effigi;
using namespace effigi::test;
namespace fs = std::filesystem;

TEST_CASE("textures: checkerboard follows Mitsuba's pattern and defaults", "[textures]") {
    Properties p("texture", "checkerboard");
    glm::mat4 m(1.f);
    m[0][0] = 3.f, m[3][0] = 0.25f, m[1][1] = 2.f;  // u' = 3u + 0.25, v' = 2v
    p.set("to_uv", Transform(m));
    Ref<ITexture> t = makeTexture("checkerboard", p);
    PCG32 rng(5, 1);
    for (int k = 0; k < 500; ++k) {
        float u = 4.f * rng.nextFloat() - 2.f, v = 4.f * rng.nextFloat() - 2.f;
        float uu = 3.f * u + 0.25f, vv = 2.f * v;
        // Mitsuba: color0 where frac(u') > ½ and frac(v') > ½ agree; defaults 0.4 and 0.2.
        bool a = uu - std::floor(uu) > 0.5f, b = vv - std::floor(vv) > 0.5f;
        float expect = a == b ? 0.4f : 0.2f;
        INFO("(" << u << ", " << v << ")");
        CHECK(t->evalFloat(at(u, v)) == Approx(expect));
        CHECK(t->eval(at(u, v), SampledWavelengths::constant(600.f))[0] == Approx(expect));
    }
    CHECK(t->mean() == Approx(0.3f));
    CHECK(t->maxValue() == Approx(0.4f));
    CHECK_FALSE(t->isConstant());
}

TEST_CASE("textures: PLY colours and attributes become mesh attributes, as Mitsuba names them", "[textures]") {
    const std::string ply = "ply\nformat ascii 1.0\nelement vertex 4\n"
                            "property float x\nproperty float y\nproperty float z\n"
                            "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                            "property float weight_0\nproperty float quality\n"
                            "element face 1\nproperty list uchar int vertex_indices\n"
                            "property float color_0\nproperty float color_1\nproperty float color_2\n"
                            "end_header\n"
                            "0 0 0 255 0 0 0.5 9\n1 0 0 0 255 0 1.5 9\n1 1 0 0 0 255 2.5 9\n0 1 0 51 102 153 3.5 9\n"
                            "4 0 1 2 3 0.25 0.5 0.75\n";
    TriangleMesh mesh = readPlyFromMemory(ply, "attr.ply");
    REQUIRE(mesh.triangleCount() == 2);
    const MeshAttribute* col = mesh.attribute("vertex_color");
    const MeshAttribute* weight = mesh.attribute("vertex_weight");
    const MeshAttribute* face = mesh.attribute("face_color");
    REQUIRE(col);
    REQUIRE(weight);
    REQUIRE(face);
    CHECK(mesh.attribute("vertex_quality") == nullptr);  // no _<suffix>: ignored, as Mitsuba
    CHECK(col->channels == 3);
    CHECK(weight->channels == 1);
    CHECK(face->perFace);
    CHECK(col->data[9] == Approx(0.2f));  // uchar 51 / 255
    CHECK(col->data[11] == Approx(0.6f));
    REQUIRE(face->data.size() == 6);  // the quad's two fan triangles share its value
    CHECK(face->data[3] == Approx(0.25f));
    CHECK_NOTHROW(mesh.validate("attr.ply"));

    // mesh_attribute interpolates with the hit's barycentrics.
    fs::path dir = tempDir("tex-attr");
    std::ofstream(dir / "attr.ply") << ply;
    Properties sp("shape", "ply");
    sp.set("filename", (dir / "attr.ply").string());
    Ref<IShape> shape = query<IShape>(Registry::instance().create("shape", "ply", sp));
    REQUIRE(shape);
    REQUIRE(shape->mesh());
    const TriangleMesh& m = *shape->mesh();
    auto attrTexture = [](const std::string& name) {
        Properties p("texture", "mesh_attribute");
        p.set("name", name);
        p.set("scale", 2.0);
        return makeTexture("mesh_attribute", p);
    };
    Ref<ITexture> wt = attrTexture("vertex_weight"), ct = attrTexture("vertex_color"), ft = attrTexture("face_color");
    PCG32 rng(9, 1);
    for (int k = 0; k < 100; ++k) {
        SurfaceInteraction si;
        si.shape = shape.get();
        si.prim = rng.nextUInt() % 2;
        float b1 = rng.nextFloat(), b2 = rng.nextFloat() * (1.f - b1);
        si.primUV = Point2f(b1, b2);
        float b[3] = {1.f - b1 - b2, b1, b2};
        float expectW = 0.f;
        Vector3f expectC(0.f);
        const MeshAttribute& ma = *m.attribute("vertex_weight");
        const MeshAttribute& mc = *m.attribute("vertex_color");
        for (int c = 0; c < 3; ++c) {
            std::uint32_t vi = m.indices[3 * si.prim + std::uint32_t(c)];
            expectW += b[c] * ma.data[vi];
            expectC += b[c] * Vector3f(mc.data[3 * vi], mc.data[3 * vi + 1], mc.data[3 * vi + 2]);
        }
        CHECK(wt->evalFloat(si) == Approx(2.f * expectW).margin(1e-5));
        Vector3f got = ct->evalVector(si);
        for (int c = 0; c < 3; ++c) CHECK(got[c] == Approx(2.f * expectC[c]).margin(1e-5));
        CHECK(ft->evalVector(si).z == Approx(1.5f));
        // A colour attribute is a spectrum: within [0, scale] at every wavelength.
        SampledSpectrum s = ct->eval(si, SampledWavelengths::sampleUniform(rng.nextFloat()));
        for (int c = 0; c < NSpectrumSamples; ++c) CHECK((s[c] >= 0.f && s[c] <= 2.f));
    }
    // No mesh, or no such attribute: black, not a crash.
    CHECK(attrTexture("vertex_nothing")->evalFloat(SurfaceInteraction{}) == 0.f);
    Properties bad("texture", "mesh_attribute");
    bad.set("name", std::string("color"));
    CHECK_THROWS_WITH(Registry::instance().create("texture", "mesh_attribute", bad), Catch::Contains("vertex_"));
    fs::remove_all(dir);
}

TEST_CASE("textures: roughness textures drive roughconductor and roughdielectric", "[textures]") {
    // alpha = checkerboard of 0.05 and 0.6: in each square the BSDF equals the one with
    // that constant roughness.
    Properties cp("texture", "checkerboard");
    cp.set("color0", 0.05);
    cp.set("color1", 0.6);
    Ref<ITexture> checks = makeTexture("checkerboard", cp);
    for (const std::string type : {"roughconductor", "roughdielectric"}) {
        Properties tp("bsdf", type);
        tp.set("alpha", ComponentValue{"texture", checks});
        tp.set("distribution", std::string("ggx"));
        Ref<IBSDF> textured = query<IBSDF>(Registry::instance().create("bsdf", type, tp));
        Ref<IBSDF> fixed[2];
        for (int i = 0; i < 2; ++i) {
            Properties q("bsdf", type);
            q.set("alpha", i == 0 ? 0.05 : 0.6);
            q.set("distribution", std::string("ggx"));
            fixed[i] = query<IBSDF>(Registry::instance().create("bsdf", type, q));
        }
        SampledWavelengths l = SampledWavelengths::constant(550.f);
        Vector3f wo = normalize(Vector3f(0.3f, 0.1f, 0.9f)), wi = normalize(Vector3f(-0.2f, 0.05f, 0.95f));
        for (float u : {0.25f, 0.75f}) {
            SurfaceInteraction si = at(u, 0.25f);  // u < ½: color0 square
            int which = u < 0.5f ? 0 : 1;
            INFO(type << " square " << which);
            CHECK(textured->f(si, wo, wi, l, TransportMode::Radiance)[0] ==
                  Approx(fixed[which]->f(si, wo, wi, l, TransportMode::Radiance)[0]));
            CHECK(textured->pdf(si, wo, wi, l, TransportMode::Radiance) ==
                  Approx(fixed[which]->pdf(si, wo, wi, l, TransportMode::Radiance)));
        }
        // The two squares differ (the texture is really read).
        CHECK(fixed[0]->f(at(0.25f, 0.25f), wo, wi, l, TransportMode::Radiance)[0] !=
              Approx(fixed[1]->f(at(0.25f, 0.25f), wo, wi, l, TransportMode::Radiance)[0]));
    }
}

TEST_CASE("textures: bitmap, checkerboard and mesh attributes render as in Mitsuba 3", "[textures][render]") {
    // Reference: python3 bench/mitsuba_reference.py tests/data/textures/scene.xml
    //   tests/data/textures/mitsuba-reference.exr --spp 1024   (Mitsuba 3.9.1 scalar_spectral)
    xml::ParseOptions opt;
    opt.defines = {{"spp", "256"}};
    auto scene = loadSceneFile(DataDir / "scene.xml", opt);
    RenderControl control;
    control.progress = false;
    scene->renderer().render(*scene, control);
    Image img = scene->camera().film().develop();
    auto in = OIIO::ImageInput::open((DataDir / "mitsuba-reference.exr").string());
    REQUIRE(in);
    const OIIO::ImageSpec& spec = in->spec();
    REQUIRE(spec.width == img.width);
    REQUIRE(spec.height == img.height);
    std::vector<float> ref(std::size_t(spec.width) * spec.height * spec.nchannels);
    REQUIRE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, ref.data()));

    // 8x8-pixel blocks, per channel, compared through the pixel differences effigi −
    // Mitsuba: the texture's structure cancels, so their spread over the block is the
    // noise (the box filter keeps pixels independent), and the block's mean difference has
    // standard error sd/√64. Tolerance: 2 % systematic (the renderers' RGB upsampling
    // tables differ slightly) plus 4 standard errors (two-sided false alarm 6e-5 per block;
    // the render is seeded, so the outcome is deterministic).
    const int B = 8;
    int blocks = 0;
    for (int by = 0; by + B <= img.height; by += B)
        for (int bx = 0; bx + B <= img.width; bx += B)
            for (int c = 0; c < 3; ++c) {
                double sum = 0, sum2 = 0, r = 0;
                for (int y = by; y < by + B; ++y)
                    for (int x = bx; x < bx + B; ++x) {
                        double m = ref[(std::size_t(y) * spec.width + x) * spec.nchannels + c];
                        double d = img.at(x, y, c) - m;
                        sum += d;
                        sum2 += d * d;
                        r += m;
                    }
                const double n = B * B, mean = sum / n;
                r /= n;
                double se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / (n - 1));
                double tol = 0.02 * std::max(r, 0.05) + 4.0 * se;
                INFO("block (" << bx << ", " << by << ") channel " << c << ": effigi − mitsuba " << mean << " ± "
                               << se << ", mitsuba " << r << ", tolerance " << tol);
                CHECK(std::abs(mean) < tol);
                CHECK(tol < 0.05);  // sharp enough to see a swapped texel or colour
                ++blocks;
            }
    CHECK(blocks == 6 * 6 * 3);
}
