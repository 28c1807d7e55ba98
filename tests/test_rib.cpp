// RenderMan RIB input (src/rib, include/effigi/rib/loader.hpp): each supported request,
// read and mapped to effigi components, checked on the scene it builds (cameras, shapes,
// areas, bounds) or on the elements the translator makes (light intensities, BSDF
// parameters). Errors: test_rib_errors.cpp.
#include "rib_helpers.hpp"
#include "scene_text.hpp"

#include "effigi/interfaces/ifilm.hpp"
#include "effigi/interfaces/isampler.hpp"

#include <cmath>

using namespace effigi;
using namespace effigi::test;

namespace {


Ray centerRay(const Scene& s, Point2f pFilm) {
    SampledSpectrum w;
    return s.camera().generateRay({pFilm, Point2f(0.5f), 0.f}, SampledWavelengths::sampleVisible(0.5f), w);
}

float angleDeg(const Vector3f& a, const Vector3f& b) {
    return std::acos(std::clamp(dot(normalize(a), normalize(b)), -1.f, 1.f)) * 180.f / Pi;
}

Point3f centerOf(const std::string& body) { return onlyShape(*loadRib(ribWorld(body))).bbox().center(); }

float areaOf(const std::string& body) { return onlyShape(*loadRib(ribWorld(body))).area(); }

} // namespace

TEST_CASE("rib: Frame World Format PixelSamples Display and Clipping set up the camera") {
    const std::string text = "FrameBegin 1\nFormat 48 30 1\nPixelSamples 3 2\nDisplay \"x.tif\" \"file\" \"rgb\"\n"
                             "Clipping 0.5 50\nProjection \"perspective\" \"fov\" 40\nTranslate 0 0 5\nWorldBegin\n"
                             "Sphere 1 -1 1 360\nWorldEnd\nFrameEnd\n";
    auto scene = loadRib(text);
    CHECK(scene->camera().film().size() == Vector2i(48, 30));
    CHECK(scene->camera().sampler().samplesPerPixel() == 6);
    CHECK(loadRib(text, {{"spp", "2"}})->camera().sampler().samplesPerPixel() == 2);
    CHECK(loadRib(ribWorld(""))->camera().sampler().samplesPerPixel() == 64);  // no PixelSamples
    // The camera sits at z = -5 (Translate moves the world away from it) looking along +z;
    // the centre ray starts on the near plane.
    Ray r = centerRay(*scene, Point2f(24.f, 15.f));
    checkVec(r.d, Vector3f(0.f, 0.f, 1.f));
    checkVec(r.o, Vector3f(0.f, 0.f, -4.5f));
}

TEST_CASE("rib: Projection perspective fov spans the shorter image side") {
    auto scene = loadRib("Format 48 30 1\nProjection \"perspective\" \"fov\" [40]\nWorldBegin\nWorldEnd\n");
    CHECK(angleDeg(centerRay(*scene, {24.f, 0.f}).d, Vector3f(0, 0, 1)) == Approx(20.f).margin(1e-3));
    const float half = std::atan(std::tan(20.f * Pi / 180.f) * 48.f / 30.f) * 180.f / Pi;
    CHECK(angleDeg(centerRay(*scene, {48.f, 15.f}).d, Vector3f(0, 0, 1)) == Approx(half).margin(1e-3));
    CHECK(angleDeg(centerRay(*loadRib("Format 30 48 1\nProjection \"perspective\"\nWorldBegin\nWorldEnd\n"),
                             {30.f, 24.f}).d, Vector3f(0, 0, 1)) == Approx(45.f).margin(1e-3));  // default 90°
}

