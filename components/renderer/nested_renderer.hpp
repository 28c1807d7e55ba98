#pragma once
// Nested renderers for the conformance configurations of the wrappers that take them
// (aov, moment), made through the registry.
#include "effigi/core/registry.hpp"

#include <optional>

namespace effigi {

/// The renderer `type` with `params`, as a property value; absent (the configuration is
/// then left out) if its module cannot be made.
inline std::optional<PropertyValue> nestedRenderer(const std::string& type,
                                                   const std::vector<std::pair<std::string, PropertyValue>>& params = {}) {
    try {
        Properties p("renderer", type);
        for (const auto& [name, value] : params) p.set(name, value);
        return ComponentValue{"renderer", Registry::instance().create("renderer", type, p)};
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

} // namespace effigi
