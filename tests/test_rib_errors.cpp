// RenderMan RIB input: every error is one line naming the RIB file and line (and the
// request, and the parameter where there is one), raised as effigi::Error; the CLI turns
// it into exit code 1. Requests that work: test_rib.cpp.
#include "app_runner.hpp"
#include "printable_line.hpp"
#include "rib_helpers.hpp"

#include <fstream>

using namespace effigi;
using namespace effigi::test;

namespace {

struct Case {
    const char* what;
    std::string text;
    std::string message;  // expected within the error, with "t.rib:<line>: "
};

void checkCases(const std::vector<Case>& cases) {
    for (const Case& c : cases) {
        INFO(c.what << "\n" << c.text);
        std::string msg = ribError(c.text);
        CHECK_THAT(msg, Catch::Matchers::Contains(c.message));
        CHECK(printableLine(msg));
    }
}

} // namespace

TEST_CASE("rib errors: unsupported requests shaders and parameters") {
    checkCases({
        {"unknown request", ribWorld("Torus 1 .2 0 360 360"), "t.rib:4: RIB request 'Torus' is not supported"},
        {"nan is a name", ribWorld("nan 1 2 3"), "t.rib:4: RIB request 'nan' is not supported"},
        {"unknown surface", ribWorld("Surface \"wood\" \"Kd\" 1"),
         "t.rib:4: RIB request 'Surface \"wood\"': surface shader 'wood' is not supported"},
        {"unknown light", ribWorld("LightSource \"spotlight\" 1"),
         "t.rib:4: RIB request 'LightSource \"spotlight\"': light shader 'spotlight' is not supported"},
        {"unknown parameter", ribWorld("Surface \"plastic\"\n  \"Kd\" .5\n  \"grain\" 10"),
         "t.rib:6: RIB request 'Surface \"plastic\"': parameter 'grain' is not supported"},
        {"parameter of the wrong size", ribWorld("Surface \"matte\" \"Kd\" [1 2]"),
         "t.rib:4: RIB request 'Surface \"matte\"': parameter 'Kd' expects 1 number, got an array of numbers of 2"},
        {"negative parameter", ribWorld("Surface \"metal\" \"roughness\" -1"), "parameter 'roughness' must be >= 0"},
        {"parameter given twice", ribWorld("Surface \"matte\" \"Kd\" 1 \"Kd\" 1"), "parameter 'Kd' is given twice"},
        {"parameter without value", ribWorld("Surface \"matte\" \"Kd\""), "t.rib:4: RIB request 'Surface \"matte\"': parameter 'Kd' has no value"},
        {"number as parameter name", ribWorld("Surface \"matte\" 1 2"), "expected a parameter name (a string), got a number"},
        {"parameter on a quadric", ribWorld("Sphere 1 -1 1 360 \"Cs\" [1 0 0]"), "t.rib:4: RIB request 'Sphere': parameter 'Cs' is not supported"},
        {"unknown projection", "Projection \"fisheye\"\nWorldBegin\nWorldEnd\n", "t.rib:1: RIB request 'Projection \"fisheye\"': projection 'fisheye' is not supported"},
        {"unknown patch type", ribWorld("Patch \"bicubicx\" \"P\" [0 0 0]"), "patch type 'bicubicx' is not supported"},
        {"unknown basis", ribWorld("Basis \"nurbs\" 1 \"bezier\" 3"), "t.rib:4: RIB request 'Basis': basis 'nurbs' is not supported"},
        {"pixel aspect", "Format 64 48 2\nWorldBegin\nWorldEnd\n", "t.rib:1: RIB request 'Format': a pixel aspect ratio other than 1"},
    });
    CHECK_THAT(ribError(ribWorld(""), {{"res", "4"}}), Catch::Matchers::Contains("-D res: a RIB scene takes only -D spp=N"));
}