TEST_CASE("rib: image right and up are RenderMan camera +x and +y") {
    auto scene = loadRib(ribWorld(""));
    CHECK(centerRay(*scene, {32.f, 12.f}).d.x > 0.1f);  // right edge
    CHECK(centerRay(*scene, {16.f, 0.f}).d.y > 0.1f);   // top edge
    // A camera turned by Rotate 90 about y looks along world -x.
    auto turned = loadRib("Format 32 24 1\nProjection \"perspective\"\nRotate 90 0 1 0\nWorldBegin\nWorldEnd\n");
    checkVec(centerRay(*turned, {16.f, 12.f}).d, Vector3f(-1.f, 0.f, 0.f));
    // Rendered: a sphere to the camera's right (+x) lights the right half of the image.
    auto lit = loadRib("Format 32 24 1\nPixelSamples 2 2\nProjection \"perspective\" \"fov\" 40\nWorldBegin\n"
                       "LightSource \"distantlight\" 1\nTranslate 1.5 0.8 6\nSphere 0.8 -0.8 0.8 360\nWorldEnd\n");
    Image img = renderSeeded(*lit, 1);
    double left = 0, right = 0, top = 0, bottom = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 3; ++c) {
                (x < img.width / 2 ? left : right) += img.at(x, y, c);
                (y < img.height / 2 ? top : bottom) += img.at(x, y, c);
            }
    CHECK(right > 10.0 * left + 1.0);
    CHECK(top > 2.0 * bottom);
}

TEST_CASE("rib: the default projection is RenderMan's orthographic one") {
    auto scene = loadRib("Format 40 20 1\nWorldBegin\nWorldEnd\n");  // screen window [-2, 2] x [-1, 1]
    Ray right = centerRay(*scene, {40.f, 10.f}), top = centerRay(*scene, {20.f, 0.f});
    checkVec(right.d, Vector3f(0.f, 0.f, 1.f));
    CHECK(right.o.x == Approx(2.f).margin(1e-4));
    CHECK(top.o.y == Approx(1.f).margin(1e-4));
}

TEST_CASE("rib: Translate Rotate Scale ConcatTransform Identity and Transform") {
    const std::string ball = "\nSphere 0.5 -0.5 0.5 360";
    checkVec(centerOf("Translate 1 2 3" + ball), {1.f, 2.f, 3.f});
    checkVec(centerOf("Rotate 90 0 0 1\nTranslate 1 0 0" + ball), {0.f, 1.f, 0.f});  // later transforms apply first
    CHECK(onlyShape(*loadRib(ribWorld("Scale 2 2 2" + ball))).bbox().extents().x == Approx(2.f));
    checkVec(centerOf("ConcatTransform [1 0 0 0 0 1 0 0 0 0 1 0 4 5 6 1]" + ball), {4.f, 5.f, 6.f});
    checkVec(centerOf("Translate 9 9 9\nIdentity" + ball), {0.f, 0.f, 0.f});
    checkVec(centerOf("Translate 9 9 9\nTransform [1 0 0 0 0 1 0 0 0 0 1 0 -1 0 0 1]" + ball), {-1.f, 0.f, 0.f});
}

