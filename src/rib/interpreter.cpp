// The RIB interpreter: requests dispatched by name (without regard to case), the block
// structure (Frame, World, Attribute, Transform), transformations and the camera options.
// Shading requests are in shading.cpp, geometry in geometry.cpp.
//
// Transformations follow the RenderMan Interface 3.2 (§4.3): each one is concatenated
// onto the current transformation so that it applies to objects first (CTM' = CTM · M);
// ConcatTransform and Transform take RenderMan's row-vector matrices (translation in
// elements 12–14). Before WorldBegin the CTM is the world-to-camera transformation;
// WorldBegin keeps it as the camera and starts the world with the identity, and inside
// the world block Identity and Transform set the CTM relative to world space.
#include "state.hpp"

#include "effigi/core/input.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cctype>

namespace effigi::rib {

namespace {

using Kind = State::BlockKind;

const char* blockName(Kind k) {
    switch (k) {
    case Kind::Frame: return "FrameBegin";
    case Kind::World: return "WorldBegin";
    case Kind::Attribute: return "AttributeBegin";
    case Kind::Transform: return "TransformBegin";
    }
    return "";
}

void push(State& s, Args& a, Kind k) {
    a.end();
    s.blocks.push_back({k, a.where().line, s.attr});
}

/// The innermost block, which `a`'s request closes; it must be of kind `k`.
State::Block pop(State& s, Args& a, Kind k) {
    a.end();
    if (std::none_of(s.blocks.begin(), s.blocks.end(), [&](const State::Block& b) { return b.kind == k; }))
        a.fail("without a matching {}", blockName(k));
    State::Block b = s.blocks.back();
    if (b.kind != k) a.fail("the {} at line {} is still open", blockName(b.kind), b.line);
    s.blocks.pop_back();
    return b;
}

void frameBegin(State& s, Args& a) {
    if (!a.atParams()) a.numbers(1);  // the frame number
    push(s, a, Kind::Frame);
}
void frameEnd(State& s, Args& a) { s.attr = pop(s, a, Kind::Frame).saved; }
void attributeBegin(State& s, Args& a) { push(s, a, Kind::Attribute); }
void attributeEnd(State& s, Args& a) { s.attr = pop(s, a, Kind::Attribute).saved; }
void transformBegin(State& s, Args& a) { push(s, a, Kind::Transform); }
void transformEnd(State& s, Args& a) { s.attr.ctm = pop(s, a, Kind::Transform).saved.ctm; }

void worldBegin(State& s, Args& a) {
    push(s, a, Kind::World);
    s.scene.camera.worldToCamera = s.attr.ctm;
    if (!s.scene.camera.where.known()) s.scene.camera.where = a.where();
    s.attr.ctm = glm::dmat4(1.0);
    s.phase = State::Phase::World;
    s.worldLine = a.where().line;
}

void worldEnd(State& s, Args& a) {
    s.attr = pop(s, a, Kind::World).saved;
    s.phase = State::Phase::Ended;
}

// --- transformations

void concat(State& s, Args& a, const glm::dmat4& m) {
    s.attr.ctm = s.attr.ctm * m;
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!(std::abs(s.attr.ctm[c][r]) <= MaxNumber)) a.fail("the current transformation overflows (beyond ±1e38)");
}

/// RenderMan's row-vector matrix as a column-vector one (the transpose: glm reads the
/// 16 numbers column by column). Projective matrices are refused.
glm::dmat4 matrixArg(Args& a) {
    std::vector<double> v = a.numbers(16);
    a.end();
    if (v[3] != 0.0 || v[7] != 0.0 || v[11] != 0.0 || v[15] == 0.0)
        a.fail("projective matrices are not supported (the last column must be 0 0 0 w, w != 0)");
    return glm::make_mat4(v.data()) / v[15];
}

void identity(State& s, Args& a) {
    a.end();
    s.attr.ctm = glm::dmat4(1.0);
}
void transform(State& s, Args& a) {
    glm::dmat4 m = matrixArg(a);
    s.attr.ctm = glm::dmat4(1.0);
    concat(s, a, m);
}
void concatTransform(State& s, Args& a) { concat(s, a, matrixArg(a)); }

void translate(State& s, Args& a) {
    std::vector<double> v = a.numbers(3);
    a.end();
    concat(s, a, glm::translate(glm::dmat4(1.0), Vector3d(v[0], v[1], v[2])));
}

void scale(State& s, Args& a) {
    std::vector<double> v = a.numbers(3);
    a.end();
    concat(s, a, glm::scale(glm::dmat4(1.0), Vector3d(v[0], v[1], v[2])));
}

void rotate(State& s, Args& a) {
    std::vector<double> v = a.numbers(4);
    a.end();
    Vector3d axis(v[1], v[2], v[3]);
    double len = glm::length(axis);
    if (!(len > 0.0) || !std::isfinite(len)) a.fail("the rotation axis must be a non-zero, finite vector");
    concat(s, a, glm::rotate(glm::dmat4(1.0), glm::radians(v[0]), axis / len));
}

// --- options (before WorldBegin)

void projection(State& s, Args& a) {
    std::string name = a.string("projection name");
    CameraSpec& c = s.scene.camera;
    a.setLabel(fmt::format("Projection \"{}\"", excerpt(name)));
    if (name != "perspective" && name != "orthographic") a.fail("projection '{}' is not supported", excerpt(name));
    Params p = a.params();
    if (name == "perspective") c.fov = p.real("fov", 90.0);
    p.finish();
    c.projection = name;
    c.where = a.where();
    s.attr.ctm = glm::dmat4(1.0);  // RiProjection clears the current transformation
}

void format(State& s, Args& a) {
    std::vector<double> v = a.numbers(3);
    a.end();
    for (int i = 0; i < 2; ++i)
        if (!(v[i] >= 1.0 && v[i] <= 32768.0) || v[i] != std::floor(v[i]))
            a.fail("the resolution must be whole numbers in [1, 32768], got {} x {}", v[0], v[1]);
    if (v[2] > 0.0 && v[2] != 1.0) a.fail("a pixel aspect ratio other than 1 is not supported (got {})", v[2]);
    s.scene.camera.formatWhere = a.where();
    s.scene.camera.width = int(v[0]);
    s.scene.camera.height = int(v[1]);
}

void display(State&, Args& a) {
    // The output name is the CLI's -o; type, mode and the display's parameters do not
    // change the image effigi computes.
    a.string("display name");
    a.string("display type");
    a.string("display mode");
    a.params();
}

void pixelSamples(State& s, Args& a) {
    std::vector<double> v = a.numbers(2);
    a.end();
    if (!(v[0] >= 1.0 && v[1] >= 1.0 && v[0] * v[1] <= 1048576.0))
        a.fail("expects two numbers >= 1 whose product is at most 2^20, got {} {}", v[0], v[1]);
    s.scene.camera.spp = std::int64_t(std::round(v[0])) * std::int64_t(std::round(v[1]));
}

void clipping(State& s, Args& a) {
    std::vector<double> v = a.numbers(2);
    a.end();
    if (!(v[0] > 0.0 && v[1] > v[0])) a.fail("expects 0 < near < far, got {} {}", v[0], v[1]);
    s.scene.camera.nearClip = v[0];
    s.scene.camera.farClip = std::min(v[1], 1e30);
}

void ignored(State&, Args&) {}

enum class When { Options, World, Anywhere };
struct Handler {
    const char* name;
    void (*fn)(State&, Args&);
    When when;
};

constexpr Handler Handlers[] = {
    {"FrameBegin", frameBegin, When::Options}, {"FrameEnd", frameEnd, When::Anywhere},
    {"WorldBegin", worldBegin, When::Options}, {"WorldEnd", worldEnd, When::World},
    {"AttributeBegin", attributeBegin, When::Anywhere}, {"AttributeEnd", attributeEnd, When::Anywhere},
    {"TransformBegin", transformBegin, When::Anywhere}, {"TransformEnd", transformEnd, When::Anywhere},
    {"Identity", identity, When::Anywhere}, {"Transform", transform, When::Anywhere},
    {"ConcatTransform", concatTransform, When::Anywhere}, {"Translate", translate, When::Anywhere},
    {"Rotate", rotate, When::Anywhere}, {"Scale", scale, When::Anywhere},
    {"Projection", projection, When::Options}, {"Format", format, When::Options},
    {"Display", display, When::Options}, {"PixelSamples", pixelSamples, When::Options},
    {"Clipping", clipping, When::Options},
    {"Color", reqColor, When::Anywhere}, {"Opacity", reqOpacity, When::Anywhere},
    {"Surface", reqSurface, When::Anywhere}, {"LightSource", reqLightSource, When::World},
    {"light", reqLightSource, When::World},  // RIB before 3.1 (Firebaugh's example)
    {"Sphere", reqSphere, When::World}, {"Cylinder", reqCylinder, When::World},
    {"Cone", reqCone, When::World}, {"Disk", reqDisk, When::World},
    {"Polygon", reqPolygon, When::World}, {"GeneralPolygon", reqGeneralPolygon, When::World},
    {"gpolygon", reqGeneralPolygon, When::World},  // RIB before 3.1
    {"PointsPolygons", reqPointsPolygons, When::World},
    {"PointsGeneralPolygons", reqPointsGeneralPolygons, When::World},
    {"Patch", reqPatch, When::World}, {"Basis", reqBasis, When::Anywhere},
    // Accepted and ignored, with any arguments: they tune a REYES renderer (dicing,
    // culling, quantisation) or name things, and change nothing a path tracer computes.
    // Sides and Orientation: every surface is two-sided (see shading.cpp).
    {"version", ignored, When::Anywhere}, {"Option", ignored, When::Anywhere},
    {"Attribute", ignored, When::Anywhere}, {"Declare", ignored, When::Anywhere},
    {"ShadingRate", ignored, When::Anywhere}, {"ShadingInterpolation", ignored, When::Anywhere},
    {"Sides", ignored, When::Anywhere}, {"Orientation", ignored, When::Anywhere},
    {"ReverseOrientation", ignored, When::Anywhere}, {"Bound", ignored, When::Anywhere},
    {"Detail", ignored, When::Anywhere}, {"DetailRange", ignored, When::Anywhere},
    {"PixelFilter", ignored, When::Options}, {"Quantize", ignored, When::Options},
    {"Hider", ignored, When::Options},
};

bool sameName(std::string_view a, std::string_view b) {
    return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
               return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
           });
}

