// Scene XML (Mitsuba 3 grammar) -> Node tree. pugixml does the XML; this file does
// the grammar: which elements exist, $variables, <include>, aliases, version < 3
// names, ids. Values are typed in values.cpp. pugixml reports byte offsets, which
// are turned into line numbers so that every node and error can say file:line.
#include "effigi/xml/parser.hpp"

#include "values.hpp"

#include <pugixml.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <fstream>
#include <sstream>

namespace effigi::xml {

using detail::Element;

namespace {

const std::vector<std::string> kPropertyTags = {"boolean", "integer", "float",    "string",    "point",
                                                "vector",  "rgb",     "spectrum", "blackbody", "transform"};
const std::vector<std::string> kObjectTags = {
    "function", "integrator", "sampler", "generator", "warp",   "rootfinder",      "shape",
    "accelerator", "bsdf",   "texture", "emitter",   "camera", "sensor",          "rfilter",
    "film",     "mesh",      "store",   "illuminationmap", "pathgenerator", "renderer", "solver",
    "formfactor"};
const std::vector<std::string> kSpecialTags = {"default", "include", "ref"};

bool contains(const std::vector<std::string>& v, const std::string& s) {
    return std::find(v.begin(), v.end(), s) != v.end();
}

bool isIdentifier(const std::string& s) {
    if (s.empty() || !(std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
    return std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

std::string readFile(const std::filesystem::path& p, bool& ok) {
    std::ifstream in(p, std::ios::binary);
    ok = in && !std::filesystem::is_directory(p);
    if (!ok) return {};
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

/// One XML file being read: its name for errors, directory for relative paths, and
/// where its lines start.
struct SourceFile {
    std::string name;
    std::filesystem::path dir;
    std::vector<std::size_t> newlines;
    bool oldNames = false;  // version < 3.0: camelCase names

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
    explicit Parser(const ParseOptions& opt) : m_opt(opt) {}

    std::unique_ptr<Node> parseTop(const std::string& text, const std::string& filename) {
        auto root = std::make_unique<Node>();
        root->tag = "scene";
        NameMap names;
        std::error_code ec;
        std::filesystem::path canon = std::filesystem::weakly_canonical(filename, ec);
        m_stack.push_back(ec ? std::filesystem::path(filename) : canon);
        parseDocument(text, filename, nullptr, *root, names);
        for (const auto& [name, value] : m_opt.defines)
            if (!m_declared.count(name))
                fail("{}: -D {}: scene declares no <default name=\"{}\">", filename, name, name);
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
            if (root) failAt(f.at(x.offset_debug()), "malformed XML: a second root element <{}>", x.name());
            root = x;
        }
        if (!root) failAt({filename, 0}, "malformed XML: no root element");
        Element e = element(root, f, false);
        if (e.tag != "scene") e.fail("the root element must be <scene>");
        e.allowOnly({"version"});
        if (const std::string* v = e.find("version")) {
            f.oldNames = versionBefore3(e, *v);
        } else if (includer) {
            f.oldNames = includer->oldNames;
        } else {
            e.fail("missing attribute 'version' (e.g. version=\"3.0.0\")");
        }
        if (!includer) {
            parent.where = e.where;
            parent.props = Properties("scene", "", e.where);
        }
        parseChildren(root, f, parent, names);
    }

    static bool versionBefore3(const Element& e, const std::string& v) {
        int major = 0;
        auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), major);
        bool ok = ec == std::errc() && ptr != v.data();
        for (const char* p = ptr; ok && p != v.data() + v.size(); ++p)
            ok = std::isdigit(static_cast<unsigned char>(*p)) || *p == '.';
        if (!ok) e.fail("attribute 'version': expected major.minor.patch, got '{}'", v);
        return major < 3;
    }

    /// An element's attributes, after $substitution unless `raw`.
    Element element(pugi::xml_node x, const SourceFile& f, bool substitute) {
        Element e;
        e.tag = x.name();
        e.where = f.at(x.offset_debug());
        for (pugi::xml_attribute a : x.attributes()) {
            std::string name = a.name();
            if (e.find(name)) e.fail("attribute '{}' given twice", name);
            e.attrs.emplace_back(name, a.value());
        }
        // `name` first, so that errors in the other attributes can name the element.
        for (auto& [k, v] : e.attrs) {
            if (k != "name") continue;
            if (substitute) v = substituted(v, e, k);
            e.name = f.oldNames ? camelToSnake(v) : v;
        }
        if (substitute)
            for (auto& [k, v] : e.attrs)
                if (k != "name") v = substituted(v, e, k);
        return e;
    }

    std::string substituted(const std::string& text, const Element& e, const std::string& attr) {
        std::string out;
        for (std::size_t i = 0; i < text.size(); ++i) {
            char next = i + 1 < text.size() ? text[i + 1] : '\0';
            if (text[i] != '$' || !(std::isalpha(static_cast<unsigned char>(next)) || next == '_')) {
                out += text[i];
                continue;
            }
            std::size_t j = i + 1;
            while (j < text.size() && (std::isalnum(static_cast<unsigned char>(text[j])) || text[j] == '_')) ++j;
            std::string var = text.substr(i + 1, j - i - 1);
            auto it = m_vars.find(var);
            if (it == m_vars.end()) {
                std::vector<std::string> known;
                for (const auto& kv : m_vars) known.push_back(kv.first);
                std::string hint = didYouMean(var, known);
                e.fail("attribute '{}': undefined variable '${}' (declare it first with <default name=\"{}\" "
                       "value=\"...\"/>){}",
                       attr, var, var, hint.empty() ? "" : fmt::format("; did you mean '${}'?", hint));
            }
            out += it->second;
            i = j - 1;
        }
        return out;
    }

    void checkName(NameMap& names, const Node& parent, const Element& e) {
        if (e.name.empty() || parent.tag == "scene") return;
        auto [it, fresh] = names.emplace(e.name, e.where);
        if (!fresh)
            e.fail("duplicate name '{}' in {} '{}' (first given at {})", e.name, parent.tag, parent.type,
                   it->second.str());
    }

    void parseChildren(pugi::xml_node xml, const SourceFile& f, Node& node, NameMap& names) {
        bool topLevel = node.tag == "scene";
        for (pugi::xml_node x : xml.children()) {
            if (x.type() == pugi::node_pcdata || x.type() == pugi::node_cdata)
                failAt(f.at(x.offset_debug()), "unexpected text '{}' inside <{}>", x.value(), xml.name());
            if (x.type() != pugi::node_element) continue;
            std::string tag = x.name();
            if (tag == "default") {
                parseDefault(x, f);
            } else if (tag == "include") {
                parseInclude(x, f, node, names);
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
                failAt(f.at(x.offset_debug()), "unknown element <{}>{}", tag,
                       hint.empty() ? "" : fmt::format(" (did you mean <{}>?)", hint));
            }
        }
    }

    void parseDefault(pugi::xml_node x, const SourceFile& f) {
        Element e = element(x, f, false);
        e.allowOnly({"name", "value"});
        std::string name = e.require("name");
        const std::string& value = e.require("value");
        if (!isIdentifier(name)) e.fail("'{}' is not a valid variable name", name);
        if (!m_declared.emplace(name, e.where).second)
            e.fail("variable '{}' is declared twice (first at {})", name, m_declared[name].str());
        auto d = m_opt.defines.find(name);
        m_vars[name] = d != m_opt.defines.end() ? d->second : value;
    }

    void parseInclude(pugi::xml_node x, const SourceFile& f, Node& node, NameMap& names) {
        Element e = element(x, f, true);
        e.allowOnly({"filename"});
        std::filesystem::path rel = e.require("filename");
        std::filesystem::path p = rel.is_absolute() ? rel : f.dir / rel;
        bool ok = false;
        std::string text = readFile(p, ok);
        if (!ok) e.fail("cannot open included file '{}' (looked for {})", rel.string(), p.string());
        std::error_code ec;
        std::filesystem::path canon = std::filesystem::weakly_canonical(p, ec);
        if (ec) canon = p;
        if (std::find(m_stack.begin(), m_stack.end(), canon) != m_stack.end()) {
            std::string chain;
            for (const auto& s : m_stack) chain += s.filename().string() + " -> ";
            e.fail("include cycle: {}{}", chain, canon.filename().string());
        }
        m_stack.push_back(canon);
        parseDocument(text, p.string(), &f, node, names);
        m_stack.pop_back();
    }

    void parseProperty(pugi::xml_node x, const SourceFile& f, Node& node, NameMap& names) {
        Element e = element(x, f, true);
        if (e.name.empty()) e.fail("missing attribute 'name'");
        if (node.tag == "scene") e.fail("properties belong inside an object, not directly inside <scene>");
        PropertyValue value;
        if (e.tag == "transform") {
            e.allowOnly({"name"});
            Transform m;
            for (pugi::xml_node c : x.children()) {
                if (c.type() == pugi::node_pcdata || c.type() == pugi::node_cdata)
                    e.fail("unexpected text '{}'", c.value());
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
            value = m;
        } else {
            for (pugi::xml_node c : x.children())
                if (c.type() == pugi::node_element || c.type() == pugi::node_pcdata)
                    e.fail("a property element takes no content");
            value = detail::parseProperty(e, f.dir);
        }
        checkName(names, node, e);
        node.props.set(e.name, std::move(value), e.where);
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
            if (!fresh) e.fail("duplicate id '{}' (first used at {})", *id, it->second.str());
            node->id = *id;
            node->props.setId(*id);
        }
        checkName(names, parent, e);
        // Real scenes nest a handful of levels; the limit keeps hostile input off the stack.
        if (++m_depth > kMaxDepth) e.fail("objects are nested more than {} levels deep", kMaxDepth);
        NameMap inner;
        parseChildren(x, f, *node, inner);
        --m_depth;
        parent.children.push_back(Child{e.name, std::move(node), "", e.where});
    }

    const ParseOptions& m_opt;
    std::map<std::string, std::string> m_vars;          // $name -> value
    std::map<std::string, SourceLocation> m_declared;   // <default> declarations
    std::map<std::string, SourceLocation> m_ids;
    std::vector<std::filesystem::path> m_stack;         // files being included
    static constexpr int kMaxDepth = 100;
    int m_depth = 0;
};

} // namespace

std::string camelToSnake(const std::string& name) {
    std::string out;
    auto upper = [](char c) { return std::isupper(static_cast<unsigned char>(c)) != 0; };
    auto lowerOrDigit = [](char c) {
        return std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c));
    };
    for (std::size_t i = 0; i < name.size(); ++i) {
        char c = name[i];
        if (upper(c) && i > 0) {
            // A word starts at an upper-case letter after a lower-case one ("maxDepth"), or at
            // the last capital of an acronym followed by lower case ("HDRFilm" -> "hdr_film").
            bool boundary = lowerOrDigit(name[i - 1]) ||
                            (upper(name[i - 1]) && i + 1 < name.size() && std::islower(static_cast<unsigned char>(name[i + 1])));
            if (boundary && out.back() != '_') out += '_';
        }
        out += char(std::tolower(static_cast<unsigned char>(c)));
    }
    return out;
}

std::unique_ptr<Node> parseString(const std::string& text, const std::string& filename, const ParseOptions& opt) {
    return Parser(opt).parseTop(text, filename);
}

std::unique_ptr<Node> parseFile(const std::filesystem::path& path, const ParseOptions& opt) {
    bool ok = false;
    std::string text = readFile(path, ok);
    if (!ok) fail("{}: cannot open scene file", path.string());
    return Parser(opt).parseTop(text, path.string());
}

} // namespace effigi::xml