TEST_CASE("rib errors: arity and value types") {
    std::string overflow;  // 1e38^9 is beyond a double
    for (int i = 0; i < 9; ++i) overflow += "Scale 1e38 1e38 1e38\n";
    checkCases({
        {"too few", ribWorld("Translate 1 2"), "t.rib:4: RIB request 'Translate': expects 3 numbers, got 2"},
        {"too many", ribWorld("Rotate 1 2 3 4 5"), "t.rib:4: RIB request 'Rotate': expects 4 numbers, got 5"},
        {"string for a number", ribWorld("Scale 1 \"2\" 3"), "t.rib:4: RIB request 'Scale': expects 3 numbers, got 1"},
        {"number for a string", ribWorld("Surface 3"), "t.rib:4: RIB request 'Surface': expects shader name (a string), got a number"},
        {"missing light handle", ribWorld("LightSource \"pointlight\""), "RIB request 'LightSource \"pointlight\"': missing light handle"},
        {"16 numbers", ribWorld("ConcatTransform [1 0 0 0 1]"), "t.rib:4: RIB request 'ConcatTransform': expects 16 numbers, got 5"},
        {"projective matrix", ribWorld("ConcatTransform [1 0 0 1 0 1 0 0 0 0 1 0 0 0 0 1]"), "projective matrices are not supported"},
        {"extra value", ribWorld("AttributeBegin 3\nAttributeEnd"), "t.rib:4: RIB request 'AttributeBegin': unexpected extra value (a number)"},
        {"zero rotation axis", ribWorld("Rotate 30 0 0 0"), "t.rib:4: RIB request 'Rotate': the rotation axis must be a non-zero"},
        {"overflowing transform", ribWorld(overflow), "the current transformation overflows"},
        {"negative colour", ribWorld("Color [1 -1 0]"), "t.rib:4: RIB request 'Color': components must lie in [0, 1e38]"},
        {"opacity above 1", ribWorld("Opacity 2 2 2"), "t.rib:4: RIB request 'Opacity': components must lie in [0, 1]"},
        {"PixelSamples 0", "PixelSamples 0 4\nWorldBegin\nWorldEnd\n", "t.rib:1: RIB request 'PixelSamples': expects two numbers >= 1"},
        {"bad clipping", "Clipping 5 1\nWorldBegin\nWorldEnd\n", "t.rib:1: RIB request 'Clipping': expects 0 < near < far"},
        {"bad resolution", "Format 0 10 1\nWorldBegin\nWorldEnd\n", "t.rib:1: RIB request 'Format': the resolution must be whole numbers"},
        {"bad fov", "Projection \"perspective\" \"fov\" 190\nWorldBegin\nWorldEnd\n", "t.rib:1: camera 'perspective': parameter 'fov'"},
        {"singular camera", "Projection \"perspective\"\nScale 0 0 0\nWorldBegin\nWorldEnd\n", "t.rib:1: the camera transformation (before WorldBegin) is singular"},
        {"sheared camera", "Projection \"perspective\"\nScale 1 2 1\nWorldBegin\nWorldEnd\n", "must be rigid or scale uniformly"},
    });
}

