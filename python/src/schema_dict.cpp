// effigi.info("tag/name"): a component's schema as a dict, the fields `effigi info` prints
// (apps/effigi/info.cpp) as Python values rather than text.
#include "schema_dict.hpp"

#include "effigi/core/error.hpp"
#include "effigi/core/registry.hpp"

#include <pybind11/stl.h>

namespace effigi::python {

namespace {

py::object vec3(const Vector3f& v) { return py::make_tuple(v.x, v.y, v.z); }

/// Row-major 4×4 (glm stores columns).
py::object matrix(const Transform& t) {
    py::list rows;
    for (int r = 0; r < 4; ++r) {
        py::list row;
        for (int c = 0; c < 4; ++c) row.append(t.matrix()[c][r]);
        rows.append(row);
    }
    return rows;
}

/// A parameter's default as the Python value closest to what the XML would say.
py::object pythonValue(const PropertyValue& value) {
    return std::visit(
        [](const auto& x) -> py::object {
            using T = std::decay_t<decltype(x)>;
            if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, std::int64_t> || std::is_same_v<T, double> ||
                          std::is_same_v<T, std::string>)
                return py::cast(x);
            else if constexpr (std::is_same_v<T, PointValue> || std::is_same_v<T, VectorValue> ||
                               std::is_same_v<T, RGBValue>)
                return vec3(x.v);
            else if constexpr (std::is_same_v<T, SpectrumValue>) {
                if (!x.name.empty()) return py::cast(x.name);
                if (x.temperature > 0.f) return py::dict(py::arg("blackbody") = x.temperature, py::arg("scale") = x.scale);
                if (x.lambdas.empty() && x.values.size() == 1) return py::cast(x.values[0] * x.scale);
                py::list pairs;
                for (std::size_t i = 0; i < x.lambdas.size() && i < x.values.size(); ++i)
                    pairs.append(py::make_tuple(x.lambdas[i], x.values[i] * x.scale));
                return pairs;
            } else if constexpr (std::is_same_v<T, Transform>) {
                return matrix(x);
            } else if constexpr (requires { x.first().matrix(); }) {
                return matrix(x.first());  // an animated transform: its first key
            } else if constexpr (std::is_same_v<T, ComponentValue>) {
                return py::cast(x.tag);  // a nested component: its tag
            } else {
                return py::none();
            }
        },
        value);
}

py::dict paramDict(const ParamSpec& p) {
    py::dict d;
    d["name"] = p.name;
    d["type"] = paramTypeName(p.type);
    d["default"] = p.defaultValue ? pythonValue(*p.defaultValue) : py::none();
    d["required"] = p.required;
    d["doc"] = p.doc;
    d["unit"] = p.unit;
    d["min"] = p.min ? py::cast(*p.min) : py::none();
    d["max"] = p.max ? py::cast(*p.max) : py::none();
    d["choices"] = p.choices;
    if (p.type == ParamType::Component || p.type == ParamType::Texture) d["component_tag"] = p.componentTag;
    d["multiple"] = p.multiple;
    d["ignored"] = p.ignored;
    return d;
}

} // namespace

py::dict schemaDict(const std::string& tagName) {
    const auto slash = tagName.find('/');
    if (slash == std::string::npos || slash == 0 || slash + 1 == tagName.size())
        fail("info: expected tag/name (e.g. bsdf/diffuse), got '{}'", tagName);
    const Schema& s = Registry::instance().info(tagName.substr(0, slash), tagName.substr(slash + 1)).schema;
    py::dict d;
    d["tag"] = s.tag();
    d["name"] = s.name();
    d["doc"] = s.doc();
    d["reference"] = s.reference();
    py::list params;
    for (const ParamSpec& p : s.params()) params.append(paramDict(p));
    d["parameters"] = params;
    py::list configs;  // the configurations effigi-conform runs
    for (const ConformanceConfig& c : s.conformance()) configs.append(c.name);
    d["conformance_configurations"] = configs;
    py::list allowances;
    for (const ConformanceAllowance& a : s.allowances())
        allowances.append(py::dict(py::arg("check") = a.check, py::arg("bound") = a.bound, py::arg("reason") = a.reason));
    d["conformance_allowances"] = allowances;
    return d;
}

std::vector<std::string> componentNames() {
    std::vector<std::string> names;
    for (const auto& [tag, name] : Registry::instance().list()) names.push_back(tag + "/" + name);
    return names;
}

} // namespace effigi::python