TEST_CASE("rib: AttributeEnd restores the attributes and TransformEnd the transformation only") {
    rib::SceneSpec s = ribSpec(ribWorld("Color [1 0 0]\nAttributeBegin\nColor [0 1 0]\nTranslate 5 0 0\n"
                                        "Surface \"plastic\"\nSphere 1 -1 1 360\nAttributeEnd\nSphere 1 -1 1 360\n"
                                        "TransformBegin\nTranslate 0 5 0\nColor [0 0 1]\nSphere 1 -1 1 360\n"
                                        "TransformEnd\nSphere 1 -1 1 360"));
    REQUIRE(s.shapes.size() == 4);
    const double tx[] = {5, 0, 0, 0}, ty[] = {0, 0, 5, 0};
    const Vector3d color[] = {{0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {0, 0, 1}};
    const char* surface[] = {"plastic", "matte", "matte", "matte"};
    for (int i = 0; i < 4; ++i) {
        INFO("shape " << i);
        CHECK(s.shapes[i].toWorld[3][0] == tx[i]);
        CHECK(s.shapes[i].toWorld[3][1] == ty[i]);
        CHECK(s.shapes[i].material.color == color[i]);
        CHECK(s.shapes[i].material.surface.type == surface[i]);
    }
}

TEST_CASE("rib: LightSource pointlight distantlight and ambientlight") {
    const std::string body = "Translate 1 0 0\nLightSource \"pointlight\" 1 \"intensity\" 2 \"lightcolor\" [1 .5 .25] "
                             "\"from\" [1 2 3]\nRotate 90 0 1 0\nLightSource \"distantlight\" \"key\" \"intensity\" .5\n"
                             "LightSource \"ambientlight\" 3 \"intensity\" .1 \"lightcolor\" [1 1 0]";
    rib::SceneSpec s = ribSpec(ribWorld(body));
    REQUIRE(s.emitters.size() == 3);
    const xml::Node &point = *s.emitters[0], &distant = *s.emitters[1], &ambient = *s.emitters[2];
    CHECK(point.type == "point");
    checkVec(point.props.getPoint("position"), {2.f, 2.f, 3.f});
    checkVec(rgbOf(point, "intensity"), Pi * Vector3f(2.f, 1.f, .5f));  // π: diffuse() has no 1/π
    CHECK(distant.type == "directional");
    checkVec(distant.props.getVector("direction"), {1.f, 0.f, 0.f});  // (0,0,1) turned about y
    checkVec(rgbOf(distant, "irradiance"), Vector3f(Pi * .5f));
    CHECK(ambient.type == "constant");
    checkVec(rgbOf(ambient, "radiance"), {.1f, .1f, 0.f});
    auto scene = loadRib(ribWorld(body));
    REQUIRE(scene->emitters().size() == 3);
    CHECK(scene->emitters()[0]->typeName() == "emitter/point");
}

TEST_CASE("rib: Surface matte plastic metal with Color and Opacity") {
    auto bsdfOf = [](const std::string& body) {
        rib::SceneSpec s = ribSpec(ribWorld(body + "\nSphere 1 -1 1 360"));
        REQUIRE(s.shapes.size() == 1);
        return rib::bsdfNode(s.shapes[0].material, s.shapes[0].where);
    };
    auto matte = bsdfOf("Color [1 .5 0]\nSurface \"matte\" \"Kd\" .5");
    CHECK(innerBsdf(*matte).type == "diffuse");
    checkVec(rgbOf(innerBsdf(*matte), "reflectance"), {.5f, .25f, 0.f});
    checkVec(rgbOf(innerBsdf(*bsdfOf("Color [.2 .3 .4]")), "reflectance"), {.2f, .3f, .4f});  // default surface
    checkVec(rgbOf(innerBsdf(*bsdfOf("Color [2 2 2]")), "reflectance"), {1.f, 1.f, 1.f});     // clamped
    auto plastic = bsdfOf("Color [1 1 0]\nSurface \"plastic\"");  // Kd .5 Ks .5 roughness .1
    const xml::Node& p = innerBsdf(*plastic);
    CHECK(p.type == "roughplastic");
    CHECK(p.props.getString("distribution") == "beckmann");
    CHECK(p.props.getFloat("alpha") == Approx(std::sqrt(2.0 / 12.0)));  // Blinn exponent 1/0.1
    checkVec(rgbOf(p, "diffuse_reflectance"), {.5f, .5f, 0.f});
    checkVec(rgbOf(p, "specular_reflectance"), {.5f, .5f, .5f});
    CHECK(innerBsdf(*bsdfOf("Surface \"plastic\" \"roughness\" 0")).type == "plastic");
    auto metal = bsdfOf("Color [1 .8 .6]\nSurface \"metal\" \"Ks\" .8 \"roughness\" .05");
    CHECK(innerBsdf(*metal).type == "roughconductor");
    CHECK(innerBsdf(*metal).props.getFloat("alpha") == Approx(std::sqrt(2.0 / 22.0)));
    checkVec(rgbOf(innerBsdf(*metal), "specular_reflectance"), {.8f, .64f, .48f});
    CHECK(innerBsdf(*bsdfOf("Surface \"metal\" \"roughness\" 0")).type == "conductor");
    auto seeThrough = bsdfOf("Opacity [.25 .5 .75]");
    CHECK(seeThrough->type == "mask");
    CHECK(seeThrough->props.getFloat("opacity") == Approx(.5f));
    // Each of them builds.
    auto scene = loadRib(ribWorld("Surface \"plastic\"\nSphere 1 -1 1 360\nSurface \"metal\"\nOpacity [.5 .5 .5]\n"
                                  "Sphere 1 -1 1 360\nSurface \"metal\" \"roughness\" 0\nSphere 1 -1 1 360"));
    CHECK(scene->shapes().size() == 3);
}

TEST_CASE("rib: Sphere Cylinder Cone and Disk") {
    auto scene = loadRib(ribWorld("Sphere 2 -2 2 360"));
    CHECK(onlyShape(*scene).typeName() == "shape/sphere");
    CHECK(onlyShape(*scene).area() == Approx(16.f * Pi).epsilon(1e-4));
    auto squashed = loadRib(ribWorld("Scale 1 1 .5\nSphere 2 -2 2 360"));  // not a similarity: a mesh
    CHECK(onlyShape(*squashed).typeName() == "shape/mesh");
    checkVec(onlyShape(*squashed).bbox().extents(), {4.f, 4.f, 2.f}, 1e-3f);
    CHECK(areaOf("Sphere 2 -2 2 180") == Approx(8.f * Pi).epsilon(0.01));  // half a turn
    CHECK(onlyShape(*loadRib(ribWorld("Sphere 2 -2 2 180"))).bbox().min.y == Approx(0.f).margin(1e-5));
    CHECK(areaOf("Sphere 2 0 2 360") == Approx(8.f * Pi).epsilon(0.01));  // cut at z = 0
    auto cylinder = loadRib(ribWorld("Cylinder 1 -1 2 360"));
    CHECK(onlyShape(*cylinder).typeName() == "shape/cylinder");
    CHECK(onlyShape(*cylinder).area() == Approx(6.f * Pi).epsilon(1e-4));
    CHECK(onlyShape(*cylinder).bbox().min.z == Approx(-1.f));
    CHECK(areaOf("Cylinder 1 -1 2 90") == Approx(1.5f * Pi).epsilon(0.01));
    CHECK(areaOf("Cone 3 1 360") == Approx(Pi * std::sqrt(10.f)).epsilon(0.01));
    CHECK(onlyShape(*loadRib(ribWorld("Cone 3 1 360"))).bbox().max.z == Approx(3.f));
    auto disk = loadRib(ribWorld("Disk 2 3 360"));
    CHECK(onlyShape(*disk).typeName() == "shape/disk");
    CHECK(onlyShape(*disk).area() == Approx(9.f * Pi).epsilon(1e-4));
    CHECK(onlyShape(*disk).bbox().center().z == Approx(2.f));
    CHECK(areaOf("Disk 0 3 -90") == Approx(9.f * Pi / 4.f).epsilon(0.01));  // a negative sweep
}

TEST_CASE("rib: Polygon GeneralPolygon PointsPolygons and PointsGeneralPolygons") {
    auto quad = loadRib(ribWorld("Polygon \"P\" [-1 -1 0 1 -1 0 1 1 0 -1 1 0] \"N\" [0 0 1 0 0 1 0 0 1 0 0 1] "
                                 "\"st\" [0 0 1 0 1 1 0 1]"));
    const TriangleMesh* m = onlyShape(*quad).mesh();
    REQUIRE(m);
    CHECK(m->triangleCount() == 2);
    CHECK(m->uvs.size() == 4);
    CHECK(m->normals.size() == 4);
    CHECK(onlyShape(*quad).area() == Approx(4.f));
    CHECK(onlyShape(*loadRib(ribWorld("Polygon \"P\" [0 0 0 1 0 0 0 1 0]"))).mesh()->normals.empty());  // flat
    // A chevron, concave at (2, 1): a fan from its first corner would cover 8, not 4.
    const std::string chevron = "\"P\" [0 0 0 2 1 0 4 0 0 2 3 0]";
    CHECK(areaOf("GeneralPolygon [4] " + chevron) == Approx(4.f));
    const std::string cube = "PointsPolygons [4 4 4 4 4 4] [0 1 3 2 4 6 7 5 0 4 5 1 2 3 7 6 0 2 6 4 1 5 7 3] \"P\" "
                             "[-1 -1 -1 1 -1 -1 -1 1 -1 1 1 -1 -1 -1 1 1 -1 1 -1 1 1 1 1 1]";
    auto box = loadRib(ribWorld(cube));
    CHECK(onlyShape(*box).mesh()->triangleCount() == 12);
    CHECK(onlyShape(*box).area() == Approx(24.f));
    CHECK(areaOf("PointsGeneralPolygons [1 1] [4 3] [0 1 2 3 4 5 6] \"P\" [0 0 0 2 1 0 4 0 0 2 3 0 "
                 "0 0 1 1 0 1 0 1 1]") == Approx(4.5f));
}

TEST_CASE("rib: Patch bilinear and bicubic in the current Basis") {
    CHECK(areaOf("Patch \"bilinear\" \"P\" [0 0 0 1 0 0 0 1 0 1 1 0]") == Approx(1.f).epsilon(1e-4));
    std::string grid = "\"P\" [";
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) grid += fmt::format("{} {} 0 ", i, j);
    grid += "]";
    CHECK(areaOf("Patch \"bicubic\" " + grid) == Approx(9.f).epsilon(1e-4));  // Bezier: the whole [0, 3]²
    CHECK(areaOf("Basis \"b-spline\" 1 \"b-spline\" 1\nPatch \"bicubic\" " + grid) == Approx(1.f).epsilon(1e-4));
    auto withSt = loadRib(ribWorld("Patch \"bilinear\" \"P\" [0 0 0 1 0 0 0 1 0 1 1 0] \"st\" [0 0 2 0 0 2 2 2]"));
    const TriangleMesh* m = onlyShape(*withSt).mesh();
    REQUIRE(m);
    CHECK(m->uvs.back().x == Approx(2.f));
    auto saddle = loadRib(ribWorld("Patch \"bilinear\" \"P\" [0 0 0 1 0 1 0 1 1 1 1 0]"));
    CHECK(onlyShape(*saddle).area() > 1.f);
}