TEST_CASE("rib errors: geometry") {
    checkCases({
        {"radius 0", ribWorld("Sphere 0 -1 1 360"), "t.rib:4: RIB request 'Sphere': the radius must be positive, got 0"},
        {"thetamax 0", ribWorld("Cylinder 1 0 1 0"), "t.rib:4: RIB request 'Cylinder': thetamax must not be 0"},
        {"empty sphere", ribWorld("Sphere 1 2 3 360"), "zmin and zmax leave nothing of the sphere"},
        {"flat cylinder", ribWorld("Cylinder 1 1 1 360"), "zmin and zmax must differ"},
        {"no P", ribWorld("Polygon \"N\" [0 0 1 0 0 1 0 0 1]"), "t.rib:4: RIB request 'Polygon': parameter 'P' is required"},
        {"P not triples", ribWorld("Polygon \"P\" [0 0 0 1]"), "parameter 'P' expects a multiple of 3 numbers, got 4"},
        {"two points", ribWorld("Polygon \"P\" [0 0 0 1 0 0]"), "a polygon has 2 vertices (at least 3 are needed)"},
        {"N count", ribWorld("Polygon \"P\" [0 0 0 1 0 0 0 1 0] \"N\" [0 0 1]"), "'N' has 1 normals for 3 points"},
        {"index out of range", ribWorld("PointsPolygons [3] [0 1 7] \"P\" [0 0 0 1 0 0 0 1 0]"),
         "t.rib:4: RIB request 'PointsPolygons': vertex index 7 is out of range ('P' has 3 points)"},
        {"counts too many", ribWorld("PointsPolygons [3 3] [0 1 2] \"P\" [0 0 0 1 0 0 0 1 0]"), "the vertex counts add up to more than"},
        {"counts too few", ribWorld("PointsPolygons [3] [0 1 2 0] \"P\" [0 0 0 1 0 0 0 1 0]"), "the vertex counts add up to 3, but 4 indices"},
        {"non-integer index", ribWorld("PointsPolygons [3] [0 1 1.5] \"P\" [0 0 0 1 0 0 0 1 0]"), "vertices must be integers"},
        {"holes", ribWorld("PointsGeneralPolygons [2] [3 3] [0 1 2 0 1 2] \"P\" [0 0 0 1 0 0 0 1 0]"),
         "t.rib:4: RIB request 'PointsGeneralPolygons': each polygon must have one loop (holes are not supported)"},
        {"holes in GeneralPolygon", ribWorld("GeneralPolygon [3 3] \"P\" [0 0 0 1 0 0 0 1 0 0 0 0 1 0 0 0 1 0]"), "got nloops = 2"},
        {"GeneralPolygon count", ribWorld("GeneralPolygon [4] \"P\" [0 0 0 1 0 0 0 1 0]"), "'P' has 3 points where 4 are needed"},
        {"huge vertex count", ribWorld("GeneralPolygon [2147483647] \"P\" [0 0 0 1 0 0 0 1 0]"),
         "t.rib:4: RIB request 'GeneralPolygon': 'P' has 3 points where 2147483647 are needed"},
        {"index beyond 2^31", ribWorld("PointsPolygons [3] [0 1 2147483648] \"P\" [0 0 0 1 0 0 0 1 0]"),
         "vertices must be integers in [0, 2^31)"},
        {"bicubic count", ribWorld("Patch \"bicubic\" \"P\" [0 0 0 1 0 0 0 1 0 1 1 0]"), "t.rib:4: RIB request 'Patch \"bicubic\"': 'P' has 4 points where 16 are needed"},
        {"beyond the coordinate range", ribWorld("Translate 1e20 0 0\nSphere 1 -1 1 360"), "t.rib:5: shape 'sphere'"},
        {"mesh beyond the range", ribWorld("Scale 1e20 1 1\nPolygon \"P\" [0 0 0 1 0 0 0 1 0]"), "t.rib:5: RIB request 'Polygon':"},
    });
}

TEST_CASE("rib errors: block structure") {
    checkCases({
        {"WorldEnd missing", "Projection \"perspective\"\nWorldBegin\nSphere 1 -1 1 360\n",
         "t.rib:3: the WorldBegin at line 2 has no WorldEnd (end of file)"},
        {"AttributeEnd missing", ribWorld("AttributeBegin\nSphere 1 -1 1 360"),
         "t.rib:6: RIB request 'WorldEnd': the AttributeBegin at line 4 is still open"},
        {"AttributeEnd alone", ribWorld("AttributeEnd"), "t.rib:4: RIB request 'AttributeEnd': without a matching AttributeBegin"},
        {"crossed blocks", ribWorld("AttributeBegin\nTransformBegin\nAttributeEnd"),
         "t.rib:6: RIB request 'AttributeEnd': the TransformBegin at line 5 is still open"},
        {"FrameEnd missing", "FrameBegin 1\nWorldBegin\nWorldEnd\n", "t.rib:3: the FrameBegin at line 1 has no FrameEnd"},
        {"no world", "Format 10 10 1\n# nothing\n", "t.rib:1: no WorldBegin: the file describes no scene"},
        {"empty file", "", "t.rib:1: no WorldBegin"},
        {"geometry before WorldBegin", "Sphere 1 -1 1 360\nWorldBegin\nWorldEnd\n",
         "t.rib:1: RIB request 'Sphere': is only allowed between WorldBegin and WorldEnd"},
        {"option inside the world", ribWorld("Format 10 10 1"), "t.rib:4: RIB request 'Format': must come before WorldBegin (line 3)"},
        {"a second world", ribWorld("") + "WorldBegin\nWorldEnd\n", "t.rib:6: RIB request 'WorldBegin': comes after WorldEnd"},
        {"WorldEnd alone", "WorldEnd\n", "t.rib:1: RIB request 'WorldEnd': is only allowed between WorldBegin and WorldEnd"},
    });
}

