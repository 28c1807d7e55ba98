// SceneSpec -> Scene: the camera (with RenderMan's handedness), the film and sampler,
// the lights and shapes through the XML loader's instantiate(), the meshes as MeshShapes,
// then the default renderer (path) and accelerator (embree), as loadScene does for XML.
#include "state.hpp"

#include "effigi/core/input.hpp"
#include "effigi/render/scene_range.hpp"
#include "effigi/render/shape_base.hpp"
#include "effigi/rib/loader.hpp"
#include "effigi/xml/loader.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cctype>

namespace effigi::rib {

namespace {

/// A triangle mesh made by the translator (polygons, patches, tessellated quadrics).
class RibMesh final : public MeshShape {
public:
    RibMesh(const Properties& p, TriangleMesh mesh, bool faceNormals) : MeshShape(p) {
        m_faceNormals = faceNormals;
        setMesh(std::move(mesh), p.describe());
    }
};

void addChild(xml::Node& parent, std::unique_ptr<xml::Node> child) {
    SourceLocation where = child->where;
    parent.children.push_back(xml::Child{"", std::move(child), "", where});
}

/// Camera-to-world for effigi: RenderMan's camera space mirrored in x (RenderMan: x
/// right; effigi: x left). A perspective camera must not scale: a uniform scale is taken
/// out (it changes no direction) and applied to the clip distances instead.
std::unique_ptr<xml::Node> cameraNode(const CameraSpec& c, std::int64_t spp) {
    const double det = glm::determinant(glm::dmat3(c.worldToCamera));
    if (!(std::abs(det) > 1e-30) || !std::isfinite(det))
        failAt(c.where, "the camera transformation (before WorldBegin) is singular");
    glm::dmat4 toWorld = glm::inverse(c.worldToCamera) * glm::scale(glm::dmat4(1.0), Vector3d(-1.0, 1.0, 1.0));
    double nearClip = c.nearClip, farClip = c.farClip;
    const bool perspective = c.projection == "perspective";
    if (perspective) {
        const double s = glm::length(glm::dvec3(toWorld[0]));
        for (int i = 0; i < 3; ++i)
            for (int j = i; j < 3; ++j)
                if (std::abs(glm::dot(glm::dvec3(toWorld[i]), glm::dvec3(toWorld[j])) - (i == j ? s * s : 0.0)) >
                    1e-6 * s * s)
                    failAt(c.where, "the camera transformation must be rigid or scale uniformly (no shear, no "
                                    "non-uniform scale)");
        for (int i = 0; i < 3; ++i) toWorld[i] /= s;
        nearClip *= s;
        farClip *= s;
    } else {
        // RenderMan's default screen window spans [-1, 1] along the shorter image axis;
        // effigi's orthographic camera spans [-1, 1] across the width.
        const double k = std::max(1.0, double(c.width) / double(c.height));
        toWorld = toWorld * glm::scale(glm::dmat4(1.0), Vector3d(k, k, 1.0));
    }
    farClip = std::min(farClip, 1e30);
    if (!(nearClip < farClip)) failAt(c.where, "the clipping range is out of range after the camera's scale");
    std::unique_ptr<xml::Node> n = makeNode("camera", c.projection, c.where);
    n->props.set("to_world", floatTransform(toWorld, c.where, "the camera transformation"), c.where);
    n->props.set("near_clip", nearClip, c.where);
    n->props.set("far_clip", farClip, c.where);
    if (perspective) {
        n->props.set("fov", c.fov, c.where);
        n->props.set("fov_axis", std::string("smaller"), c.where);  // RenderMan's fov spans the shorter side
    }
    const SourceLocation& filmAt = c.formatWhere.known() ? c.formatWhere : c.where;
    std::unique_ptr<xml::Node> film = makeNode("film", "hdrfilm", filmAt);
    film->props.set("width", std::int64_t(c.width), filmAt);
    film->props.set("height", std::int64_t(c.height), filmAt);
    addChild(*n, std::move(film));
    std::unique_ptr<xml::Node> sampler = makeNode("sampler", "independent", c.where);
    sampler->props.set("sample_count", spp, c.where);
    addChild(*n, std::move(sampler));
    return n;
}

std::int64_t samplesPerPixel(const SceneSpec& spec, const xml::ParseOptions& opt) {
    std::int64_t spp = spec.camera.spp > 0 ? spec.camera.spp : 64;
    for (const auto& [name, value] : opt.defines) {
        if (name != "spp") fail("{}: -D {}: a RIB scene takes only -D spp=N", spec.file, excerpt(name));
        char* end = nullptr;
        long long v = std::strtoll(value.c_str(), &end, 10);
        if (value.empty() || *end != '\0' || v < 1 || v > (1 << 20))
            fail("{}: -D spp={}: expects an integer in [1, 2^20]", spec.file, excerpt(value));
        spp = v;
    }
    return spp;
}

Ref<IShape> buildShape(ShapeSpec& sh, Registry& registry) {
    const SourceLocation& surfaceAt = sh.material.surface.where;
    std::unique_ptr<xml::Node> bsdf = bsdfNode(sh.material, surfaceAt.known() ? surfaceAt : sh.where);
    if (sh.node) {
        addChild(*sh.node, std::move(bsdf));
        return query<IShape>(instantiate(*sh.node, registry));  // range-checked there
    }
    Properties p("shape", "mesh", sh.where);
    p.set("to_world", floatTransform(sh.toWorld, sh.where, "the shape's transformation"), sh.where);
    p.set("bsdf", ComponentValue{"bsdf", instantiate(*bsdf, registry)}, sh.where);
    try {
        auto mesh = std::make_shared<RibMesh>(p, std::move(sh.mesh), sh.faceNormals);
        mesh->setIdentity("shape/mesh", "");
        if (std::string why = shapeRangeProblem(*mesh); !why.empty()) fail("{}", why);
        return mesh;
    } catch (const Error& e) {
        failAt(sh.where, "RIB request '{}': {}", sh.label, e.what());
    }
}

std::unique_ptr<Scene> build(SceneSpec& spec, const xml::ParseOptions& opt, Registry& registry) {
    Ref<ICamera> camera = query<ICamera>(instantiate(*cameraNode(spec.camera, samplesPerPixel(spec, opt)), registry));
    if (!camera) failAt(spec.camera.where, "the camera could not be created");
    if (std::string why = cameraRangeProblem(*camera); !why.empty()) failAt(spec.camera.where, "the camera: {}", why);
    std::vector<Ref<IEmitter>> emitters;
    for (const auto& e : spec.emitters) emitters.push_back(query<IEmitter>(instantiate(*e, registry)));
    std::vector<Ref<IShape>> shapes;
    for (ShapeSpec& sh : spec.shapes) shapes.push_back(buildShape(sh, registry));
    const SourceLocation file{spec.file, 0};
    Properties rp("renderer", "path", file), ap("accelerator", "embree", file);
    Ref<IRenderer> renderer = query<IRenderer>(registry.create("renderer", "path", rp));
    Ref<IIntersect> accel = query<IIntersect>(registry.create("accelerator", "embree", ap));
    if (!renderer || !accel) fail("{}: the default renderer or accelerator could not be created", spec.file);
    auto scene = std::make_unique<Scene>(std::move(shapes), std::move(emitters), std::move(camera), std::move(accel),
                                         std::move(renderer));
    scene->sourceFile = spec.file;
    return scene;
}

} // namespace

bool isRibFile(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".rib";
}

std::unique_ptr<Scene> loadString(const std::string& text, const std::string& filename, const xml::ParseOptions& opt,
                                  Registry& registry) {
    SceneSpec spec = interpret(text, filename);
    return build(spec, opt, registry);
}

std::unique_ptr<Scene> loadFile(const std::filesystem::path& path, const xml::ParseOptions& opt, Registry& registry) {
    return loadString(readRegularFile(path, "RIB file"), path.string(), opt, registry);
}

} // namespace effigi::rib
