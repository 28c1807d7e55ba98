// Scene XML (Mitsuba 3 grammar) -> Node tree. pugixml does the XML; this file does
// the grammar: which elements exist, $variables (variables.cpp), <include>, <path> and
// file names (Mitsuba's file resolver, resolver.cpp), aliases, version < 3 names
// (upgrade.cpp), ids. Values are typed in values.cpp. pugixml reports byte offsets,
// which are turned into line numbers so that every node and error can say file:line.
#include "effigi/xml/parser.hpp"

#include "effigi/core/input.hpp"
#include "resolver.hpp"
#include "upgrade.hpp"
#include "values.hpp"
#include "variables.hpp"

#include <pugixml.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>

namespace effigi::xml {

using detail::Element;
using detail::upgradeAttribute;
using detail::upgradeFromV1;
using detail::upgradeName;
using detail::upgradeTag;

namespace {

const std::vector<std::string> kPropertyTags = {"boolean", "integer", "float",    "string",    "point",
                                                "vector",  "rgb",     "spectrum", "blackbody", "transform", "animation"};
const std::vector<std::string> kObjectTags = {
    "function", "integrator", "sampler", "generator", "warp",   "rootfinder",      "shape",
    "accelerator", "bsdf",   "texture", "emitter",   "camera", "sensor",          "rfilter",
    "film",     "mesh",      "store",   "illuminationmap", "pathgenerator", "renderer", "solver",
    "formfactor", "medium", "phase", "volume"};
const std::vector<std::string> kSpecialTags = {"default", "include", "ref", "path"};

bool contains(const std::vector<std::string>& v, const std::string& s) {
    return std::find(v.begin(), v.end(), s) != v.end();
}

/// One XML file being read: its name for errors, directory for relative paths, and
/// where its lines start.
struct SourceFile {
    std::string name;
    std::filesystem::path dir;
    std::vector<std::size_t> newlines;
    bool oldNames = false;  // version < 3.0: camelCase names
    int major = 3;          // the file's version="major.minor.patch"

    SourceFile(std::string n, std::filesystem::path d, const std::string& text)
        : name(std::move(n)), dir(std::move(d)) {
        for (std::size_t i = 0; i < text.size(); ++i)
            if (text[i] == '\n') newlines.push_back(i);
    }
    SourceLocation at(std::ptrdiff_t offset) const {
        if (offset < 0) return {name, 0};
        auto before = std::lower_bound(newlines.begin(), newlines.end(), std::size_t(offset));
        return {name, int(before - newlines.begin()) + 1};
    }
};

/// Names already used inside one element (properties and named children share them).
using NameMap = std::map<std::string, SourceLocation>;

class Parser {
public:
    explicit Parser(const ParseOptions& opt) : m_vars(opt.defines) {}

    std::unique_ptr<Node> parseTop(const std::string& text, const std::string& filename) {
        auto root = std::make_unique<Node>();
        root->tag = "scene";
        NameMap names;
        std::error_code ec;
        std::filesystem::path canon = std::filesystem::weakly_canonical(filename, ec);
        m_stack.push_back(ec ? std::filesystem::path(filename) : canon);
        // Mitsuba's file resolver starts with the folder of the main scene file.
        m_resolver.reset(std::filesystem::path(filename).parent_path());
        parseDocument(text, filename, nullptr, *root, names);
        m_vars.checkDefinesUsed(filename);
        return root;
    }

private:
    /// Parse one file and add its <scene>'s children to `parent`; `includer` is the file
    /// that included it (null for the top file).
    void parseDocument(const std::string& text, const std::string& filename, const SourceFile* includer,
                       Node& parent, NameMap& names) {
        std::filesystem::path path(filename);
        SourceFile f(filename, path.parent_path(), text);
        pugi::xml_document doc;
        pugi::xml_parse_result res = doc.load_buffer(text.data(), text.size(), pugi::parse_default);
        if (!res) failAt(f.at(res.offset), "malformed XML: {}", res.description());

        pugi::xml_node root;
        for (pugi::xml_node x : doc.children()) {
            if (x.type() != pugi::node_element) continue;
            if (root) failAt(f.at(x.offset_debug()), "malformed XML: a second root element <{}>", excerpt(x.name()));
            root = x;
        }
        if (!root) failAt({filename, 0}, "malformed XML: no root element");
        Element e = element(root, f, false);
        if (e.tag != "scene") e.fail("the root element must be <scene>");
        e.allowOnly({"version"});
        if (const std::string* v = e.find("version")) {
            f.major = versionMajor(e, *v);
            f.oldNames = f.major < 3;
        } else if (includer) {
            f.oldNames = includer->oldNames;
            f.major = includer->major;
        } else {
            e.fail("missing attribute 'version' (e.g. version=\"3.0.0\")");
        }
        if (!includer) {
            parent.where = e.where;
            parent.props = Properties("scene", "", e.where);
        }
        parseChildren(root, f, parent, names);
    }

