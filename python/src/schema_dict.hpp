#pragma once
// The registry seen from Python: component names and schemas as plain Python values.
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

namespace effigi::python {

namespace py = pybind11;

/// "tag/name" of every component the registry knows (built in or on EFFIGI_PLUGIN_PATH).
std::vector<std::string> componentNames();
/// A component's schema: tag, name, doc, reference, parameters (name, type, default, ...),
/// conformance configurations and allowances. Throws effigi::Error for an unknown one.
py::dict schemaDict(const std::string& tagName);

} // namespace effigi::python
