#pragma once
// (tag, name) -> factory. A build-time manifest maps each component to the module
// file that holds it; the module is dlopen'ed the first time something asks for one
// of its components, so a scene that needs no texture loads no texture module.
#include "effigi/core/component.hpp"
#include "effigi/core/schema.hpp"

#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace effigi {

using Factory = std::function<Ref<IComponent>(const Properties&)>;

struct ComponentInfo {
    Schema schema;
    Factory create;
    std::string module;  // path of the module that registered it ("" = built in)
};

class Registry {
public:
    /// The process-wide registry, with the built-in module directory and
    /// EFFIGI_PLUGIN_PATH (colon-separated) already scanned for manifests.
    static Registry& instance();

    /// An empty registry (tests).
    Registry() = default;

    /// Read `dir/manifest.txt` (lines "tag name module-file"), or without one take every
    /// `<tag>-<name>.so` in dir; later entries of the same (tag, name) — plugins — take
    /// precedence, with a warning.
    void addModuleDirectory(const std::filesystem::path& dir);
    /// Register a component directly (called from a module's entry point, or by tests).
    void add(ComponentInfo info);

    /// Validate props against the component's schema and create it.
    Ref<IComponent> create(const std::string& tag, const std::string& name, Properties& props);
    /// Schema and factory of a component, loading its module if needed.
    const ComponentInfo& info(const std::string& tag, const std::string& name);

    bool knows(const std::string& tag, const std::string& name) const;
    /// Every (tag, name) known from manifests and direct registration, sorted.
    std::vector<std::pair<std::string, std::string>> list() const;
    /// Module files loaded so far, in load order.
    std::vector<std::string> loadedModules() const;

    /// Canonical tag for XML aliases: "sensor" -> "camera".
    static std::string canonicalTag(const std::string& tag);

private:
    using Key = std::pair<std::string, std::string>;
    void loadModule(const std::string& path, const Key& wanted);

    mutable std::recursive_mutex m_mutex;
    std::map<Key, ComponentInfo> m_components;
    std::map<Key, std::string> m_manifest;  // not yet loaded
    std::vector<std::string> m_loaded;
};

/// Signature of the entry point each module exports as `effigiRegisterModule`.
using ModuleEntry = void (*)(Registry&);

} // namespace effigi

/// One component per module: defines the module's entry point registering Class,
/// which provides `static Schema schema()` and a constructor from Properties.
#define EFFIGI_EXPORT_COMPONENT(Class)                                                            \
    extern "C" __attribute__((visibility("default"))) void effigiRegisterModule(effigi::Registry& r) { \
        r.add(effigi::ComponentInfo{Class::schema(),                                             \
                                    [](const effigi::Properties& p) -> effigi::Ref<effigi::IComponent> { \
                                        return std::make_shared<Class>(p);                       \
                                    },                                                           \
                                    {}});                                                        \
    }
