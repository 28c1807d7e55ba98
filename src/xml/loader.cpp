// Node tree -> components -> Scene. Children are created before their parent (a
// component's constructor receives finished parts), in file order. A <ref> may name an
// object declared later, as in Mitsuba 3: that object is then built first, on demand,
// and a cycle of references is an error naming the chain.
#include "effigi/xml/loader.hpp"

#include "animation.hpp"

#include "effigi/core/input.hpp"
#include "effigi/core/log.hpp"
#include "effigi/render/scene_range.hpp"
#include "effigi/rib/loader.hpp"

#include <mutex>

#include <algorithm>

namespace effigi {

namespace {

using NamedMap = std::map<std::string, Ref<IComponent>>;

/// The XML tag of a finished component: the registry names it "tag/name".
std::string tagOf(const Ref<IComponent>& c) {
    const std::string& t = c->typeName();
    return t.substr(0, t.find('/'));
}

/// Building one scene: every object with an id (at any depth) is known up front so that
/// a <ref> can build it on demand; `building` holds the ids under construction.
struct Builder {
    Registry& registry;
    NamedMap named;
    std::map<std::string, const xml::Node*> declared;
    std::vector<std::pair<std::string, SourceLocation>> building;

    void index(const xml::Node& n) {
        if (!n.id.empty()) declared.emplace(n.id, &n);
        for (const xml::Child& c : n.children)
            if (c.node) index(*c.node);
    }

    [[noreturn]] void unknownRef(const xml::Child& c) const {
        std::vector<std::string> ids;
        for (const auto& kv : named) ids.push_back(kv.first);
        for (const auto& kv : declared)
            if (!named.count(kv.first)) ids.push_back(kv.first);
        std::sort(ids.begin(), ids.end());
        if (ids.empty())
            failAt(c.where, "<ref id=\"{}\">: unknown id (no object in the scene has an id)", excerpt(c.refId));
        std::string hint = didYouMean(c.refId, ids);
        // Ids are the scene's text: each quoted through excerpt(), and a long list cut short.
        constexpr std::size_t MaxListed = 20;
        std::string list;
        for (std::size_t i = 0; i < std::min(ids.size(), MaxListed); ++i) list += (i ? ", " : "") + excerpt(ids[i]);
        if (ids.size() > MaxListed) list += fmt::format(", … ({} more)", ids.size() - MaxListed);
        failAt(c.where, "<ref id=\"{}\">: unknown id{} (ids in the scene: {})", excerpt(c.refId),
               hint.empty() ? "" : fmt::format("; did you mean '{}'?", excerpt(hint)), list);
    }

    Ref<IComponent> resolve(const xml::Child& c) {
        if (auto it = named.find(c.refId); it != named.end()) return it->second;
        auto d = declared.find(c.refId);
        if (d == declared.end()) unknownRef(c);
        auto cyc = std::find_if(building.begin(), building.end(), [&](auto& b) { return b.first == c.refId; });
        if (cyc != building.end()) {
            std::string chain;
            for (auto it = cyc; it != building.end(); ++it) chain += excerpt(it->first) + " -> ";
            failAt(c.where, "<ref id=\"{}\">: circular reference {}{} (declared at {})", excerpt(c.refId), chain,
                   excerpt(c.refId), d->second->where.str());
        }
        // A reference to an object declared later: build it now.
        return build(*d->second, nullptr);
    }

    /// The registry tag of an element, given its parent's. Mitsuba nests integrators in
    /// integrators (aov, moment), at any depth; inside an effigi renderer a nested
    /// <integrator> is a renderer too, unless it names one of effigi's numerical
    /// integrators (mean, stratified).
    std::string tagFor(const xml::Node& node, const std::string& parentTag) const {
        if (node.tag == "integrator" && parentTag == "renderer" &&
            !registry.knows("integrator", node.type) && registry.knows("renderer", typeFor("renderer", node.type)))
            return "renderer";
        return node.tag;
    }