    static int versionMajor(const Element& e, const std::string& v) {
        int major = 0;
        auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), major);
        bool ok = ec == std::errc() && ptr != v.data();
        for (const char* p = ptr; ok && p != v.data() + v.size(); ++p)
            ok = std::isdigit(static_cast<unsigned char>(*p)) || *p == '.';
        if (!ok) e.fail("attribute 'version': expected major.minor.patch, got '{}'", excerpt(v));
        return major;
    }

    /// An element's attributes, after $substitution unless `raw`.
    Element element(pugi::xml_node x, const SourceFile& f, bool substitute) {
        Element e;
        e.tag = f.oldNames ? upgradeTag(x.name()) : std::string(x.name());
        e.where = f.at(x.offset_debug());
        for (pugi::xml_attribute a : x.attributes()) {
            std::string name = f.oldNames ? upgradeAttribute(e.tag, a.name()) : std::string(a.name());
            if (e.find(name)) e.fail("attribute '{}' given twice", excerpt(name));
            e.attrs.emplace_back(name, a.value());
        }
        // `name` first, so that errors in the other attributes can name the element.
        for (auto& [k, v] : e.attrs) {
            if (k != "name") continue;
            if (substitute) v = m_vars.substitute(v, e, k);
            e.name = f.oldNames ? upgradeName(v) : v;
        }
        if (substitute)
            for (auto& [k, v] : e.attrs)
                if (k != "name") v = m_vars.substitute(v, e, k);
        return e;
    }

    void checkName(NameMap& names, const Node& parent, const Element& e) {
        if (e.name.empty() || parent.tag == "scene") return;
        auto [it, fresh] = names.emplace(e.name, e.where);
        if (!fresh)
            e.fail("duplicate name '{}' in {} '{}' (first given at {})", excerpt(e.name), parent.tag,
                   excerpt(parent.type), it->second.str());
    }

    void parseChildren(pugi::xml_node xml, const SourceFile& f, Node& node, NameMap& names) {
        bool topLevel = node.tag == "scene";
        for (pugi::xml_node x : xml.children()) {
            if (x.type() == pugi::node_pcdata || x.type() == pugi::node_cdata)
                failAt(f.at(x.offset_debug()), "unexpected text '{}' inside <{}>", excerpt(x.value()),
                       excerpt(xml.name()));
            if (x.type() != pugi::node_element) continue;
            std::string tag = f.oldNames ? upgradeTag(x.name()) : std::string(x.name());
            if (tag == "default") {
                m_vars.declare(element(x, f, false));
            } else if (tag == "include") {
                parseInclude(x, f, node, names);
            } else if (tag == "path") {
                parsePath(x, f, node);
            } else if (tag == "ref") {
                Element e = element(x, f, true);
                e.allowOnly({"id", "name"});
                const std::string& id = e.require("id");
                if (topLevel) e.fail("a <ref> directly inside <scene> has no effect");
                if (!x.first_child().empty()) e.fail("a <ref> takes no children");
                checkName(names, node, e);
                node.children.push_back(Child{e.name, nullptr, id, e.where});
            } else if (contains(kPropertyTags, tag)) {
                parseProperty(x, f, node, names);
            } else if (contains(kObjectTags, tag)) {
                parseObject(x, f, node, names);
            } else {
                std::vector<std::string> all = kPropertyTags;
                all.insert(all.end(), kObjectTags.begin(), kObjectTags.end());
                all.insert(all.end(), kSpecialTags.begin(), kSpecialTags.end());
                std::string hint = didYouMean(tag, all);
                failAt(f.at(x.offset_debug()), "unknown element <{}>{}", excerpt(tag),
                       hint.empty() ? "" : fmt::format(" (did you mean <{}>?)", hint));
            }
        }
    }

