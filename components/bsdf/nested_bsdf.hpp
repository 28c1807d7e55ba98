#pragma once
// Nested BSDFs for the conformance configurations of the adapters that take them
// (blendbsdf, mask, twosided), made through the registry.
#include "effigi/core/registry.hpp"
#include "effigi/interfaces/ibsdf.hpp"

#include <optional>

namespace effigi {

/// The BSDF `type` with `params`, as a property value; absent (the configuration is then
/// left out) if its module cannot be made.
inline std::optional<PropertyValue> nestedBSDF(const std::string& type,
                                               const std::vector<std::pair<std::string, PropertyValue>>& params = {}) {
    try {
        Properties p("bsdf", type);
        for (const auto& [name, value] : params) p.set(name, value);
        return ComponentValue{"bsdf", Registry::instance().create("bsdf", type, p)};
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

} // namespace effigi