    /// Renderer names effigi reads as another renderer (same parameters), each said once
    /// at -v. Mitsuba's `volpathmis` (spectral MIS over the wavelengths that sample
    /// distances) is what effigi's `volpath` always does. `lighttracer` (particle tracing
    /// connected to the camera) is Mitsuba's `ptracer`, the light-path walk photon mapping
    /// also uses (light_path.hpp).
    struct RendererAlias {
        const char* name;
        const char* as;
        const char* why;
    };
    static constexpr RendererAlias RendererAliases[] = {
        {"volpathmis", "volpath", "volpath samples distances with spectral MIS already"},
        {"lighttracer", "ptracer", "the same particle tracer"}};
    std::string typeFor(const std::string& tag, const std::string& type) const {
        if (tag != "renderer" || registry.knows(tag, type)) return type;
        static std::once_flag said[std::size(RendererAliases)];
        for (std::size_t i = 0; i < std::size(RendererAliases); ++i) {
            const RendererAlias& a = RendererAliases[i];
            if (type != a.name) continue;
            std::call_once(said[i], [&] { log::info("renderer '{}' is read as '{}' ({})", a.name, a.as, a.why); });
            return a.as;
        }
        return type;
    }

    /// `parentTag`: the registry tag the parent resolved to (a nested <integrator> may be
    /// a renderer, and then so may its own nested <integrator>).
    Ref<IComponent> build(const xml::Node& node, const xml::Node* parent, const std::string& parentTag = {}) {
        const std::string tag = tagFor(node, parentTag);
        const std::string type = typeFor(tag, node.type);
        if (!node.id.empty())
            if (auto it = named.find(node.id); it != named.end()) return it->second;  // built on demand earlier
        if (!node.id.empty()) building.emplace_back(node.id, node.where);
        Properties props = node.props;
        for (const xml::Child& c : node.children) {
            Ref<IComponent> obj;
            std::string childTag;
            if (c.node) {
                obj = build(*c.node, &node, tag);
                childTag = tagFor(*c.node, tag);
            } else {
                obj = resolve(c);
                childTag = tagOf(obj);
            }
            // Unnamed children go in under the empty name; the schema assigns them to its
            // child slots by tag.
            props.set(c.name, ComponentValue{childTag, obj}, c.where);
        }
        // An unknown nested type names its parent: "unknown integrator 'nope' ... inside
        // renderer 'moment' at file:line" says where to look in a deep tree.
        if (parent && !registry.knows(tag, type)) {
            try {
                // A nested <integrator> in a renderer is most likely meant as a renderer.
                bool nestedRenderer = tag == "integrator" && parentTag == "renderer";
                registry.info(nestedRenderer ? "renderer" : tag, type);
            } catch (const Error& e) {
                std::string msg = e.what();
                // A top-level <integrator> is a renderer in effigi; say what the file says.
                std::string outer = parent->tag == "renderer" ? "integrator" : parent->tag;
                failAt(node.where, "{} (inside {} '{}' at {})", msg, outer, excerpt(parent->type), parent->where.str());
            }
        }
        Ref<IComponent> obj;
        const auto motion = tag == "shape" ? xml::detail::takeShapeMotion(props) : std::nullopt;
        try {
            obj = registry.create(tag, type, props);
            if (motion && obj) obj = xml::detail::placeMoving(registry, obj, *motion, props);
        } catch (const Error&) {
            throw;
        } catch (const std::exception& ex) {
            // A component that throws something else still gets a located, one-line message.
            failAt(node.where, "{} '{}': {}", tag, excerpt(node.type), excerpt(ex.what(), 300));
        }
        if (!obj) failAt(node.where, "{} '{}': the component could not be created", tag, excerpt(node.type));
        // Geometry out of range would reach the accelerator as invalid rays: refuse it here,
        // where the <shape> is known (also inside shapegroups).
        if (tag == "shape")
            if (Ref<IShape> shape = query<IShape>(obj))
                if (std::string why = shapeRangeProblem(*shape); !why.empty())
                    failAt(node.where, "{}{}: {}", node.props.describe(),
                           node.id.empty() ? "" : fmt::format(" (id '{}')", excerpt(node.id)), why);
        if (!node.id.empty()) {
            named[node.id] = obj;
            building.pop_back();
        }
        return obj;
    }
};

template <typename I> Ref<I> as(const Ref<IComponent>& obj, const xml::Node& node) {
    Ref<I> r = query<I>(obj);
    if (!r) failAt(node.where, "{} '{}' does not implement the {} interface", node.tag, node.type, I::Tag);
    return r;
}

} // namespace

Ref<IComponent> instantiate(const xml::Node& node, Registry& registry,
                            const std::map<std::string, Ref<IComponent>>& named) {
    Builder b{registry, named, {}, {}};
    b.index(node);
    return b.build(node, nullptr);
}

/// A scene with participating media and a renderer that cannot render them: an error
/// for those that would give a wrong image, a warning for those that ignore media as
/// Mitsuba's `path` and `direct` do.
static void checkMediaSupport(const IRenderer& renderer, const SourceLocation& where) {
    const std::string name = renderer.typeName();
    switch (renderer.mediaSupport()) {
    case IRenderer::MediaSupport::Renders: return;
    case IRenderer::MediaSupport::Ignores:
        log::warn("{}: {} ignores the scene's participating media (as Mitsuba's does); volpath renders them",
                  where.str(), name);
        return;
    case IRenderer::MediaSupport::Refuses:
        failAt(where, "{} does not render participating media, and the scene has a <medium>: use volpath", name);
    }
}

std::unique_ptr<Scene> loadScene(const xml::Node& root, Registry& registry) {
    if (root.tag != "scene") failAt(root.where, "expected a <scene> element, got <{}>", root.tag);
    Builder builder{registry, {}, {}, {}};
    builder.index(root);
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

        Ref<IComponent> obj = builder.build(n, nullptr);
        if (t == "shape") {
            // A shapegroup is geometry for instances to reference (Mitsuba 3), never
            // rendered by itself: it stays out of the scene's shape list.
            if (n.type == "shapegroup") continue;
            shapes.push_back(as<IShape>(obj, n));
        } else if (t == "emitter") {
            emitters.push_back(as<IEmitter>(obj, n));
        } else if (t == "camera") {
            camera = as<ICamera>(obj, n);
            cameraAt = n.where;
            if (std::string why = cameraRangeProblem(*camera); !why.empty())
                failAt(n.where, "{}: {} (check 'to_world' and the clip planes)", n.props.describe(), why);
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
        // Mitsuba 3's scene-level switch for Embree's robust mode (off by default there,
        // on here: see the embree component).
        if (const char* robust = "embree_use_robust_intersections"; root.props.has(robust))
            p.set("robust", root.props.getBool(robust), root.props.whereOf(robust));
        accel = query<IIntersect>(registry.create("accelerator", "embree", p));
        if (!accel) fail("{}: the default accelerator 'embree' is not an accelerator", root.where.file);
    }
    auto scene = std::make_unique<Scene>(std::move(shapes), std::move(emitters), std::move(camera), std::move(accel),
                                         std::move(renderer));
    scene->sourceFile = root.where.file;
    if (scene->hasMedia()) checkMediaSupport(scene->renderer(), rendererAt.known() ? rendererAt : root.where);
    if (scene->hasMotion() && !scene->renderer().rendersMotion())
        failAt(rendererAt.known() ? rendererAt : root.where,
               "{} does not render motion blur, and a shape or the camera is animated: use path, volpath, direct, "
               "whitted or bdpt",
               scene->renderer().typeName());
    return scene;
}

std::unique_ptr<Scene> loadSceneFile(const std::filesystem::path& path, const xml::ParseOptions& opt,
                                     Registry& registry) {
    if (rib::isRibFile(path)) return rib::loadFile(path, opt, registry);  // RenderMan RIB (src/rib)
    std::unique_ptr<xml::Node> root = xml::parseFile(path, opt);
    return loadScene(*root, registry);
}

} // namespace effigi
