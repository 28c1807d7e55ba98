#include "effigi/core/registry.hpp"

#include "effigi/core/input.hpp"
#include "effigi/core/log.hpp"
#include "effigi/core/module.hpp"

#include <algorithm>
#include <dlfcn.h>
#include <fstream>
#include <sstream>

namespace effigi {

Registry& Registry::instance() {
    static Registry* registry = [] {
        auto* r = new Registry();  // never destroyed: modules stay loaded for the process
        for (const auto& dir : moduleDirectories()) r->addModuleDirectory(dir);
        return r;
    }();
    return *registry;
}

std::string Registry::canonicalTag(const std::string& tag) {
    if (tag == "sensor") return "camera";
    return tag;
}

void Registry::addModuleDirectory(const std::filesystem::path& dir) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) {
        log::warn("module directory {} does not exist (EFFIGI_PLUGIN_PATH?); ignored", dir.string());
        return;
    }
    struct Entry {
        std::string tag, name, file;
    };
    std::vector<Entry> entries;
    const fs::path manifest = dir / "manifest.txt";
    if (std::ifstream in(manifest); in) {
        std::string line;
        while (std::getline(in, line)) {
            if (line.empty() || line[0] == '#') continue;
            std::istringstream ss(line);
            Entry e;
            if (!(ss >> e.tag >> e.name >> e.file)) {
                log::warn("{}: ignoring malformed line '{}'", manifest.string(), line);
                continue;
            }
            entries.push_back(std::move(e));
        }
    } else {
        // No manifest (modules copied by hand): the file name <tag>-<name>.so says what a
        // module holds, so nothing has to be loaded to list it.
        for (const auto& f : fs::directory_iterator(dir, ec)) {
            if (f.path().extension() != ".so") continue;
            const std::string stem = f.path().stem().string();
            const auto dash = stem.find('-');
            if (dash == std::string::npos || dash == 0 || dash + 1 == stem.size()) {
                log::warn("{}: not named <tag>-<name>.so and no manifest.txt lists it; ignored", f.path().string());
                continue;
            }
            entries.push_back({stem.substr(0, dash), stem.substr(dash + 1), f.path().filename().string()});
        }
        if (entries.empty()) {
            log::warn("no manifest.txt and no <tag>-<name>.so modules in {}; nothing found there", dir.string());
            return;
        }
        std::sort(entries.begin(), entries.end(),
                  [](const Entry& a, const Entry& b) { return a.file < b.file; });
    }
    std::lock_guard lock(m_mutex);
    for (const Entry& e : entries) {
        Key key{canonicalTag(e.tag), e.name};
        std::string path = (dir / e.file).string();
        // A later directory (a plugin) replaces a component of the same tag and name,
        // built in or not; say so, since it changes what every scene using it renders.
        if (auto it = m_manifest.find(key); it != m_manifest.end() && it->second != path)
            log::warn("{} '{}' from {} replaces the one from {}", key.first, key.second, path, it->second);
        m_manifest[key] = path;
        // ... provided the component is not loaded yet.
        if (auto it = m_components.find(key); it != m_components.end() && !it->second.module.empty())
            m_components.erase(it);
    }
}

void Registry::add(ComponentInfo info) {
    std::lock_guard lock(m_mutex);
    Key key{info.schema.tag(), info.schema.name()};
    m_components[key] = std::move(info);
}

void Registry::loadModule(const std::string& path, const Key& wanted) {
    void* handle = dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
    if (!handle) fail("cannot load module {} for {} '{}': {}", path, wanted.first, wanted.second, dlerror());
    auto entry = reinterpret_cast<ModuleEntry>(dlsym(handle, "effigiRegisterModule"));
    if (!entry)
        fail("{} is not an effigi module: it has no effigiRegisterModule entry point (EFFIGI_EXPORT_COMPONENT)",
             path);
    std::size_t before = m_components.size();
    entry(*this);
    for (auto& [key, info] : m_components)
        if (info.module.empty() && m_manifest.count(key) && m_manifest[key] == path) info.module = path;
    if (m_components.size() == before && !m_components.count(wanted))
        fail("module {} did not register {} '{}'", path, wanted.first, wanted.second);
    m_loaded.push_back(path);
    log::debug("loaded module {}", path);
}

const ComponentInfo& Registry::info(const std::string& tag_, const std::string& name) {
    std::lock_guard lock(m_mutex);
    std::string tag = canonicalTag(tag_);
    Key key{tag, name};
    if (auto it = m_components.find(key); it != m_components.end()) return it->second;
    if (auto it = m_manifest.find(key); it != m_manifest.end()) {
        loadModule(it->second, key);
        if (auto c = m_components.find(key); c != m_components.end()) return c->second;
        fail("module {} did not register {} '{}'", it->second, tag, name);
    }
    std::vector<std::string> names;
    for (const auto& [k, v] : list())
        if (k == tag) names.push_back(v);
    if (names.empty()) fail("no components of kind '{}' are known", tag);
    std::string hint = didYouMean(name, names);
    fail("unknown {} '{}'{}; available: {}", tag, excerpt(name),
         hint.empty() ? "" : fmt::format(" (did you mean '{}'?)", hint), fmt::join(names, ", "));
}

Ref<IComponent> Registry::create(const std::string& tag_, const std::string& name, Properties& props) {
    std::string tag = canonicalTag(tag_);
    const ComponentInfo* ci;
    try {
        ci = &info(tag, name);
    } catch (const Error& e) {
        if (!props.where().known()) throw;
        throw Error(props.where(), e.what());
    }
    ci->schema.validate(props);
    Ref<IComponent> obj;
    try {
        obj = ci->create(props);
    } catch (const Error& e) {
        // Errors found while building (a missing mesh file, ...) get the element's place.
        if (e.where().known() || !props.where().known()) throw;
        throw Error(props.where(), fmt::format("{}: {}", props.describe(), e.what()));
    }
    obj->setIdentity(tag + "/" + name, props.id());
    return obj;
}

bool Registry::knows(const std::string& tag, const std::string& name) const {
    std::lock_guard lock(m_mutex);
    Key key{canonicalTag(tag), name};
    return m_components.count(key) || m_manifest.count(key);
}

std::vector<std::pair<std::string, std::string>> Registry::list() const {
    std::lock_guard lock(m_mutex);
    std::vector<Key> out;
    for (const auto& [k, v] : m_manifest) out.push_back(k);
    for (const auto& [k, v] : m_components)
        if (!m_manifest.count(k)) out.push_back(k);
    std::sort(out.begin(), out.end());
    return out;
}

std::vector<std::string> Registry::loadedModules() const {
    std::lock_guard lock(m_mutex);
    return m_loaded;
}

} // namespace effigi