TEST_CASE("rib errors: malformed text") {
    checkCases({
        {"unterminated string", ribWorld("Surface \"matte\n\"Kd\" 1"), "t.rib:4: unterminated string"},
        {"string at the end", "WorldBegin\nSurface \"matte", "t.rib:2: unterminated string"},
        {"unterminated array", ribWorld("Polygon \"P\" [0 0 0\n1 0 0\n0 1 0\n"), "t.rib:4: unterminated array"},
        {"array at the end", "WorldBegin\nPolygon \"P\" [0 0 0", "t.rib:2: unterminated array"},
        {"nested array", ribWorld("Polygon \"P\" [[0 0 0]]"), "t.rib:4: nested arrays are not allowed"},
        {"mixed array", ribWorld("Polygon \"P\" [0 \"a\"]"), "t.rib:4: an array mixes numbers and strings"},
        {"stray bracket", ribWorld("Sphere 1 -1 1 360 ]"), "t.rib:4: ']' without a matching '['"},
        {"huge number", ribWorld("Translate 1e39 0 0"), "t.rib:4: number '1e39' is out of range"},
        {"beyond double", ribWorld("Translate 1e999 0 0"), "t.rib:4: number '1e999' is out of range"},
        {"malformed number", ribWorld("Translate 1.2.3 0 0"), "t.rib:4: malformed number '1.2.3'"},
        {"dangling exponent", ribWorld("Translate 1e 0 0"), "t.rib:4: malformed number '1e'"},
        {"lone sign", ribWorld("Translate - 0 0"), "t.rib:4: malformed number '-'"},
        {"value first", "1 2 3\nWorldBegin\nWorldEnd\n", "t.rib:1: a value before the first request"},
        {"binary RIB", std::string("WorldBegin\n\x85\x01\n"), "t.rib:2: unexpected byte 0x85 (binary RIB is not supported)"},
        {"stray brace", std::string("WorldBegin\n{\n"), "t.rib:2: unexpected character '{'"},
        {"NUL byte", std::string("WorldBegin\n\0\n", 13), "t.rib:2: unexpected character '\\x00'"},
    });
}

TEST_CASE("rib errors: the CLI reports one line and exits with 1") {
    auto dir = tempDir("rib");
    const auto file = dir / "bad.rib";
    std::ofstream(file) << "Format 8 8 1\nWorldBegin\nSurface \"wood\"\nWorldEnd\n";
    AppResult r = runApp("render " + file.string() + " -o " + (dir / "out.exr").string() + " --no-progress");
    CHECK(r.exitCode == 1);
    CHECK(r.out == "error: " + file.string() + ":3: RIB request 'Surface \"wood\"': surface shader 'wood' is not "
                                               "supported (matte, plastic and metal are)\n");
    const auto good = dir / "good.rib";
    std::ofstream(good) << "Format 8 6 1\nPixelSamples 1 1\nProjection \"perspective\"\nWorldBegin\n"
                           "LightSource \"ambientlight\" 1\nTranslate 0 0 3\nSphere 1 -1 1 360\nWorldEnd\n";
    r = runApp("render " + good.string() + " -o " + (dir / "good.exr").string() + " --no-progress");
    CHECK(r.exitCode == 0);
    CHECK(std::filesystem::exists(dir / "good.exr"));
    std::filesystem::remove_all(dir);
}