void dispatch(State& s, const Request& r) {
    const Handler* h = nullptr;
    for (const Handler& c : Handlers)
        if (sameName(c.name, r.name)) h = &c;
    if (!h) failAt(s.at(r.line), "RIB request '{}' is not supported", excerpt(r.name));
    Args a(r, s.scene.file);
    const bool ignoredOne = h->fn == ignored;
    if (s.phase == State::Phase::Ended && h->fn != frameEnd && !ignoredOne)
        a.fail("comes after WorldEnd: only one world block (one frame) per file is supported");
    if (h->when == When::Options && s.phase == State::Phase::World)
        a.fail("must come before WorldBegin (line {})", s.worldLine);
    if (h->when == When::World && s.phase != State::Phase::World)
        a.fail("is only allowed between WorldBegin and WorldEnd");
    try {
        h->fn(s, a);
    } catch (const Error& e) {
        if (e.where().known()) throw;
        a.fail("{}", e.what());  // an error from a helper that knows no place
    }
}

} // namespace

std::unique_ptr<xml::Node> makeNode(const std::string& tag, const std::string& type, const SourceLocation& where) {
    auto n = std::make_unique<xml::Node>();
    n->tag = tag;
    n->type = type;
    n->where = where;
    n->props = Properties(tag, type, where);
    return n;
}

Transform floatTransform(const glm::dmat4& m, const SourceLocation& where, const char* what) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            if (!(std::abs(m[c][r]) <= MaxNumber)) failAt(where, "{} is out of range (an entry beyond ±1e38)", what);
    return Transform(glm::mat4(m));
}

SceneSpec interpret(std::string_view text, const std::string& file) {
    State s;
    s.scene.file = file;
    namedBasis("bezier", s.attr.basisU);
    namedBasis("bezier", s.attr.basisV);
    Reader reader(text, file);
    Request r;
    while (reader.next(r)) dispatch(s, r);
    const SourceLocation end = s.at(reader.line());
    if (!s.blocks.empty()) {
        const State::Block& b = s.blocks.back();
        const char* close[] = {"FrameEnd", "WorldEnd", "AttributeEnd", "TransformEnd"};
        failAt(end, "the {} at line {} has no {} (end of file)", blockName(b.kind), b.line, close[int(b.kind)]);
    }
    if (s.phase == State::Phase::Options) failAt(end, "no WorldBegin: the file describes no scene");
    return std::move(s.scene);
}

} // namespace effigi::rib
