// Node tree -> components -> Scene. Children are created before their parent (a
// component's constructor receives finished parts), in file order, so a <ref> can
// only name an object declared earlier — as in Mitsuba.
#include "effigi/xml/loader.hpp"

#include <algorithm>

namespace effigi {

namespace {

using NamedMap = std::map<std::string, Ref<IComponent>>;

/// The XML tag of a finished component: the registry names it "tag/name".
std::string tagOf(const Ref<IComponent>& c) {
    const std::string& t = c->typeName();
    return t.substr(0, t.find('/'));
}

[[noreturn]] void unknownRef(const xml::Child& c, const NamedMap& named) {
    std::vector<std::string> ids;
    for (const auto& kv : named) ids.push_back(kv.first);
    if (ids.empty()) failAt(c.where, "<ref id=\"{}\">: unknown id (no object with an id is declared before it)", c.refId);
    std::string known;
    for (const auto& id : ids) known += (known.empty() ? "" : ", ") + id;
    std::string hint = didYouMean(c.refId, ids);
    failAt(c.where, "<ref id=\"{}\">: unknown id{} (ids declared before it: {})", c.refId,
           hint.empty() ? "" : fmt::format("; did you mean '{}'?", hint), known);
}

Ref<IComponent> build(const xml::Node& node, Registry& registry, NamedMap& named) {
    Properties props = node.props;
    for (const xml::Child& c : node.children) {
        Ref<IComponent> obj;
        std::string tag;
        if (c.node) {
            obj = build(*c.node, registry, named);
            tag = c.node->tag;
        } else {
            auto it = named.find(c.refId);
            if (it == named.end()) unknownRef(c, named);
            obj = it->second;
            tag = tagOf(obj);
        }
        // Unnamed children go in under the empty name; the schema assigns them to its
        // child slots by tag.
        props.set(c.name, ComponentValue{tag, obj}, c.where);
    }
    Ref<IComponent> obj;
    try {
        obj = registry.create(node.tag, node.type, props);
    } catch (const Error&) {
        throw;
    } catch (const std::exception& ex) {
        // A component that throws something else still gets a located, one-line message.
        failAt(node.where, "{} '{}': {}", node.tag, node.type, ex.what());
    }
    if (!obj) failAt(node.where, "{} '{}': the component could not be created", node.tag, node.type);
    if (!node.id.empty()) named[node.id] = obj;
    return obj;
}

template <typename I> Ref<I> as(const Ref<IComponent>& obj, const xml::Node& node) {
    Ref<I> r = query<I>(obj);
    if (!r) failAt(node.where, "{} '{}' does not implement the {} interface", node.tag, node.type, I::Tag);
    return r;
}

} // namespace

Ref<IComponent> instantiate(const xml::Node& node, Registry& registry,
                            const std::map<std::string, Ref<IComponent>>& named) {
    NamedMap local = named;
    return build(node, registry, local);
}

std::unique_ptr<Scene> loadScene(const xml::Node& root, Registry& registry) {
    if (root.tag != "scene") failAt(root.where, "expected a <scene> element, got <{}>", root.tag);
    NamedMap named;
    std::vector<Ref<IShape>> shapes;
    std::vector<Ref<IEmitter>> emitters;
    Ref<ICamera> camera;
    Ref<IRenderer> renderer;
    Ref<IIntersect> accel;
    SourceLocation cameraAt, rendererAt, accelAt;

    auto once = [](const xml::Node& n, bool seen, const SourceLocation& first, const char* what) {
        if (seen) failAt(n.where, "a second {} (the first is at {}); a scene has exactly one", what, first.str());
    };
    for (const xml::Child& c : root.children) {
        if (!c.node) failAt(c.where, "a <ref> directly inside <scene> has no effect");
        const xml::Node& n = *c.node;
        const std::string& t = n.tag;
        bool part = t == "shape" || t == "emitter" || t == "camera" || t == "renderer" || t == "accelerator";
        if (!part && n.id.empty())
            failAt(n.where, "a top-level <{}> needs an id: outside a shape, camera or renderer it can only be "
                            "used through <ref id=\"...\"/>", t);
        if (t == "camera") once(n, camera != nullptr, cameraAt, "camera");
        if (t == "renderer") once(n, renderer != nullptr, rendererAt, "renderer (<integrator>)");
        if (t == "accelerator") once(n, accel != nullptr, accelAt, "accelerator");

        Ref<IComponent> obj = build(n, registry, named);
        if (t == "shape") {
            shapes.push_back(as<IShape>(obj, n));
        } else if (t == "emitter") {
            emitters.push_back(as<IEmitter>(obj, n));
        } else if (t == "camera") {
            camera = as<ICamera>(obj, n);
            cameraAt = n.where;
        } else if (t == "renderer") {
            renderer = as<IRenderer>(obj, n);
            rendererAt = n.where;
        } else if (t == "accelerator") {
            accel = as<IIntersect>(obj, n);
            accelAt = n.where;
        }
    }
    if (!camera) fail("{}: scene has no <sensor>/<camera>", root.where.file);
    if (!renderer) {
        Properties p("renderer", "path", root.where);
        renderer = query<IRenderer>(registry.create("renderer", "path", p));
        if (!renderer) fail("{}: the default renderer 'path' is not a renderer", root.where.file);
    }
    if (!accel) {
        Properties p("accelerator", "embree", root.where);
        accel = query<IIntersect>(registry.create("accelerator", "embree", p));
        if (!accel) fail("{}: the default accelerator 'embree' is not an accelerator", root.where.file);
    }
    auto scene = std::make_unique<Scene>(std::move(shapes), std::move(emitters), std::move(camera), std::move(accel),
                                         std::move(renderer));
    scene->sourceFile = root.where.file;
    return scene;
}

std::unique_ptr<Scene> loadSceneFile(const std::filesystem::path& path, const xml::ParseOptions& opt,
                                     Registry& registry) {
    std::unique_ptr<xml::Node> root = xml::parseFile(path, opt);
    return loadScene(*root, registry);
}

} // namespace effigi