    void parseInclude(pugi::xml_node x, const SourceFile& f, Node& node, NameMap& names) {
        Element e = element(x, f, true);
        e.allowOnly({"filename"});
        std::filesystem::path rel = e.require("filename");
        // As in Mitsuba: the including file's folder first, then the search path (<path>
        // entries and the main scene's folder).
        std::vector<std::filesystem::path> tried;
        std::filesystem::path p = m_resolver.find(rel, f.dir, false, tried);
        std::error_code ec;
        if (!std::filesystem::exists(p, ec))
            e.fail("cannot open included file '{}' (looked for {})", excerpt(rel.string(), 200),
                   excerpt(detail::joinPaths(tried), 1000));
        std::string text;
        try {
            text = readRegularFile(p, "included file");  // refuses /dev/zero, FIFOs, folders
        } catch (const Error& err) {
            e.fail("{}", err.what());
        }
        std::filesystem::path canon = std::filesystem::weakly_canonical(p, ec);
        if (ec) canon = p;
        if (std::find(m_stack.begin(), m_stack.end(), canon) != m_stack.end()) {
            std::string chain;
            for (const auto& s : m_stack) chain += excerpt(s.filename().string()) + " -> ";
            e.fail("include cycle: {}{}", chain, excerpt(canon.filename().string()));
        }
        m_stack.push_back(canon);
        // <path> entries of the included file hold while it is read, as in Mitsuba.
        std::vector<std::filesystem::path> searchPath = m_resolver.dirs();
        parseDocument(text, p.string(), &f, node, names);
        m_resolver.setDirs(std::move(searchPath));
        m_stack.pop_back();
    }

    /// <path value="dir"/>: put a folder in front of the search path for file names
    /// given later; a relative one is looked up from the current file's folder first.
    void parsePath(pugi::xml_node x, const SourceFile& f, const Node& node) {
        Element e = element(x, f, true);
        e.allowOnly({"value"});
        const std::string& value = e.require("value");
        if (node.tag != "scene") e.fail("<path> must be a direct child of <scene>");
        if (!x.first_child().empty()) e.fail("a <path> takes no children");
        std::vector<std::filesystem::path> tried;
        std::filesystem::path dir = m_resolver.find(value, f.dir, true, tried);
        std::error_code ec;
        if (!std::filesystem::is_directory(dir, ec))
            e.fail("folder '{}' not found (looked for {})", excerpt(value, 200),
                   excerpt(detail::joinPaths(tried), 1000));
        m_resolver.prepend(dir);
    }

    void parseProperty(pugi::xml_node x, const SourceFile& f, Node& node, NameMap& names) {
        Element e = element(x, f, true);
        if (e.name.empty()) e.fail("missing attribute 'name'");
        // Mitsuba 3's scene takes one property of its own (the loader hands it to Embree).
        if (node.tag == "scene" && e.name != "embree_use_robust_intersections")
            e.fail("properties belong inside an object, not directly inside <scene> (the only scene property is "
                   "embree_use_robust_intersections)");
        PropertyValue value;
        if (e.tag == "transform") {
            e.allowOnly({"name"});
            value = transformOps(x, f, e);
        } else if (e.tag == "animation") {
            // Mitsuba 0.6's keyframed transform: <transform time="t"> children in
            // increasing time (AnimatedTransform interpolates between them).
            e.allowOnly({"name"});
            std::vector<AnimatedTransform::Key> keys;
            for (pugi::xml_node c : x.children()) {
                if (c.type() == pugi::node_pcdata || c.type() == pugi::node_cdata)
                    e.fail("unexpected text '{}'", excerpt(c.value()));
                if (c.type() != pugi::node_element) continue;
                Element k = element(c, f, true);
                k.context = e.describe();
                if (k.tag != "transform") k.fail("an <animation> holds only <transform time=\"...\"> keyframes");
                k.allowOnly({"time"});
                const float time = float(detail::parseNumber(k, "time", k.require("time")));
                if (!keys.empty() && !(time > keys.back().time))
                    k.fail("keyframe times must increase (this one is {} after {})", time, keys.back().time);
                keys.push_back({time, transformOps(c, f, k)});
            }
            if (keys.empty()) e.fail("an <animation> needs at least one <transform time=\"...\"> keyframe");
            value = AnimatedTransform(std::move(keys));
        } else {
            for (pugi::xml_node c : x.children())
                if (c.type() == pugi::node_element || c.type() == pugi::node_pcdata)
                    e.fail("a property element takes no content");
            // File names go through the search path (<path>, the main scene's folder).
            const char* fileAttr = e.tag == "spectrum"                           ? "filename"
                                   : e.tag == "string" && e.name == "filename" ? "value"
                                                                               : nullptr;
            for (auto& [k, v] : e.attrs)
                if (fileAttr && k == fileAttr) v = m_resolver.resolveName(v, f.dir);
            value = detail::parseProperty(e, f.dir);
        }
        checkName(names, node, e);
        node.props.set(e.name, std::move(value), e.where);
    }

