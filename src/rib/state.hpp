#pragma once
// The RIB interpreter's state (RenderMan's graphics state: options, the attribute and
// transform stacks) and what it produces, a SceneSpec: the camera, the lights as effigi
// <emitter> elements, the shapes as <shape> elements or triangle meshes, each with the
// surface in force. build.cpp turns a SceneSpec into a Scene.
#include "args.hpp"

#include "effigi/render/mesh.hpp"
#include "effigi/xml/parser.hpp"

#include <glm/mat4x4.hpp>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace effigi::rib {

/// A Surface request: the shader and its parameters, RenderMan's defaults filled in.
struct Surface {
    std::string type = "matte";  // RenderMan's implementation-defined default surface is read as matte
    double ka = 1.0, kd = 1.0, ks = 0.0, roughness = 0.1;
    Vector3d specularColor{1.0};
    SourceLocation where;
};

/// A bicubic basis matrix, row-major as RenderMan writes it (RI 3.2, §5.7).
using Basis = std::array<double, 16>;

/// What a shape is made of: the surface with the colour and opacity in force.
struct Material {
    Surface surface;
    Vector3d color{1.0}, opacity{1.0};
};

struct Attributes {
    glm::dmat4 ctm{1.0};  // object -> world inside the world block; world -> camera before it
    Material material;
    Basis basisU{}, basisV{};  // bicubic patch bases (set to Bezier at start)
};

struct CameraSpec {
    std::string projection = "orthographic";  // RenderMan's default projection
    double fov = 90.0;                       // RenderMan's default "fov"
    double nearClip = 1e-3, farClip = 1e7;   // camera-space distances
    int width = 640, height = 480;           // RenderMan's default Format
    std::int64_t spp = 0;                    // PixelSamples xs·ys; 0: not given
    glm::dmat4 worldToCamera{1.0};
    SourceLocation where;        // the Projection request (or WorldBegin)
    SourceLocation formatWhere;  // the Format request, if any
};

/// One shape: an analytic effigi shape (`node` set) or a triangle mesh in object space.
struct ShapeSpec {
    SourceLocation where;
    std::string label;  // the request, for errors
    std::unique_ptr<xml::Node> node;
    TriangleMesh mesh;
    bool faceNormals = false;
    glm::dmat4 toWorld{1.0};
    Material material;
};

struct SceneSpec {
    std::string file;
    CameraSpec camera;
    std::vector<std::unique_ptr<xml::Node>> emitters;
    std::vector<ShapeSpec> shapes;
};

struct State {
    enum class Phase { Options, World, Ended };
    enum class BlockKind { Frame, World, Attribute, Transform };
    struct Block {
        BlockKind kind;
        int line;
        Attributes saved;
    };

    SceneSpec scene;
    Attributes attr;
    std::vector<Block> blocks;
    Phase phase = Phase::Options;
    int worldLine = 0;

    SourceLocation at(int line) const { return {scene.file, line}; }
};

/// The transformation as effigi's (float) Transform; every entry must lie within ±1e38,
/// else an error at `where` about `what`.
Transform floatTransform(const glm::dmat4& m, const SourceLocation& where, const char* what);

/// Reads RIB text into a SceneSpec (interpreter.cpp); throws Error at file:line.
SceneSpec interpret(std::string_view text, const std::string& file);

/// An xml::Node for a component, as the XML parser would make it.
std::unique_ptr<xml::Node> makeNode(const std::string& tag, const std::string& type, const SourceLocation& where);

// Requests, by file. Each takes the state and the request's arguments.
void reqColor(State&, Args&);
void reqOpacity(State&, Args&);
void reqSurface(State&, Args&);
void reqLightSource(State&, Args&);
void reqSphere(State&, Args&);
void reqCylinder(State&, Args&);
void reqCone(State&, Args&);
void reqDisk(State&, Args&);
void reqPolygon(State&, Args&);
void reqGeneralPolygon(State&, Args&);
void reqPointsPolygons(State&, Args&);
void reqPointsGeneralPolygons(State&, Args&);
void reqPatch(State&, Args&);
void reqBasis(State&, Args&);

/// Adds a triangle mesh (object space) with the current transformation and material,
/// its winding made to agree with its normals (geometry.cpp).
void addMesh(State& s, Args& a, TriangleMesh m, bool faceNormals);

/// The bicubic basis matrices (RenderMan Interface 3.2, §5.7), by name; false if unknown.
bool namedBasis(const std::string& name, Basis& m);

/// The effigi BSDF element for a material (shading.cpp).
std::unique_ptr<xml::Node> bsdfNode(const Material& m, const SourceLocation& where);

} // namespace effigi::rib