TEST_CASE("rib: comments continuation lines case old names and ignored requests") {
    // Firebaugh's chapter writes RIB 3.03: lower-case names, `light`, `gpolygon`, values
    // glued to strings.
    const std::string text = "##RenderMan RIB-Structure 1.1\nversion 3.03\nprojection \"perspective\" \"fov\" [30.8]\n"
                             "Option \"searchpath\" \"shader\" \"/nowhere\"  # a comment\nShadingRate 1\nHider "
                             "\"hidden\"\nworldbegin\nlight \"distantlight\" 1 \"intensity\" [1.000]\"from\" [0 0 0]"
                             "\"to\" [-0.346 -0.621 0.703]\nattributebegin\nattribute \"identifier\" \"name\" \"a\\\"b\"\n"
                             "Declare \"grain\" \"uniform float\"\nsides 1\nOrientation \"rh\"\nsurface \"matte\"\n"
                             "gpolygon [4] \"P\" [0 0 5\n 1 0 5\n 1 1 5\n 0 1 5]\nattributeend\nworldend\n";
    auto scene = loadRib(text);
    CHECK(scene->shapes().size() == 1);
    CHECK(scene->emitters().size() == 1);
}

TEST_CASE("rib: the Firebaugh table-and-cube scene renders") {
    const std::string file = std::string(EFFIGI_SOURCE_DIR) + "/scenes/firebaugh/scene.rib";
    xml::ParseOptions opt;
    opt.defines = {{"spp", "1"}};
    auto scene = rib::loadFile(file, opt);
    CHECK(scene->shapes().size() == 7);  // floor, table top, four legs, cube
    CHECK(scene->emitters().size() == 2);
    CHECK(scene->camera().film().size() == Vector2i(640, 480));
    Image img = renderSeeded(*scene, 3);
    REQUIRE(allFinite(img));
    double sum = 0;
    for (float v : img.pixels) sum += v;
    CHECK(sum / double(img.pixels.size()) > 0.05);
    // Through loadSceneFile, as `effigi render` reads it.
    CHECK(loadSceneFile(file)->shapes().size() == 7);
}