    /// The transform composed of the operations inside x (<translate>, <rotate>, ...).
    Transform transformOps(pugi::xml_node x, const SourceFile& f, const Element& e) {
        Transform m;
        for (pugi::xml_node c : x.children()) {
            if (c.type() == pugi::node_pcdata || c.type() == pugi::node_cdata)
                e.fail("unexpected text '{}'", excerpt(c.value()));
            if (c.type() != pugi::node_element) continue;
            Element op = element(c, f, true);
            op.context = e.describe();
            if (!c.first_child().empty()) op.fail("a transform operation takes no content");
            detail::applyTransformOp(op, m);
        }
        const glm::mat4 &a = m.matrix(), &b = m.inverseMatrix();
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
                if (!std::isfinite(a[i][j]) || !std::isfinite(b[i][j]))
                    e.fail("the composed transform is not finite (or is singular)");
        return m;
    }

    void parseObject(pugi::xml_node x, const SourceFile& f, Node& parent, NameMap& names) {
        Element e = element(x, f, true);
        e.allowOnly({"type", "id", "name"});
        const std::string* type = e.find("type");
        if (!type || type->empty()) e.fail("missing attribute 'type'");
        auto node = std::make_unique<Node>();
        node->tag = e.tag == "sensor" ? "camera" : e.tag;
        // A top-level <integrator> is Mitsuba's rendering method: effigi's renderer.
        if (node->tag == "integrator" && parent.tag == "scene") node->tag = "renderer";
        node->type = *type;
        node->where = e.where;
        node->props = Properties(node->tag, node->type, e.where);
        if (const std::string* id = e.find("id")) {
            if (id->empty()) e.fail("attribute 'id' is empty");
            auto [it, fresh] = m_ids.emplace(*id, e.where);
            if (!fresh) e.fail("duplicate id '{}' (first used at {})", excerpt(*id), it->second.str());
            node->id = *id;
            node->props.setId(*id);
        }
        checkName(names, parent, e);
        // Real scenes nest a handful of levels; the limit keeps hostile input off the stack.
        if (++m_depth > kMaxDepth) e.fail("objects are nested more than {} levels deep", kMaxDepth);
        NameMap inner;
        parseChildren(x, f, *node, inner);
        if (f.major < 2) upgradeFromV1(*node);
        --m_depth;
        parent.children.push_back(Child{e.name, std::move(node), "", e.where});
    }

    detail::Variables m_vars;                           // <default>, -D and $substitution
    std::map<std::string, SourceLocation> m_ids;
    std::vector<std::filesystem::path> m_stack;         // files being included
    detail::FileResolver m_resolver;                    // the search path for file names
    static constexpr int kMaxDepth = 100;
    int m_depth = 0;
};

} // namespace

std::unique_ptr<Node> parseString(const std::string& text, const std::string& filename, const ParseOptions& opt) {
    return Parser(opt).parseTop(text, filename);
}

std::unique_ptr<Node> parseFile(const std::filesystem::path& path, const ParseOptions& opt) {
    std::string text = readRegularFile(path, "scene file");
    return Parser(opt).parseTop(text, path.string());
}

} // namespace effigi::xml
